"""``learned``: an evader whose heading is a small linear policy, trained against the recommended controller.

With defenders sensed (within its sensing radius), the attacker runs at full
speed along the unit vector of W·φ, where φ (:func:`features`) describes the
sensed defenders in the frame of the attacker's intent (so the policy is the same
whatever the intent's direction): the inverse-square flee direction, the bisector
of the widest angular gap, the direction to the sensed defenders' centroid, each a
unit vector; the nearest one's distance and that centroid's, per sensing radius;
the fraction of the team sensed; and a constant. The heading is bent by the
obstacles' field and kept out of every obstacle like every evader's
(:func:`mpc_hunt.world.behaviours.base.heading`); with nobody sensed, it is the
paper's undisturbed attacker. W (2 × :data:`FEATURES`) is trained by the
cross-entropy method against the recommended controller (``python
studies/train_attacker.py``, docs/model.md) and shipped in ``learned.json``
beside this file.
"""

from __future__ import annotations

import json
import math
from importlib import resources
from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.errors import DataFileError, ScenarioError
from mpc_hunt.world.behaviours.base import heading, sensed, undisturbed
from mpc_hunt.world.behaviours.flee import flee_direction
from mpc_hunt.world.behaviours.gap import widest_gap
from mpc_hunt.world.field import nominal_intent
from mpc_hunt.world.geometry import norm, unit
from mpc_hunt.world.packed import sensing_radius

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario

FEATURES = 10
PARAMETERS = "learned.json"


def intent_frame(intent: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rotations into the frame whose x axis is the intent (the world's for an attacker with no intent) and
    back."""
    angle = math.atan2(intent[1], intent[0]) if np.hypot(*intent) > 0 else 0.0
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, s], [-s, c]]), np.array([[c, -s], [s, c]])


def features(p_a: np.ndarray, near: np.ndarray, team: int, radius: float, to_intent: np.ndarray) -> np.ndarray:
    """φ of the module's docstring for the sensed defenders ``near`` (k ≥ 1 rows) of a team of ``team``, turned
    into the intent's frame by ``to_intent`` (:func:`intent_frame`)."""
    start, width = widest_gap(p_a, near)
    gap = np.array([math.cos(start + 0.5 * width), math.sin(start + 0.5 * width)])
    centre = near.mean(axis=0) - p_a
    return np.concatenate(
        [
            to_intent @ unit(flee_direction(p_a, near)),
            to_intent @ gap,
            to_intent @ unit(centre),
            [norm(near - p_a).min() / radius, norm(centre) / radius, len(near) / team, 1.0],
        ]
    )


def weights_file():
    """The shipped weights file, ``learned.json`` beside this module."""
    return resources.files("mpc_hunt.world.behaviours").joinpath(PARAMETERS)


def shipped_weights() -> np.ndarray:
    """The trained W shipped with the package (:func:`load_weights` of :func:`weights_file`)."""
    return load_weights(weights_file())


def load_weights(path) -> np.ndarray:
    """W from a weights file (``{"weights": [[10 numbers], [10 numbers]], ...}``, as studies/train_attacker.py
    writes it), checked when loaded: an unreadable, empty, truncated or malformed file, a missing ``weights``, the
    wrong shape or a non-finite number is a one-line :class:`DataFileError` naming the file."""
    fix = "write it again with python studies/train_attacker.py, or reinstall mpc-hunt"
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise DataFileError(
            f"{path}: cannot read the learned attacker's weights ({getattr(exc, 'strerror', None) or exc}); {fix}"
        ) from None
    if not text.strip():
        raise DataFileError(f"{path}: empty, expected the learned attacker's weights; {fix}")
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise DataFileError(f"{path}: not valid JSON ({exc}); {fix}") from None
    except (ValueError, RecursionError):  # a whole number of too many digits, arrays nested too deeply
        raise DataFileError(f"{path}: not valid JSON (too many digits, or nested too deeply); {fix}") from None
    if not isinstance(data, dict) or "weights" not in data:
        raise DataFileError(f'{path}: expected a JSON object with "weights": 2 lists of {FEATURES} numbers; {fix}')
    try:
        return checked_weights(data["weights"])
    except ScenarioError as exc:
        raise DataFileError(f"{path}: {exc}; {fix}") from None


def checked_weights(weights) -> np.ndarray:
    """W as a (2, FEATURES) array of finite numbers (an array, or 2 lists of FEATURES numbers), or a one-line
    ScenarioError."""
    rule = f"learned attacker: weights must be 2 × {FEATURES} finite numbers"
    if not isinstance(weights, np.ndarray):
        if not (
            isinstance(weights, (list, tuple))
            and len(weights) == 2
            and all(isinstance(row, (list, tuple)) and len(row) == FEATURES for row in weights)
        ):
            raise ScenarioError(f"{rule}, got {_outline(weights)}")
        if not all(isinstance(x, (int, float)) and not isinstance(x, bool) for row in weights for x in row):
            raise ScenarioError(f"{rule}, got an entry that is not a number")
    try:
        w = np.asarray(weights, dtype=float)
    except (TypeError, ValueError):
        raise ScenarioError(f"{rule}, got an entry that is not a number") from None
    if w.shape != (2, FEATURES) or not np.all(np.isfinite(w)):
        raise ScenarioError(
            f"{rule}, got " + (f"shape {w.shape}" if w.shape != (2, FEATURES) else "a NaN or infinite entry")
        )
    return w


def _outline(value) -> str:
    """The shape of nested lists, for a message: 'a list of 3', 'a list of 2 lists of 9, 10', 'a str'."""
    if not isinstance(value, (list, tuple)):
        return f"a {type(value).__name__}"
    if all(isinstance(row, (list, tuple)) for row in value):
        return f"a list of {len(value)} lists of " + ", ".join(str(len(row)) for row in value[:4])
    return f"a list of {len(value)}"


class LearnedAttacker:
    """Along the trained policy's heading while defenders are sensed (the module's docstring)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator, weights: np.ndarray | None = None):
        self.scenario = scenario
        self.radius = sensing_radius(scenario)
        self.team = len(scenario.defenders)
        a = scenario.attacker
        self.to_intent, self.to_world = intent_frame(nominal_intent(np.array(a.nominal_velocity), a.max_speed))
        self.weights = shipped_weights() if weights is None else checked_weights(weights)

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        near = sensed(p_a, p_d, self.radius)
        if not len(near):
            return undisturbed(self.scenario, p_a)
        phi = features(p_a, near, self.team, self.radius, self.to_intent)
        return heading(self.scenario, p_a, self.to_world @ (self.weights @ phi))

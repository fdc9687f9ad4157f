"""``gap``: through the widest angular gap between the defenders it senses.

A gap-seeking evader, common among the baselines of multi-agent pursuit
benchmarks: the bearings of the sensed defenders, seen from the attacker, split
the turn into gaps; the attacker runs at full speed along the bisector of the
widest, unless its intent already points into that gap at least
``GAP_MARGIN`` from both edges, in which case it keeps its intent's heading.
With one defender sensed the gap is the whole turn but that defender's bearing;
with none, it follows its intent.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.world.behaviours.base import heading, sensed, sensing_radius, undisturbed
from mpc_hunt.world.field import nominal_intent

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario

GAP_MARGIN = math.pi / 6  # rad: how far inside the widest gap the intent must point to be kept


def widest_gap(p_a: np.ndarray, near: np.ndarray) -> tuple[float, float]:
    """(the bearing of the gap's first edge, its width), counter-clockwise, among the bearings of ``near``."""
    offsets = near - p_a
    bearings = np.sort(np.arctan2(offsets[:, 1], offsets[:, 0]))
    widths = np.diff(np.append(bearings, bearings[0] + 2 * math.pi))
    j = int(np.argmax(widths))
    return float(bearings[j]), float(widths[j])


def gap_heading(p_a: np.ndarray, near: np.ndarray, intent: np.ndarray) -> float:
    """The bearing the attacker runs along: its intent's if inside the widest gap with the margin, else the
    gap's bisector."""
    start, width = widest_gap(p_a, near)
    if np.hypot(*intent) > 0:
        into = (math.atan2(intent[1], intent[0]) - start) % (2 * math.pi)
        if GAP_MARGIN <= into <= width - GAP_MARGIN:
            return start + into
    return start + 0.5 * width


class GapAttacker:
    """Through the widest gap between the sensed defenders (the module's docstring)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator):
        self.scenario = scenario
        self.radius = sensing_radius(scenario)
        a = scenario.attacker
        self.intent = nominal_intent(np.array(a.nominal_velocity), a.max_speed)

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        near = sensed(p_a, p_d, self.radius)
        if not len(near):
            return undisturbed(self.scenario, p_a)
        angle = gap_heading(p_a, near, self.intent)
        return heading(self.scenario, p_a, np.array([math.cos(angle), math.sin(angle)]))

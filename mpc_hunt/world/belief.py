"""What the defenders believe about the attacker, apart from what the world does.

The world moves the attacker by its scenario's behaviour
(:mod:`mpc_hunt.world.behaviours`). The defenders predict it with an
:class:`AttackerModel`: the paper's APF attacker (Eqs. 2, 3 and 9) with its
intent, gains, perception radius and top speed, built in one place from the
world's scenario and a :class:`Belief` (:meth:`AttackerModel.believed`), whose
parameters may be wrong on purpose, so that a sweep measures what a model error
costs. A controller is never built on the world's scenario: it gets
:func:`believed`, the same hunt with the attacker replaced by the model
(:meth:`AttackerModel.scenario`, the one place a believed scenario is made),
which names no behaviour, sensing radius or disturbance of the world's.

A belief states each error as the world's value over the believed one, so the
world (and with it the reachable and comfortable labels) stays as drawn and
only the defenders' model moves: ``perception_radius = 1.3`` means the
attacker perceives 30 % farther than the defenders believe, ``eta = 3`` that it
reacts three times as strongly. ``intent_heading`` (degrees) is the largest
error of the believed intent's heading; each hunt draws its error uniformly in
[−intent_heading, intent_heading] from the passed-in random generator, which
:func:`belief_rng` derives from the hunt's seed (for the CLI and the sweep
alike).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, fields
from typing import ClassVar

import numpy as np

from mpc_hunt.errors import ScenarioError
from mpc_hunt.world.behaviours import DEFAULT_BEHAVIOUR
from mpc_hunt.world.scenario import Scenario, Vector, checked_number

MAX_RATIO = 100.0  # a belief error's ratio, either way
MAX_HEADING_ERROR = 180.0  # degrees
WORLD, BELIEF = 0, 1  # a sweep hunt's streams (children of its SeedSequence node): the world's, the belief's


@dataclass(frozen=True)
class Belief:
    """The defenders' model of the attacker as errors against the world (the module's docstring)."""

    perception_radius: float = 1.0  # world's R_agg / believed R_agg
    eta: float = 1.0  # world's η / believed η
    intent_heading: float = 0.0  # degrees: the believed intent's heading is off by up to ± this

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "intent_heading":
                checked_number(value, "belief.intent_heading", non_negative=True, limit=MAX_HEADING_ERROR, unit="°")
            else:
                ratio = checked_number(value, f"belief.{f.name}", positive=True, limit=MAX_RATIO)
                if ratio < 1 / MAX_RATIO:
                    raise ScenarioError(f"belief.{f.name}: {ratio} is below the limit of {1 / MAX_RATIO:g}")

    def label(self) -> str:
        """``exact``, or the errors as written on the command line (``perception_radius=1.3x,eta=3x``)."""
        parts = [
            f"{f.name}={getattr(self, f.name):g}" + ("" if f.name == "intent_heading" else "x")
            for f in fields(self)
            if getattr(self, f.name) != f.default
        ]
        return ",".join(parts) or "exact"


def parse_belief(text: str) -> Belief:
    """A belief from ``NAME=VALUE[,NAME=VALUE…]``: ``perception_radius=1.3x``, ``eta=3x``, ``intent_heading=60``
    (degrees), or ``exact``."""
    if text.strip() == "exact":
        return Belief()
    known = {f.name for f in fields(Belief)}
    values = {}
    for item in text.split(","):
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or name not in known:
            raise ScenarioError(
                f"belief {text!r}: expected NAME=VALUE with NAME one of {', '.join(sorted(known))} "
                "(e.g. perception_radius=1.3x, eta=3x, intent_heading=60)"
            )
        if name in values:
            raise ScenarioError(f"belief {text!r}: {name} is given twice (give each name once)")
        value = value.strip()
        if name != "intent_heading":
            value = value.removesuffix("x")
        try:
            values[name] = float(value)
        except ValueError:
            raise ScenarioError(f"belief {text!r}: {name}'s value {value!r} is not a number") from None
    return Belief(**values)


@dataclass(frozen=True)
class AttackerModel:
    """The attacker the defenders predict with: the paper's APF attacker (Eqs. 2, 3 and 9) with these parameters.

    Built in one place from the world's scenario and a :class:`Belief` (:meth:`believed`), updated by the
    online estimator (:meth:`fitted`); :meth:`scenario` is the one place a believed scenario is made.
    """

    LAW: ClassVar[str] = DEFAULT_BEHAVIOUR  # the paper's APF attacker: the only law the defenders model

    intent: Vector  # v_nom, m/s
    perception_radius: float  # R_agg, m
    eta: float  # η (Eq. 2; it scales the obstacles' field too, Eq. 3)
    k_d: float  # weight of the defenders' field (Eq. 9)
    max_speed: float  # v_a, m/s: known to the defenders

    @property
    def gain(self) -> float:
        """g = k_d η, the defenders' push on the attacker (Eq. 9 with Eq. 2)."""
        return self.k_d * self.eta

    @classmethod
    def of(cls, scenario: Scenario) -> "AttackerModel":
        """The model ``scenario``'s attacker and hunt parameters state."""
        a, hunt = scenario.attacker, scenario.hunt
        return cls(a.nominal_velocity, a.perception_radius, hunt.eta, hunt.k_d, a.max_speed)

    @classmethod
    def believed(
        cls, world: Scenario, belief: Belief = Belief(), rng: np.random.Generator | None = None
    ) -> "AttackerModel":
        """The defenders' model of ``world``'s attacker with ``belief``'s errors (the module's docstring).

        ``rng`` draws the intent's heading error; it is needed only when ``belief.intent_heading`` > 0.
        """
        a = world.attacker
        turn = 0.0
        if belief.intent_heading > 0:
            if rng is None:
                raise ScenarioError("belief.intent_heading: a random generator is needed to draw the heading error")
            turn = math.radians(rng.uniform(-belief.intent_heading, belief.intent_heading))
        c, s = math.cos(turn), math.sin(turn)
        vx, vy = a.nominal_velocity
        return cls(
            (c * vx - s * vy, s * vx + c * vy),
            a.perception_radius / belief.perception_radius,
            world.hunt.eta / belief.eta,
            world.hunt.k_d,
            a.max_speed,
        )

    def fitted(self, intent: np.ndarray, gain: float, perception_radius: float) -> "AttackerModel":
        """This model with estimated v_nom, g and R_agg put in: k_d = g / η, keeping η (which also scales the
        obstacles' field, Eq. 3, known to the defenders)."""
        return dataclasses.replace(
            self,
            intent=(float(intent[0]), float(intent[1])),
            perception_radius=float(perception_radius),
            k_d=float(gain) / self.eta,
        )

    def scenario(self, world: Scenario) -> Scenario:
        """``world`` with its attacker replaced by this model, for posing the capture problem (Eqs. 12–15): the
        arena, defenders, obstacles and the other hunt parameters are the world's; the attacker names no
        behaviour, sensing radius or disturbance of the world's."""
        attacker = dataclasses.replace(
            world.attacker,
            nominal_velocity=self.intent,
            max_speed=self.max_speed,
            perception_radius=self.perception_radius,
            behaviour=self.LAW,
            sensing_radius=None,
            disturbance=None,
        )
        hunt = dataclasses.replace(world.hunt, eta=self.eta, k_d=self.k_d)
        return dataclasses.replace(world, attacker=attacker, hunt=hunt)


def believed(scenario: Scenario, belief: Belief = Belief(), rng: np.random.Generator | None = None) -> Scenario:
    """``scenario`` as the defenders believe it: :meth:`AttackerModel.believed`'s model put in."""
    return AttackerModel.believed(scenario, belief, rng).scenario(scenario)


def belief_rng(seed: int, index: int | None = None, member: int = 0) -> np.random.Generator:
    """The generator of the belief's draws (the intent's heading error): the first child of the hunt's
    ``SeedSequence`` that its world's generator does not take.

    A lone hunt (``index`` None: ``mpc-hunt simulate --seed``), whose world draws from ``default_rng(seed)``
    itself: child 0 of ``SeedSequence(seed)``, spawn key ``(0,)``. Hunt ``index`` of the sweep ``seed``, ensemble
    member ``member``, whose world takes child ``WORLD`` of its node ``(index, member)``
    (:func:`mpc_hunt.sweep.runner.hunt_rngs`): child ``BELIEF``, spawn key ``(index, member, BELIEF)``.
    """
    key = (0,) if index is None else (index, member, BELIEF)
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=key))

"""What the defenders believe about the attacker, apart from what the world does.

The world moves the attacker by its scenario's behaviour
(:mod:`mpc_hunt.world.behaviours`). A controller is never built on that
scenario: it gets :func:`believed`, the same hunt with the attacker replaced by
the defenders' model of it, the paper's APF attacker (Eqs. 2 and 9), whose
parameters may be wrong on purpose (:class:`Belief`), so that a sweep measures
what a model error costs. The believed scenario names no behaviour, sensing
radius or disturbance of the world's: only ``apf`` with the believed
parameters.

A belief states each error as the world's value over the believed one, so the
world (and with it the reachable and comfortable labels) stays as drawn and
only the defenders' model moves: ``perception_radius = 1.3`` means the
attacker perceives 30 % farther than the defenders believe, ``eta = 3`` that it
reacts three times as strongly. ``intent_heading`` (degrees) is the largest
error of the believed intent's heading; each hunt draws its error uniformly in
[−intent_heading, intent_heading] from the passed-in random generator.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, fields

import numpy as np

from mpc_hunt.errors import ScenarioError
from mpc_hunt.world.behaviours import DEFAULT_BEHAVIOUR
from mpc_hunt.world.scenario import Scenario, checked_number

MAX_RATIO = 100.0         # a belief error's ratio, either way
MAX_HEADING_ERROR = 180.0  # degrees


@dataclass(frozen=True)
class Belief:
    """The defenders' model of the attacker as errors against the world (the module's docstring)."""

    perception_radius: float = 1.0   # world's R_agg / believed R_agg
    eta: float = 1.0                 # world's η / believed η
    intent_heading: float = 0.0      # degrees: the believed intent's heading is off by up to ± this

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "intent_heading":
                checked_number(value, "belief.intent_heading", non_negative=True, limit=MAX_HEADING_ERROR,
                               unit="°")
            else:
                ratio = checked_number(value, f"belief.{f.name}", positive=True, limit=MAX_RATIO)
                if ratio < 1 / MAX_RATIO:
                    raise ScenarioError(f"belief.{f.name}: {ratio} is below the limit of {1 / MAX_RATIO:g}")

    def label(self) -> str:
        """``exact``, or the errors as written on the command line (``perception_radius=1.3x,eta=3x``)."""
        parts = [f"{f.name}={getattr(self, f.name):g}" + ("" if f.name == "intent_heading" else "x")
                 for f in fields(self) if getattr(self, f.name) != f.default]
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
            raise ScenarioError(f"belief {text!r}: expected NAME=VALUE with NAME one of {', '.join(sorted(known))} "
                                "(e.g. perception_radius=1.3x, eta=3x, intent_heading=60)")
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


def believed(scenario: Scenario, belief: Belief = Belief(), rng: np.random.Generator | None = None) -> Scenario:
    """``scenario`` as the defenders believe it: the paper's attacker with the believed parameters.

    ``rng`` draws the intent's heading error; it is needed only when ``belief.intent_heading`` > 0.
    """
    a = scenario.attacker
    turn = 0.0
    if belief.intent_heading > 0:
        if rng is None:
            raise ScenarioError("belief.intent_heading: a random generator is needed to draw the heading error")
        turn = math.radians(rng.uniform(-belief.intent_heading, belief.intent_heading))
    c, s = math.cos(turn), math.sin(turn)
    vx, vy = a.nominal_velocity
    model = dataclasses.replace(a, nominal_velocity=(c * vx - s * vy, s * vx + c * vy),
                                perception_radius=a.perception_radius / belief.perception_radius,
                                behaviour=DEFAULT_BEHAVIOUR, sensing_radius=None, disturbance=None)
    hunt = dataclasses.replace(scenario.hunt, eta=scenario.hunt.eta / belief.eta)
    return dataclasses.replace(scenario, attacker=model, hunt=hunt)

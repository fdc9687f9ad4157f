"""``minimax``: a best-response evader that plans against where the defenders can be, not how they decide.

Once it senses a defender (within its sensing radius; before, it follows its
intent like every behaviour), the attacker plans against the whole team each
step: for every heading of :data:`~mpc_hunt.world.reachable_set.RAYS` it takes
the straight run at v_a and the worst case over the defenders' moves, each
defender anywhere the team's top speed takes it (the robots are kinematic,
Eq. 1, so their velocities do not narrow that set), which is the ray's part of the
attacker's dominance region (:mod:`mpc_hunt.world.reachable_set`; a defender
within R_hunt counts as there). Among the headings that meet no obstacle before
the arena's edge it takes the one with the widest time margin at the edge: the
defenders' earliest arrival there less its own (max over its own heading, min
over the defenders' arrival). A positive margin is an escape that no defender
can stop; a negative one is the opening the defenders close last, where any
slip of theirs lets it out. Where an obstacle stands before the edge on every
heading, it takes the heading it can run farthest along before any defender or
obstacle closes it. The heading is bent by the
obstacles' field and kept out of every obstacle like every behaviour's
(:func:`~mpc_hunt.world.behaviours.base.heading`).

The search is exhaustive over the rays (a zero-sum game of one move against
reachable sets, solved exactly on that grid), so it needs no solver; a plan
costs 1.3–2.0 ms against five defenders and two obstacles on the 2-core
development machine under load (docs/model.md, E13, gives the command).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.world.behaviours.base import heading, sensed, undisturbed
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.packed import sensing_radius
from mpc_hunt.world.reachable_set import dominance

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario


def best_heading(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """The unit heading of the module's docstring against the defenders at ``p_d``."""
    s = scenario
    speeds = np.full(len(p_d), float(np.max(s.defender_max_speeds)))
    region = dominance(
        p_a, p_d, speeds, s.attacker.max_speed, s.obstacle_centres, s.obstacle_radii, s.arena, reach=s.hunt.hunt_radius
    )
    open_ = region.blocked > region.edge  # no obstacle before the edge
    if open_.any():
        exits = p_a + region.edge[:, None] * region.rays  # (m, 2) the edge points
        arrival = np.min((norm(exits[:, None, :] - p_d[None]) - s.hunt.hunt_radius) / speeds, axis=1)
        margin = np.where(open_, arrival - region.edge / s.attacker.max_speed, -np.inf)
        return region.rays[int(np.argmax(margin))]
    return region.rays[int(np.argmax(region.extent))]


class MinimaxAttacker:
    """The best response to the defenders' reachable sets (the module's docstring)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator):
        self.scenario = scenario
        self.radius = sensing_radius(scenario)

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        p_d = np.asarray(p_d, dtype=float).reshape(-1, 2)
        if not len(sensed(p_a, p_d, self.radius)):
            return undisturbed(self.scenario, p_a)
        return heading(self.scenario, p_a, best_heading(self.scenario, p_a, p_d))

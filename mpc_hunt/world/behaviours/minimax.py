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
reachable sets, solved exactly on that grid), so it needs no solver; compiled (:mod:`mpc_hunt.compiled`), a plan
costs microseconds against five defenders and two obstacles (docs/model.md, E13, gives the command and the
figures).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.behaviours.base import CompiledBehaviour, calm, headed, near
from mpc_hunt.world.geometry import length
from mpc_hunt.world.packed import HUNT_RADIUS, SENSING, V_A, X_MAX, X_MIN, Y_MAX, Y_MIN
from mpc_hunt.world.reachable_set import RAYS, defender_reach, edge_along, obstacle_block, ray_directions

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario

DIRECTIONS = ray_directions(RAYS)


@kernel
def best_ray(p_a, p_d, top, centres, radii, prm, rays):
    """The index of the ray of the module's docstring against the defenders at ``p_d``, each at the team's top
    speed ``top``."""
    reach, v_a = prm[HUNT_RADIUS], prm[V_A]
    ratios = np.full(p_d.shape[0], v_a / top)
    limits = defender_reach(p_a, rays, p_d, ratios, reach)
    blocked = obstacle_block(p_a, rays, centres, radii)
    edge = edge_along(p_a, rays, prm[X_MIN], prm[Y_MIN], prm[X_MAX], prm[Y_MAX])
    best, chosen = -np.inf, -1
    for k in range(rays.shape[0]):  # the widest margin at the edge, over the rays no obstacle closes before it
        if blocked[k] > edge[k]:
            ex, ey = p_a[0] + edge[k] * rays[k, 0], p_a[1] + edge[k] * rays[k, 1]
            arrival = np.inf
            for i in range(p_d.shape[0]):
                arrival = min(arrival, (length(ex - p_d[i, 0], ey - p_d[i, 1]) - reach) / top)
            margin = arrival - edge[k] / v_a
            if chosen < 0 or margin > best:
                best, chosen = margin, k
    if chosen >= 0:
        return chosen
    best = -np.inf
    for k in range(rays.shape[0]):  # else the farthest run before any defender or obstacle closes it
        extent = min(edge[k], blocked[k])
        for i in range(p_d.shape[0]):
            extent = min(extent, limits[k, i])
        if chosen < 0 or extent > best:
            best, chosen = extent, k
    return chosen


@kernel
def minimax_velocity(p_a, p_d, centres, radii, prm, speeds, rays):
    """The ``minimax`` attacker's velocity (the module's docstring); ``speeds`` the defenders' top speeds."""
    if near(p_a, p_d, prm[SENSING]).shape[0] == 0:
        return calm(p_a, centres, radii, prm)
    k = best_ray(p_a, p_d, speeds.max(), centres, radii, prm, rays)
    return headed(p_a, rays[k, 0], rays[k, 1], centres, radii, prm)


def best_heading(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """The unit heading of the module's docstring against the defenders at ``p_d``."""
    s = scenario
    p_a, p_d = np.asarray(p_a, dtype=float), np.asarray(p_d, dtype=float).reshape(-1, 2)
    top = float(np.max(s.defender_max_speeds))
    return DIRECTIONS[best_ray(p_a, p_d, top, s.obstacle_centres, s.obstacle_radii, s.packed, DIRECTIONS)]


class MinimaxAttacker(CompiledBehaviour):
    """The best response to the defenders' reachable sets (the module's docstring)."""

    rule = staticmethod(minimax_velocity)

    def extra(self) -> tuple:
        """The defenders' top speeds and the rays."""
        return self.scenario.defender_max_speeds, DIRECTIONS

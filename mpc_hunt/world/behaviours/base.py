"""What every attacker behaviour shares: sensing, full-speed headings bent by obstacles, and never entering one.

A behaviour turns the state (the attacker at ``p_a``, the defenders at
``p_d``) into the attacker's velocity for the next step. With no defender
sensed, every behaviour follows its intent exactly as the paper's attacker does
with no defender in range (Eq. 2: its nominal velocity plus the obstacles'
field, capped at v_a), so the undisturbed path, and with it the reachable and
comfortable labels (:mod:`mpc_hunt.sweep.reachability`), is the same for all.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

import numpy as np

from mpc_hunt.world import attacker
from mpc_hunt.world.field import obstacle_repulsion
from mpc_hunt.world.geometry import dot2, norm, saturate, unit

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario

DEFAULT_SENSING = 3.0  # m: an evader's sensing radius unless its scenario gives one (docs/model.md)
NOBODY = np.empty((0, 2))


class Behaviour(Protocol):
    """Built from a scenario and a random generator; ``velocity`` once per step."""

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray: ...


def sensing_radius(scenario: Scenario) -> float:
    """How far the attacker senses defenders: the scenario's ``sensing_radius``, else ``DEFAULT_SENSING``."""
    given = scenario.attacker.sensing_radius
    return DEFAULT_SENSING if given is None else given


def sensed(p_a: np.ndarray, p_d: np.ndarray, radius: float) -> np.ndarray:
    """The defenders strictly within ``radius`` of the attacker, shape (k, 2)."""
    p_d = np.asarray(p_d, dtype=float).reshape(-1, 2)
    return p_d[norm(p_d - p_a) < radius]


def undisturbed(scenario: Scenario, p_a: np.ndarray) -> np.ndarray:
    """The attacker's velocity with no defender sensed: its intent and the obstacles' field (Eq. 2)."""
    return keep_out(scenario, p_a, attacker.velocity(scenario, p_a, NOBODY))


def heading(scenario: Scenario, p_a: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Full speed (v_a) along ``direction``, :func:`steered`."""
    return steered(scenario, p_a, scenario.attacker.max_speed * unit(np.asarray(direction, dtype=float)))


def steered(scenario: Scenario, p_a: np.ndarray, wish: np.ndarray) -> np.ndarray:
    """The velocity ``wish`` plus the obstacles' field (Eq. 3, weighted by k_o), capped at v_a and kept out of
    every obstacle."""
    hunt = scenario.hunt
    push = hunt.k_o * obstacle_repulsion(
        p_a, scenario.obstacle_centres, scenario.obstacle_radii, hunt.protective_distance, hunt.eta
    )
    return keep_out(scenario, p_a, saturate(wish + push, scenario.attacker.max_speed))


def attacker_move(scenario: Scenario, p_a: np.ndarray, action) -> np.ndarray:
    """An agent's velocity for the attacker at ``p_a`` as the world allows it: capped at v_a, kept out of every
    obstacle (as every attacker behaviour's)."""
    wish = saturate(np.asarray(action, dtype=float).reshape(2), scenario.attacker.max_speed)
    return keep_out(scenario, p_a, wish)


def keep_out(scenario: Scenario, p_a: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``v`` without its part towards an obstacle whose surface the next step would cross (it slides along)."""
    T = scenario.hunt.time_step
    for c, r in zip(scenario.obstacle_centres, scenario.obstacle_radii):
        if norm(p_a + T * v - c) <= r:
            inward = unit(c - p_a)
            v = v - max(dot2(v, inward), 0.0) * inward
    return v

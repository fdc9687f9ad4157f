"""What every attacker behaviour shares: sensing, full-speed headings bent by obstacles, and never entering one.

A behaviour turns the state (the attacker at ``p_a``, the defenders at
``p_d``) into the attacker's velocity for the next step. With no defender
sensed, every behaviour follows its intent exactly as the paper's attacker does
with no defender in range (Eq. 2: its nominal velocity plus the obstacles'
field, capped at v_a), so the undisturbed path, and with it the reachable and
comfortable labels (:mod:`mpc_hunt.sweep.reachability`), is the same for all.

The rules are compiled (:mod:`mpc_hunt.compiled`) on one hunt's arrays: the obstacles' centres and radii and the
packed parameters ``prm`` (:mod:`mpc_hunt.world.packed`); a behaviour written so (``gap``, say) moves a batch of
hunts in one call (:mod:`mpc_hunt.world.behaviours.batch`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Protocol

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.attacker import velocity_of
from mpc_hunt.world.field import obstacle_push
from mpc_hunt.world.geometry import capped, length
from mpc_hunt.world.packed import ETA, K_O, PROTECTIVE, V_A, T

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario

NOBODY = np.empty((0, 2))


class Behaviour(Protocol):
    """Built from a scenario and a random generator; ``velocity`` once per step."""

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray: ...


class CompiledBehaviour:
    """A behaviour whose velocity is a compiled rule, ``rule(p_a, p_d, centres, radii, prm, *self.extra())``, for a
    hunt alone (a batch calls the same rule, :mod:`mpc_hunt.world.behaviours.batch`)."""

    rule: Callable

    def __init__(self, scenario: Scenario, rng: np.random.Generator):
        self.scenario, self.rng = scenario, rng

    def extra(self) -> tuple:
        """The rule's arguments beyond the hunt's arrays and parameters (none)."""
        return ()

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        s = self.scenario
        p_a, p_d = np.asarray(p_a, dtype=float), np.asarray(p_d, dtype=float).reshape(-1, 2)
        return np.array(self.rule(p_a, p_d, s.obstacle_centres, s.obstacle_radii, s.packed, *self.extra()))


@kernel
def near(p_a: np.ndarray, p_d: np.ndarray, radius: float) -> np.ndarray:
    """The defenders strictly within ``radius`` of the attacker, shape (k, 2), in their order."""
    keep = np.empty(p_d.shape[0], dtype=np.bool_)
    for i in range(p_d.shape[0]):
        keep[i] = length(p_d[i, 0] - p_a[0], p_d[i, 1] - p_a[1]) < radius
    return p_d[keep]


@kernel
def kept_out(p_a: np.ndarray, vx: float, vy: float, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """(vx, vy) without its part towards an obstacle whose surface the next step would cross (it slides along)."""
    for j in range(radii.shape[0]):
        cx, cy = centres[j, 0], centres[j, 1]
        if length(p_a[0] + prm[T] * vx - cx, p_a[1] + prm[T] * vy - cy) <= radii[j]:
            ix, iy = cx - p_a[0], cy - p_a[1]
            scale = length(ix, iy)
            scale = scale if scale > 0 else 1.0
            ix, iy = ix / scale, iy / scale
            inward = max(vx * ix + vy * iy, 0.0)
            vx, vy = vx - inward * ix, vy - inward * iy
    return vx, vy


@kernel
def calm(p_a: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """The attacker's velocity with no defender sensed: its intent and the obstacles' field (Eq. 2)."""
    vx, vy = velocity_of(p_a, NOBODY, centres, radii, prm)
    return kept_out(p_a, vx, vy, centres, radii, prm)


@kernel
def wished(p_a: np.ndarray, wx: float, wy: float, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """The velocity (wx, wy) plus the obstacles' field (Eq. 3, weighted by k_o), capped at v_a and kept out of
    every obstacle."""
    ox, oy = obstacle_push(p_a, centres, radii, prm[PROTECTIVE], prm[ETA])
    vx, vy = capped(wx + prm[K_O] * ox, wy + prm[K_O] * oy, prm[V_A])
    return kept_out(p_a, vx, vy, centres, radii, prm)


@kernel
def headed(p_a: np.ndarray, dx: float, dy: float, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """Full speed (v_a) along (dx, dy), :func:`wished`; a zero direction wishes no velocity."""
    scale = length(dx, dy)
    scale = scale if scale > 0 else 1.0
    return wished(p_a, prm[V_A] * (dx / scale), prm[V_A] * (dy / scale), centres, radii, prm)


@kernel
def attacker_moves(running, actions, p_a, centres, radii, m, prm, out) -> None:
    """``out[b]``: the velocity ``actions[b]`` of each running hunt b's attacker as the world allows it: capped at
    its v_a, kept out of every obstacle (arrays of a batch, ``m`` its obstacle counts)."""
    for b in range(running.shape[0]):
        if running[b]:
            x, y = capped(actions[b, 0], actions[b, 1], prm[b, V_A])
            out[b, 0], out[b, 1] = kept_out(p_a[b], x, y, centres[b, : m[b]], radii[b, : m[b]], prm[b])


def sensed(p_a: np.ndarray, p_d: np.ndarray, radius: float) -> np.ndarray:
    """The defenders strictly within ``radius`` of the attacker, shape (k, 2)."""
    return near(np.asarray(p_a, dtype=float), np.asarray(p_d, dtype=float).reshape(-1, 2), float(radius))


def undisturbed(scenario: Scenario, p_a: np.ndarray) -> np.ndarray:
    """The attacker's velocity with no defender sensed: its intent and the obstacles' field (Eq. 2)."""
    s = scenario
    return np.array(calm(np.asarray(p_a, dtype=float), s.obstacle_centres, s.obstacle_radii, s.packed))


def heading(scenario: Scenario, p_a: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Full speed (v_a) along ``direction``, bent by the obstacles' field and kept out of them."""
    s, (dx, dy) = scenario, np.asarray(direction, dtype=float)
    return np.array(headed(np.asarray(p_a, dtype=float), dx, dy, s.obstacle_centres, s.obstacle_radii, s.packed))


def attacker_move(scenario: Scenario, p_a: np.ndarray, action) -> np.ndarray:
    """An agent's velocity for the attacker at ``p_a`` as the world allows it: capped at v_a, kept out of every
    obstacle (as every attacker behaviour's)."""
    x, y = np.asarray(action, dtype=float).reshape(2)
    return keep_out(scenario, p_a, np.array(capped(x, y, scenario.attacker.max_speed)))


def keep_out(scenario: Scenario, p_a: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``v`` without its part towards an obstacle whose surface the next step would cross (it slides along)."""
    s, p_a = scenario, np.asarray(p_a, dtype=float)
    return np.array(kept_out(p_a, float(v[0]), float(v[1]), s.obstacle_centres, s.obstacle_radii, s.packed))

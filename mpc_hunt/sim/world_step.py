"""The world's step and how a hunt stands after it: what the simulator and the environments (mpc_hunt.envs) share.

One step of length T, explicit Euler from the state at t: every defender at its
commanded velocity capped at its max speed (Eq. 1), a stopped one not at all;
the attacker at the velocity its behaviour (or an agent) chose. After it, the
hunt ends if the state is no longer finite, if the attacker has left the arena,
or when the success test (Eqs. 4–5) has held for ``hold_time``. Both are compiled rules
(:mod:`mpc_hunt.compiled`) on one hunt's arrays; a batch runs them hunt by hunt (:mod:`mpc_hunt.sim.batch`).
"""

from __future__ import annotations

import math

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.geometry import capped
from mpc_hunt.world.hunting_circle import circle_test
from mpc_hunt.world.packed import CENTRE_TOLERANCE, HUNT_RADIUS, X_MAX, X_MIN, Y_MAX, Y_MIN, T
from mpc_hunt.world.scenario import Scenario

RUNNING, NON_FINITE, ESCAPED, CAPTURED = 0, 1, 2, 3  # how a hunt stands after a step (:func:`stand`)
ENDS = {NON_FINITE: "non_finite_state", ESCAPED: "attacker_escaped", CAPTURED: "captured"}


def steps(scenario: Scenario) -> tuple[int, int]:
    """(steps to the time limit, steps the success test must hold)."""
    hunt = scenario.hunt
    return (
        int(math.ceil(hunt.time_limit / hunt.time_step - 1e-9)),
        int(math.ceil(hunt.hold_time / hunt.time_step - 1e-9)),
    )


@kernel
def move(
    p_a: np.ndarray,
    p_d: np.ndarray,
    velocities: np.ndarray,
    attacker_velocity: np.ndarray,
    stopped: np.ndarray,
    speeds: np.ndarray,
    prm: np.ndarray,
) -> None:
    """Everybody one step on (the module's docstring), in place."""
    T_ = prm[T]
    for i in range(p_d.shape[0]):
        if not stopped[i]:
            vx, vy = capped(velocities[i, 0], velocities[i, 1], speeds[i])
            p_d[i, 0] += T_ * vx
            p_d[i, 1] += T_ * vy
    p_a[0] += T_ * attacker_velocity[0]
    p_a[1] += T_ * attacker_velocity[1]


@kernel
def stand(p_a: np.ndarray, p_d: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray) -> int:
    """How the hunt stands after a step: :data:`NON_FINITE`, :data:`ESCAPED` (beyond an edge of the arena, whose
    edges are infinite when there is none), :data:`CAPTURED` when the success test holds, else
    :data:`RUNNING`."""
    finite = math.isfinite(p_a[0]) and math.isfinite(p_a[1])
    for i in range(p_d.shape[0]):
        finite = finite and math.isfinite(p_d[i, 0]) and math.isfinite(p_d[i, 1])
    if not finite:
        return NON_FINITE
    if p_a[0] < prm[X_MIN] or p_a[0] > prm[X_MAX] or p_a[1] < prm[Y_MIN] or p_a[1] > prm[Y_MAX]:
        return ESCAPED
    holds = circle_test(p_a, p_d, centres, radii, prm[HUNT_RADIUS], prm[CENTRE_TOLERANCE])[0]
    return CAPTURED if holds else RUNNING


@kernel
def standing_of(
    p_a: np.ndarray, p_d: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray, held: int, hold: int
) -> tuple[int, int]:
    """(how the hunt stands, for how many steps the success test has held): :func:`stand`, CAPTURED once the
    test has held for ``hold`` steps."""
    status = stand(p_a, p_d, centres, radii, prm)
    if status == NON_FINITE or status == ESCAPED:
        return status, held
    held = held + 1 if status == CAPTURED else 0
    return (CAPTURED if held >= hold else RUNNING), held


@kernel
def step_batch(
    running: np.ndarray,
    k: np.ndarray,
    p_a: np.ndarray,
    p_d: np.ndarray,
    n: np.ndarray,
    velocities: np.ndarray,
    attacker_velocity: np.ndarray,
    fails_at: np.ndarray,
    speeds: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    m: np.ndarray,
    prm: np.ndarray,
    held: np.ndarray,
    hold: np.ndarray,
    status: np.ndarray,
) -> None:
    """Step ``k[b]`` of every running hunt b of a batch (arrays padded, ``n`` and ``m`` their counts): everybody moved
    (:func:`move`; a defender stopped from its ``fails_at``), then ``status`` and ``held`` (:func:`standing_of`)."""
    for b in range(running.shape[0]):
        if not running[b]:
            continue
        d = p_d[b, : n[b]]
        stopped = k[b] * prm[b, T] >= fails_at[b, : n[b]]
        move(p_a[b], d, velocities[b, : n[b]], attacker_velocity[b], stopped, speeds[b, : n[b]], prm[b])
        status[b], held[b] = standing_of(p_a[b], d, centres[b, : m[b]], radii[b, : m[b]], prm[b], held[b], hold[b])


def moved(
    scenario: Scenario,
    p_a: np.ndarray,
    p_d: np.ndarray,
    velocities: np.ndarray,
    attacker_velocity: np.ndarray,
    stopped: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Everybody one step on (the module's docstring): (attacker, defenders), new arrays."""
    p_a, p_d = np.array(p_a, dtype=float), np.array(p_d, dtype=float).reshape(-1, 2)
    velocities = np.asarray(velocities, dtype=float).reshape(-1, 2)
    attacker_velocity = np.asarray(attacker_velocity, dtype=float).reshape(2)
    move(
        p_a,
        p_d,
        velocities,
        attacker_velocity,
        np.asarray(stopped, dtype=bool),
        scenario.defender_max_speeds,
        scenario.packed,
    )
    return p_a, p_d


def standing(
    scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray, held: int, hold_steps: int
) -> tuple[str | None, int]:
    """How the hunt stands after a step: its end (``non_finite_state``, ``attacker_escaped``, ``captured``) or
    None, and for how many steps the success test has held."""
    s = scenario
    p_a, p_d = np.asarray(p_a, dtype=float), np.asarray(p_d, dtype=float).reshape(-1, 2)
    status, held = standing_of(p_a, p_d, s.obstacle_centres, s.obstacle_radii, s.packed, held, hold_steps)
    return ENDS.get(status), held

"""The world's step and how a hunt stands after it: what the simulator and the environments (mpc_hunt.envs) share.

One step of length T, explicit Euler from the state at t: every defender at its
commanded velocity capped at its max speed (Eq. 1), a stopped one not at all;
the attacker at the velocity its behaviour (or an agent) chose. After it, the
hunt ends if the state is no longer finite, if the attacker has left the arena,
or when the success test (Eqs. 4–5) has held for ``hold_time``.
"""

from __future__ import annotations

import math

import numpy as np

from mpc_hunt.world.arena import attacker_escaped
from mpc_hunt.world.geometry import saturate
from mpc_hunt.world.hunting_circle import success_test
from mpc_hunt.world.scenario import Scenario


def steps(scenario: Scenario) -> tuple[int, int]:
    """(steps to the time limit, steps the success test must hold)."""
    hunt = scenario.hunt
    return (
        int(math.ceil(hunt.time_limit / hunt.time_step - 1e-9)),
        int(math.ceil(hunt.hold_time / hunt.time_step - 1e-9)),
    )


def moved(
    scenario: Scenario,
    p_a: np.ndarray,
    p_d: np.ndarray,
    velocities: np.ndarray,
    attacker_velocity: np.ndarray,
    stopped: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Everybody one step on (the module's docstring): (attacker, defenders)."""
    T = scenario.hunt.time_step
    p_d = p_d + T * saturate(np.where(stopped[:, None], 0.0, velocities), scenario.defender_max_speeds)
    return p_a + T * attacker_velocity, p_d


def standing(
    scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray, held: int, hold_steps: int
) -> tuple[str | None, int]:
    """How the hunt stands after a step: its end (``non_finite_state``, ``attacker_escaped``, ``captured``) or
    None, and for how many steps the success test has held."""
    if not (np.all(np.isfinite(p_a)) and np.all(np.isfinite(p_d))):
        return "non_finite_state", held
    if attacker_escaped(scenario, p_a):
        return "attacker_escaped", held
    hunt = scenario.hunt
    held = (
        held + 1
        if success_test(
            p_a, p_d, scenario.obstacle_centres, scenario.obstacle_radii, hunt.hunt_radius, hunt.centre_tolerance
        ).holds
        else 0
    )
    return ("captured" if held >= hold_steps else None), held

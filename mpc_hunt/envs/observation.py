"""What every agent of a hunt environment observes: the whole state, one flat vector in physical units.

Fields, in order (:func:`field_names`; m, m/s, s):

- ``time``: the hunt's time t;
- ``attacker_x``, ``attacker_y``; ``attacker_vx``, ``attacker_vy``, its velocity over the last step (0 at t = 0);
- ``attacker_intent_x``, ``attacker_intent_y``: its nominal velocity capped at v_a (docs/model.md, E6), which
  the defenders believe too (the paper's broadcast);
- for each defender i: ``defender_i_x``, ``defender_i_y``, ``defender_i_vx``, ``defender_i_vy``;
- for each of ``max_obstacles`` slots j: ``obstacle_j_x``, ``obstacle_j_y``, ``obstacle_j_radius`` (all 0 for
  an empty slot);
- ``arena_x_min``, ``arena_y_min``, ``arena_x_max``, ``arena_y_max`` (±1e6 for a scenario with no arena).

Every agent sees all of it: the paper's UAV broadcasts the positions to the defenders (its Fig. 2), and the
attacker's own sensing radius is a behaviour's choice, not the world's. Bounds: positions and lengths within
±:data:`mpc_hunt.world.scenario.MAX_MAGNITUDE` (an environment refuses a hunt whose robots or time could leave them:
:mod:`mpc_hunt.envs.hunts`), velocities within ± :func:`velocity_bound`: the fastest robot's speed plus the
rounding of the world's step, which a velocity over the last step carries.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from mpc_hunt.world.field import nominal_intent
from mpc_hunt.world.scenario import MAX_MAGNITUDE, Scenario

NO_ARENA = (-MAX_MAGNITUDE, -MAX_MAGNITUDE, MAX_MAGNITUDE, MAX_MAGNITUDE)
EPS = float(np.finfo(np.float64).eps)


def velocity_bound(max_speed: float, time_step: float) -> float:
    """The largest velocity component a hunt can be observed with, its robots no faster than ``max_speed`` and its
    step ``time_step`` long: ``max_speed`` (1 + 8ε) + 2ε·MAX_MAGNITUDE / T, with ε the float64 machine epsilon.

    A velocity over the last step is ((p + T·v) − p) / T with v capped at its robot's speed. Capping a vector
    (a norm, a quotient, a product; an obstacle's part taken off) leaves its length within a few ε of the cap,
    and adding T·v to a position |p| ≤ MAX_MAGNITUDE rounds the sum by up to ε·|p| / 2, which the division by T
    magnifies: up to 1.1e-9 m/s at T = 0.1 s (a defender at its 0.08 m/s is observed at 0.08000000000000007,
    say). The bound holds both, with room to spare."""
    return max_speed * (1 + 8 * EPS) + 2 * EPS * MAX_MAGNITUDE / time_step


def field_names(defenders: int, max_obstacles: int) -> list[str]:
    """The observation's fields, in order (the module's docstring)."""
    names = ["time", "attacker_x", "attacker_y", "attacker_vx", "attacker_vy", "attacker_intent_x", "attacker_intent_y"]
    names += [f"defender_{i}_{k}" for i in range(defenders) for k in ("x", "y", "vx", "vy")]
    names += [f"obstacle_{j}_{k}" for j in range(max_obstacles) for k in ("x", "y", "radius")]
    return names + ["arena_x_min", "arena_y_min", "arena_x_max", "arena_y_max"]


def observation_space(defenders: int, max_obstacles: int, max_speed: float, time_step: float) -> spaces.Box:
    """The Box of :func:`field_names`' vector: velocities within ± :func:`velocity_bound` of ``max_speed`` and
    ``time_step`` (the shortest step the environment plays), the rest within ±1e6; times and radii from 0."""
    names = field_names(defenders, max_obstacles)
    speed = np.array([n.endswith(("_vx", "_vy")) or "intent" in n for n in names])
    high = np.where(speed, velocity_bound(max_speed, time_step), MAX_MAGNITUDE).astype(np.float64)
    low = np.where(np.array([n == "time" or n.endswith("radius") for n in names]), 0.0, -high)
    return spaces.Box(low, high, dtype=np.float64)


def observe(
    scenario: Scenario,
    time: float,
    attacker: np.ndarray,
    attacker_velocity: np.ndarray,
    defenders: np.ndarray,
    defender_velocities: np.ndarray,
    max_obstacles: int,
) -> np.ndarray:
    """The vector of :func:`field_names` for this state."""
    a = scenario.attacker
    obstacles = np.zeros((max_obstacles, 3))
    for j, o in enumerate(scenario.obstacles[:max_obstacles]):
        obstacles[j] = (*o.centre, o.radius)
    return np.concatenate(
        [
            [time],
            attacker,
            attacker_velocity,
            nominal_intent(np.array(a.nominal_velocity), a.max_speed),
            np.hstack([defenders, defender_velocities]).ravel(),
            obstacles.ravel(),
            scenario.arena if scenario.arena is not None else NO_ARENA,
        ]
    ).astype(np.float64)

"""The arena: the rectangle the attacker must be kept in.

A scenario may declare an arena (x_min, y_min, x_max, y_max). The paper gives
none (both of its simulations are open planes), so the built-in scenarios have
none. An attacker strictly beyond one of the arena's edges has escaped, and the
hunt has failed (docs/robustness.md); a point on an edge is still inside. A
sweep also counts a defender beyond an edge as a failure (``margin`` < 0).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.world.geometry import dot2, norm, unit

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario

Arena = tuple[float, float, float, float]


def beyond_edge(arena: Arena, p) -> bool:
    """True when ``p`` lies strictly beyond an edge of ``arena``.

    A non-finite point is not outside: the simulator ends such a run with its own cause.
    """
    x, y = float(p[0]), float(p[1])
    x_min, y_min, x_max, y_max = arena
    return x < x_min or x > x_max or y < y_min or y > y_max


def margin(arena: Arena, points) -> np.ndarray:
    """How far each point (…, 2) lies inside the arena: its distance to the nearest edge's line, negative
    beyond an edge (by the most it exceeds one edge's line); zero on an edge."""
    p = np.asarray(points, dtype=float)
    x_min, y_min, x_max, y_max = arena
    x, y = p[..., 0], p[..., 1]
    return np.minimum(np.minimum(x - x_min, x_max - x), np.minimum(y - y_min, y_max - y))


def attacker_escaped(scenario: Scenario, p_a) -> bool:
    """Has the attacker at ``p_a`` left the scenario's arena? Never, when the scenario has no arena."""
    return scenario.arena is not None and beyond_edge(scenario.arena, p_a)


def kept_clear(scenario: Scenario, targets: np.ndarray) -> np.ndarray:
    """``targets`` (…, 2) moved into the arena, R_safe from its edges, and out of every obstacle's R_safe
    (Eq. 15), the obstacles in turn."""
    safe = scenario.hunt.safety_distance
    targets = np.array(targets, dtype=float)
    if scenario.arena is not None:
        x_min, y_min, x_max, y_max = scenario.arena
        targets = np.clip(targets, [x_min + safe, y_min + safe], [x_max - safe, y_max - safe])
    for c, r in zip(scenario.obstacle_centres, scenario.obstacle_radii):
        inside = norm(targets - c) < r + safe
        if np.any(inside):
            targets = np.where(np.expand_dims(inside, -1), c + (r + safe) * unit(targets - c), targets)
    return targets


def safe_velocity(scenario: Scenario, p_d: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A defender's velocity ``v`` at ``p_d`` without its part into an obstacle's R_safe (Eq. 15) or out of the
    arena, where a step would go there."""
    s = scenario
    T = s.hunt.time_step
    for c, r in zip(s.obstacle_centres, s.obstacle_radii):
        inward = unit(c - p_d)
        if norm(p_d + T * v - c) < r + s.hunt.safety_distance and dot2(v, inward) > 0:
            v = v - dot2(v, inward) * inward
    if s.arena is not None:
        x_min, y_min, x_max, y_max = s.arena
        v = (np.clip(p_d + T * v, [x_min, y_min], [x_max, y_max]) - p_d) / T
    return v


def arena_rows(
    p_d: np.ndarray, arena: tuple[float, float, float, float] | None, time_step: float
) -> list[tuple[np.ndarray, float]]:
    """Half-planes a · v ≥ b that keep a defender at ``p_d``'s step in the arena, or no farther out than it is
    (b ≤ 0: holding position keeps them); none without an arena."""
    if arena is None:
        return []
    x_min, y_min, x_max, y_max = arena
    x, y = float(p_d[0]), float(p_d[1])
    return [
        (np.array([time_step, 0.0]), min(0.0, x_min - x)),
        (np.array([-time_step, 0.0]), min(0.0, x - x_max)),
        (np.array([0.0, time_step]), min(0.0, y_min - y)),
        (np.array([0.0, -time_step]), min(0.0, y - y_max)),
    ]

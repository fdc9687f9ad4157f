"""The arena: the rectangle the attacker must be kept in.

A scenario may declare an arena (x_min, y_min, x_max, y_max). The paper gives
none (both of its simulations are open planes), so the built-in scenarios have
none. An attacker strictly beyond one of the arena's edges has escaped, and the
hunt has failed (docs/robustness.md); a point on an edge is still inside. A
sweep also counts a defender beyond an edge as a failure (``margin`` < 0).
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.geometry import length
from mpc_hunt.world.packed import HAS_ARENA, SAFETY, X_MAX, X_MIN, Y_MAX, Y_MIN, T

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


@kernel
def clear_of(x: float, y: float, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray) -> tuple[float, float]:
    """(x, y) moved into the arena, R_safe from its edges (no arena: infinite edges), and out of every obstacle's
    R_safe (Eq. 15), the obstacles in turn."""
    safe = prm[SAFETY]
    if prm[HAS_ARENA]:
        x = min(max(x, prm[X_MIN] + safe), prm[X_MAX] - safe)
        y = min(max(y, prm[Y_MIN] + safe), prm[Y_MAX] - safe)
    for j in range(radii.shape[0]):
        ox, oy = x - centres[j, 0], y - centres[j, 1]
        distance = length(ox, oy)
        if distance < radii[j] + safe:
            scale = distance if distance > 0 else 1.0
            x, y = centres[j, 0] + (radii[j] + safe) * (ox / scale), centres[j, 1] + (radii[j] + safe) * (oy / scale)
    return x, y


@kernel
def safe_of(p_d: np.ndarray, vx: float, vy: float, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """A defender's velocity (vx, vy) at ``p_d`` without its part into an obstacle's R_safe (Eq. 15) or out of
    the arena, where a step would go there."""
    T_ = prm[T]
    for j in range(radii.shape[0]):
        ix, iy = centres[j, 0] - p_d[0], centres[j, 1] - p_d[1]
        scale = length(ix, iy)
        scale = scale if scale > 0 else 1.0
        ix, iy = ix / scale, iy / scale
        along = vx * ix + vy * iy
        if length(p_d[0] + T_ * vx - centres[j, 0], p_d[1] + T_ * vy - centres[j, 1]) < radii[j] + prm[SAFETY]:
            if along > 0:
                vx, vy = vx - along * ix, vy - along * iy
    if prm[HAS_ARENA]:
        vx = (min(max(p_d[0] + T_ * vx, prm[X_MIN]), prm[X_MAX]) - p_d[0]) / T_
        vy = (min(max(p_d[1] + T_ * vy, prm[Y_MIN]), prm[Y_MAX]) - p_d[1]) / T_
    return vx, vy

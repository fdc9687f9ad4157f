"""Separation in every stage: a filter on the commands of defenders that no capture plan moves.

The capture problem keeps ``min_separation`` between the defenders it plans
(and to the others, held where they are). The approaching stage's repulsion
(Eq. 6) does not guarantee it: two approaching defenders, or one approaching a
capture-stage defender's next position, can come closer. This filter changes
each unplanned defender's velocity v as little as it can so that, after the
step of length T:

- against a defender whose next position q is known (a planned one):
  n·(p + T v − q) ≥ d_sep, with n the unit vector from q to p;
- against another unplanned defender at p_j (reciprocal, each takes half):
  n·(p + T v − m) ≥ d_sep / 2, with m the midpoint and n from p_j to p.

Each is a half-plane in v, an inner approximation of the distance, so keeping
all of them keeps every pair at least d_sep apart (both halves of a reciprocal
pair add up). A bound that the current positions already break is relaxed to
its current value ("never worse than now"), so holding position (v = 0) always
satisfies every one: the filter projects v onto each broken half-plane in turn,
caps the speed, then scales v towards 0 until none is broken.
"""

from __future__ import annotations

import math

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.geometry import capped


@kernel
def apart(x: float, y: float) -> tuple[float, float]:
    """The unit vector along (x, y); (1, 0) for a zero vector, as two defenders at one point need some direction
    apart (:func:`~mpc_hunt.world.geometry.unit` keeps it zero)."""
    length = math.hypot(x, y)
    return (x / length, y / length) if length > 0 else (1.0, 0.0)


@kernel
def separation_rows(
    i: int,
    positions: np.ndarray,
    unplanned: np.ndarray,
    planned_next: np.ndarray,
    time_step: float,
    min_separation: float,
) -> tuple[np.ndarray, np.ndarray]:
    """The half-planes a · v ≥ b of the module's docstring for the unplanned defender ``i``: (A (r, 2), b (r,)),
    the planned defenders' rows first."""
    n = positions.shape[0]
    A, b = np.empty((n, 2)), np.empty(n)
    r = 0
    px, py = positions[i, 0], positions[i, 1]
    for j in range(n):
        if not unplanned[j]:
            nx, ny = apart(px - planned_next[j, 0], py - planned_next[j, 1])
            gap = nx * (px - planned_next[j, 0]) + ny * (py - planned_next[j, 1])
            A[r, 0], A[r, 1], b[r] = time_step * nx, time_step * ny, min(min_separation, gap) - gap
            r += 1
    for j in range(n):
        if unplanned[j] and j != i:
            mx, my = 0.5 * (px + positions[j, 0]), 0.5 * (py + positions[j, 1])
            nx, ny = apart(px - positions[j, 0], py - positions[j, 1])
            gap = nx * (px - mx) + ny * (py - my)
            A[r, 0], A[r, 1], b[r] = time_step * nx, time_step * ny, min(0.5 * min_separation, gap) - gap
            r += 1
    return A[:r], b[:r]


@kernel
def onto_rows(vx: float, vy: float, A: np.ndarray, b: np.ndarray, speed: float, aim: float) -> tuple[float, float]:
    """(vx, vy) projected onto each broken half-plane A[k] · v ≥ b[k] in turn (onto A[k] · v = b[k] + ``aim``),
    capped at ``speed``, then scaled towards 0 until none is broken (every b ≤ 0, so v = 0 keeps them all)."""
    for k in range(b.shape[0]):
        ax, ay = A[k, 0], A[k, 1]
        if ax * vx + ay * vy < b[k]:
            c = (b[k] + aim - (ax * vx + ay * vy)) / (ax * ax + ay * ay)
            vx, vy = vx + c * ax, vy + c * ay
    vx, vy = capped(vx, vy, speed)
    scale = 1.0
    for k in range(b.shape[0]):
        along = A[k, 0] * vx + A[k, 1] * vy
        if along < b[k]:
            scale = min(scale, b[k] / along)
    return scale * vx, scale * vy


@kernel
def separated(positions, velocities, unplanned, planned_next, time_step, speeds, min_separation) -> None:
    """:func:`keep_separation` in place."""
    for i in range(positions.shape[0]):
        if unplanned[i]:
            A, b = separation_rows(i, positions, unplanned, planned_next, time_step, min_separation)
            velocities[i, 0], velocities[i, 1] = onto_rows(velocities[i, 0], velocities[i, 1], A, b, speeds[i], 0.0)


def keep_separation(
    positions: np.ndarray,
    velocities: np.ndarray,
    unplanned: np.ndarray,
    planned_next: np.ndarray,
    time_step: float,
    speeds: np.ndarray,
    min_separation: float,
) -> np.ndarray:
    """``velocities`` with the unplanned defenders' rows filtered (see the module's docstring).

    ``planned_next`` holds the next positions of the defenders not in
    ``unplanned`` (rows of unplanned defenders are ignored).
    """
    out = np.array(velocities, dtype=float)
    positions, planned_next = np.asarray(positions, dtype=float), np.asarray(planned_next, dtype=float)
    unplanned, speeds = np.asarray(unplanned, dtype=bool), np.asarray(speeds, dtype=float)
    separated(positions, out, unplanned, planned_next, float(time_step), speeds, float(min_separation))
    return out

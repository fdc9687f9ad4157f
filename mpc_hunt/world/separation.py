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

from collections.abc import Callable

import numpy as np

from mpc_hunt.world.geometry import dot2, saturate


def _normal(v: np.ndarray) -> np.ndarray:
    """The unit vector along the 2-vector ``v``; (1, 0) for a zero vector, as two defenders at one point
    need some direction apart (:func:`~mpc_hunt.world.geometry.unit` keeps it zero). Its length is
    ``np.hypot``'s, whose last bit the committed hunts depend on."""
    length = float(np.hypot(*v))
    return v / length if length > 0 else np.array([1.0, 0.0])


def keep_separation(
    positions: np.ndarray,
    velocities: np.ndarray,
    unplanned: np.ndarray,
    planned_next: np.ndarray,
    time_step: float,
    speeds: np.ndarray,
    min_separation: float,
    also: Callable[[int], list] | None = None,
) -> np.ndarray:
    """``velocities`` with the unplanned defenders' rows filtered (see the module's docstring).

    ``planned_next`` holds the next positions of the defenders not in
    ``unplanned`` (rows of unplanned defenders are ignored). ``also(i)``, if given, are more half-planes
    (a, b) that defender ``i`` keeps in the same filter, each with b ≤ 0 (holding position keeps it): the
    obstacles' safety distance, say (:func:`mpc_hunt.world.safety.safety_rows`), which a projection onto a
    separation row could otherwise break.
    """
    out = np.array(velocities, dtype=float)
    planned = np.flatnonzero(~unplanned)
    movers = np.flatnonzero(unplanned)
    for i in movers:
        p = positions[i]
        rows = []  # (a, b): a · v ≥ b
        for j in planned:
            n = _normal(p - planned_next[j])
            gap = dot2(n, p - planned_next[j])
            rows.append((time_step * n, min(min_separation, gap) - gap))
        for j in movers:
            if j != i:
                m, n = 0.5 * (p + positions[j]), _normal(p - positions[j])
                gap = dot2(n, p - m)
                rows.append((time_step * n, min(0.5 * min_separation, gap) - gap))
        if also is not None:
            rows += also(int(i))
        out[i] = onto_half_planes(out[i], rows, speeds[i])
    return out


def onto_half_planes(v: np.ndarray, rows: list[tuple[np.ndarray, float]], speed: float, aim: float = 0.0) -> np.ndarray:
    """``v`` projected onto each broken half-plane a · v ≥ b of ``rows`` in turn (onto a · v = b + ``aim``),
    capped at ``speed``, then scaled towards 0 until none is broken (every b ≤ 0, so v = 0 keeps them all)."""
    for a, b in rows:
        if dot2(a, v) < b:
            v = v + (b + aim - dot2(a, v)) / dot2(a, a) * a
    v = saturate(v, speed)
    scale = min([1.0] + [b / dot2(a, v) for a, b in rows if dot2(a, v) < b])
    return scale * v

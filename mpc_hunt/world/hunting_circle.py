"""The hunting circle: its members, the herding target (Eqs. 10–11) and the success test (Eqs. 4–5).

Members (docs/model.md, E5, E7): every defender robot, plus obstacles used as stationary
defenders. An obstacle joins when its surface lies within the given radius of
the attacker; when there are fewer than three robots, the nearest obstacles are
recruited until the circle has three members, since three are the fewest that
can surround an attacker. A member's *anchor* is its position (a robot) or the
surface point nearest the attacker (an obstacle); its distance to the attacker
is measured to that anchor, so R_hunt is a clearance from the obstacle's surface.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.geometry import encloses, length, saturate

MIN_MEMBERS = 3


@dataclass(frozen=True)
class Members:
    """Who forms the hunting circle, and where each member stands."""

    anchors: np.ndarray  # (k, 2): robots first, then obstacle surface points
    distances: np.ndarray  # (k,): distance from the attacker to each anchor
    obstacle_indices: tuple[int, ...]

    @property
    def centre(self) -> np.ndarray:
        """Eq. 4's right-hand side (Eq. 11 read as it): the mean of the members' anchors."""
        return self.anchors.mean(axis=0)


@kernel
def member_arrays(
    p_a: np.ndarray, defenders: np.ndarray, centres: np.ndarray, radii: np.ndarray, obstacle_range: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(anchors (k, 2), distances (k,), the obstacles' indices, ascending) of :func:`members`."""
    n, m = defenders.shape[0], radii.shape[0]
    gaps = np.empty(m)
    for j in range(m):
        gaps[j] = length(p_a[0] - centres[j, 0], p_a[1] - centres[j, 1]) - radii[j]
    chosen = np.zeros(m, dtype=np.bool_)
    count = 0
    for j in range(m):
        if gaps[j] <= obstacle_range:
            chosen[j] = True
            count += 1
    if n + count < MIN_MEMBERS:  # recruit the nearest, in order of their gaps (ties by index)
        for j in np.argsort(gaps, kind="mergesort"):
            if n + count >= MIN_MEMBERS:
                break
            if not chosen[j]:
                chosen[j] = True
                count += 1
    obstacles = np.flatnonzero(chosen)
    anchors = np.empty((n + count, 2))
    distances = np.empty(n + count)
    for i in range(n):
        anchors[i] = defenders[i]
        distances[i] = length(p_a[0] - defenders[i, 0], p_a[1] - defenders[i, 1])
    for k in range(count):
        j = obstacles[k]
        tx, ty = p_a[0] - centres[j, 0], p_a[1] - centres[j, 1]
        scale = length(tx, ty)
        scale = scale if scale > 0 else 1.0
        anchors[n + k, 0] = centres[j, 0] + tx / scale * radii[j]
        anchors[n + k, 1] = centres[j, 1] + ty / scale * radii[j]
        distances[n + k] = max(gaps[j], 0.0)
    return anchors, distances, obstacles


def members(
    p_a: np.ndarray, defenders: np.ndarray, centres: np.ndarray, radii: np.ndarray, obstacle_range: float
) -> Members:
    """Robots plus obstacles within ``obstacle_range`` of the attacker (recruiting up to three)."""
    anchors, distances, obstacles = member_arrays(
        np.asarray(p_a, dtype=float),
        np.asarray(defenders, dtype=float).reshape(-1, 2),
        np.asarray(centres, dtype=float).reshape(-1, 2),
        np.asarray(radii, dtype=float).reshape(-1),
        float(obstacle_range),
    )
    return Members(anchors, distances, tuple(int(j) for j in obstacles))


def desired_velocity(p_a: np.ndarray, target: np.ndarray, max_speed: float, hunt_radius: float) -> np.ndarray:
    """u'_a of Eq. 12: towards the herding target p_k at angle α (Eq. 10).

    Full speed while the attacker is farther than R_hunt from p_k, proportional
    inside (time constant R_hunt / v_a,max), so it settles at p_k instead of
    overshooting it.
    """
    offset = np.asarray(target, dtype=float) - np.asarray(p_a, dtype=float)
    return saturate(offset * (max_speed / hunt_radius), max_speed)


@dataclass(frozen=True)
class CircleStatus:
    """One evaluation of the success test (Eqs. 4–5)."""

    holds: bool
    radius: float  # largest member distance: the hunting radius
    centre_offset: float  # |p_a − mean of anchors|
    enclosed: bool
    member_count: int


@kernel
def circle_test(p_a, defenders, centres, radii, hunt_radius, centre_tolerance):
    """(holds, radius, centre offset, enclosed, member count) of :func:`success_test`."""
    anchors, distances, _ = member_arrays(p_a, defenders, centres, radii, hunt_radius)
    k = anchors.shape[0]
    cx = cy = 0.0
    for i in range(k):
        cx += anchors[i, 0]
        cy += anchors[i, 1]
    cx, cy = cx / k, cy / k
    offset = length(p_a[0] - cx, p_a[1] - cy)
    enclosed = encloses(p_a, anchors)
    radius = distances.max()
    holds = k >= MIN_MEMBERS and radius <= hunt_radius and enclosed and offset <= centre_tolerance
    return holds, radius, offset, enclosed, k


def success_test(
    p_a: np.ndarray,
    defenders: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    hunt_radius: float,
    centre_tolerance: float,
) -> CircleStatus:
    """Eqs. 4–5: at least three members, every one within R_hunt, the attacker enclosed and at their centre.

    Members here are all robots plus the obstacles whose surface lies within
    R_hunt (docs/model.md, E7). Eq. 4's equality is read as "within ``centre_tolerance``
    of the centroid" together with strict enclosure (the attacker inside the
    members' convex hull), which is what "surrounded" requires.
    """
    holds, radius, offset, enclosed, count = circle_test(
        np.asarray(p_a, dtype=float),
        np.asarray(defenders, dtype=float).reshape(-1, 2),
        np.asarray(centres, dtype=float).reshape(-1, 2),
        np.asarray(radii, dtype=float).reshape(-1),
        float(hunt_radius),
        float(centre_tolerance),
    )
    return CircleStatus(bool(holds), float(radius), float(offset), bool(enclosed), int(count))

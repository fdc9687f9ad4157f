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

from mpc_hunt.world.geometry import encloses, norm, saturate, unit

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


def members(
    p_a: np.ndarray, defenders: np.ndarray, centres: np.ndarray, radii: np.ndarray, obstacle_range: float
) -> Members:
    """Robots plus obstacles within ``obstacle_range`` of the attacker (recruiting up to three)."""
    p_a = np.asarray(p_a, dtype=float)
    defenders = np.asarray(defenders, dtype=float).reshape(-1, 2)
    centres = np.asarray(centres, dtype=float).reshape(-1, 2)
    radii = np.asarray(radii, dtype=float)
    to_attacker = p_a - centres
    gaps = norm(to_attacker) - radii
    chosen = [j for j in np.argsort(gaps, kind="stable") if gaps[j] <= obstacle_range]
    for j in np.argsort(gaps, kind="stable"):
        if len(defenders) + len(chosen) >= MIN_MEMBERS:
            break
        if j not in chosen:
            chosen.append(int(j))
    chosen = sorted(int(j) for j in chosen)
    surface = centres[chosen] + unit(to_attacker[chosen]) * radii[chosen, None]
    anchors = np.vstack([defenders, surface.reshape(-1, 2)])
    distances = np.concatenate([norm(p_a - defenders), np.maximum(gaps[chosen], 0.0)])
    return Members(anchors, distances, tuple(chosen))


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
    m = members(p_a, defenders, centres, radii, hunt_radius)
    offset = float(norm(np.asarray(p_a, dtype=float) - m.centre))
    enclosed = encloses(np.asarray(p_a, dtype=float), m.anchors)
    radius = float(m.distances.max())
    holds = len(m.anchors) >= MIN_MEMBERS and radius <= hunt_radius and enclosed and offset <= centre_tolerance
    return CircleStatus(holds, radius, offset, enclosed, len(m.anchors))

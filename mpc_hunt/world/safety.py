"""The safety distance in the approaching stage: a filter on an approaching defender's command.

The capture problem keeps every planned defender R_safe from every obstacle's
surface (Eq. 15). The approaching stage's obstacle response (Eq. 6) only bends
a defender's way and bounds nothing: heading for an intercept past an obstacle,
a defender can come inside R_safe (0.094 m of a surface on held-out hunts, with
R_safe = 0.1 m). This filter leaves a velocity v as it is unless the step of
length T would end inside R_safe of an obstacle, or, for a defender already
inside, closer than it is now ("never worse than now"). Only then it keeps, for
every obstacle of centre c and radius r, with n the unit vector from c to p:

    n·(p + T v − c) ≥ r + min(R_safe, |p − c| − r),

a half-plane in v inside the disc it stands for, as the separation filter's
rows are (:mod:`mpc_hunt.world.separation`). It projects v onto each broken
half-plane (which takes away the inward radial part: the defender slides along
the obstacle), aiming ``AIM`` inside it so that round-off cannot leave it
broken, caps the speed, then scales v towards 0 until none is broken; holding
position keeps every one.
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.world.geometry import norm
from mpc_hunt.world.separation import onto_half_planes

AIM = 1e-12  # m: how far inside a broken row's half-plane a projection aims


def _floors(
    p: np.ndarray, centres: np.ndarray, radii: np.ndarray, safety_distance: float
) -> tuple[np.ndarray, np.ndarray]:
    """(the distance from ``p`` to each centre, the least distance allowed to it: "never worse than now")."""
    distances = norm(p - centres)
    return distances, radii + np.minimum(safety_distance, distances - radii)


def safety_rows(
    p: np.ndarray, centres: np.ndarray, radii: np.ndarray, safety_distance: float, time_step: float
) -> list[tuple[np.ndarray, float]]:
    """The module's half-planes a · v ≥ b for a defender at ``p``, one per obstacle."""
    distances, floor = _floors(p, centres, radii, safety_distance)
    return [(time_step * (p - c) / d, f - d) for c, d, f in zip(centres, distances, floor)]


def keep_safety_distance(
    p: np.ndarray,
    v: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    safety_distance: float,
    time_step: float,
    speed: float,
) -> np.ndarray:
    """``v`` for a defender at ``p``, filtered as the module's docstring says (unchanged unless it must be)."""
    if np.all(norm(p + time_step * v - centres) >= _floors(p, centres, radii, safety_distance)[1]):
        return v
    return onto_half_planes(v, safety_rows(p, centres, radii, safety_distance, time_step), speed, AIM)

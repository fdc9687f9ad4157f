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

from mpc_hunt.compiled import kernel
from mpc_hunt.world.geometry import length
from mpc_hunt.world.separation import onto_rows

AIM = 1e-12  # m: how far inside a broken row's half-plane a projection aims


@kernel
def safety_arrays(p, centres, radii, safety_distance, time_step):
    """The module's half-planes A[j] · v ≥ b[j] for a defender at ``p``, one per obstacle."""
    m = radii.shape[0]
    A, b = np.empty((m, 2)), np.empty(m)
    for j in range(m):
        d = length(p[0] - centres[j, 0], p[1] - centres[j, 1])
        floor = radii[j] + min(safety_distance, d - radii[j])
        A[j, 0], A[j, 1] = time_step * (p[0] - centres[j, 0]) / d, time_step * (p[1] - centres[j, 1]) / d
        b[j] = floor - d
    return A, b


@kernel
def kept_safe(p, vx, vy, centres, radii, safety_distance, time_step, speed):
    """(vx, vy) for a defender at ``p``, filtered as the module's docstring says (unchanged unless it must be)."""
    broken = False
    for j in range(radii.shape[0]):
        d = length(p[0] - centres[j, 0], p[1] - centres[j, 1])
        floor = radii[j] + min(safety_distance, d - radii[j])
        broken = broken or not (
            length(p[0] + time_step * vx - centres[j, 0], p[1] + time_step * vy - centres[j, 1]) >= floor
        )
    if not broken:
        return vx, vy
    A, b = safety_arrays(p, centres, radii, safety_distance, time_step)
    return onto_rows(vx, vy, A, b, speed, AIM)


def keep_safety_distance(
    p: np.ndarray,
    v: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    safety_distance: float,
    time_step: float,
    speed: float,
) -> np.ndarray:
    """``v`` for a defender at ``p``, filtered as the module's docstring says (``v`` itself when unchanged)."""
    p, centres, radii = np.asarray(p, dtype=float), np.asarray(centres, dtype=float), np.asarray(radii, dtype=float)
    out = kept_safe(p, float(v[0]), float(v[1]), centres.reshape(-1, 2), radii.reshape(-1), float(safety_distance),
                    float(time_step), float(speed))  # fmt: skip
    return v if out == (v[0], v[1]) else np.array(out)

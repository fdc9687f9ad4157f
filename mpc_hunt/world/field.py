"""The artificial potential field (Eqs. 2, 3 and 9) in NumPy.

Sign (docs/model.md, E1): the printed η(1 − R³/|r|³)·r attracts; the text says the field
repels, so H(r) = η(R³/|r|³ − 1)·r for |r| < R and 0 beyond. It points along r
(away from the source when r = p_target − p_source), is zero and continuous at
|r| = R, and grows without bound as |r| → 0.

Obstacles (docs/model.md, E2): an obstacle's field is H applied to the offset from the
nearest point of its surface, with range ``protective_distance``. Measured from
the centre, an obstacle of radius 1 m would exert no force outside itself with
R = 1 m.

Distances below ``FIELD_FLOOR`` are raised to it (the offset keeps its
direction and takes the floor's length), so the field stays finite, and huge,
at a contact or inside an obstacle instead of becoming NaN. Only an offset of
exactly zero, which has no direction, gives no push. The optimiser's field
(:mod:`mpc_hunt.formulations.field`) is this one in CasADi, or rounded at |r| = R.
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.world.geometry import norm, saturate

FIELD_FLOOR = 1e-3


def repulsion_gain(d, length, radius: float, eta: float, select=np.where):
    """H(r)/|r| of Eq. 2: η (R³/d³ − 1) d/|r| for the floored distance d < R, else 0, with |r| = ``length``.

    ``select`` is np.where here, casadi.if_else in the optimiser's field (:mod:`mpc_hunt.formulations.field`).
    """
    return select(d < radius, eta * (radius**3 / d**3 - 1.0), 0.0) * d / length


def repulsion(r: np.ndarray, radius: float, eta: float) -> np.ndarray:
    """H(r) of Eq. 2 for vectors ``r`` of shape (..., 2): repulsive, zero for |r| ≥ radius."""
    r = np.asarray(r, dtype=float)
    length = norm(r)
    gain = repulsion_gain(np.maximum(length, FIELD_FLOOR), np.where(length > 0, length, 1.0), radius, eta)
    return r * gain[..., None]


def surface_offset(p: np.ndarray, centres: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Offsets from the nearest surface point of each obstacle to ``p``: shape (m, 2).

    Inside an obstacle the offset keeps the outward direction with length
    ``FIELD_FLOOR``, so its field pushes the point back out.
    """
    v = np.asarray(p, dtype=float) - np.asarray(centres, dtype=float).reshape(-1, 2)
    dc = norm(v)
    direction = v / np.where(dc > 0, dc, 1.0)[:, None]
    clearance = np.maximum(dc - np.asarray(radii, dtype=float), FIELD_FLOOR)
    return direction * clearance[:, None]


def obstacle_repulsion(p: np.ndarray, centres: np.ndarray, radii: np.ndarray, radius: float, eta: float) -> np.ndarray:
    """Σ_o H(r_o) of Eq. 3 (docs/model.md, E2: distances from the surface)."""
    if len(radii) == 0:
        return np.zeros(2)
    return repulsion(surface_offset(p, centres, radii), radius, eta).sum(axis=0)


def nominal_intent(nominal_velocity: np.ndarray, max_speed: float) -> np.ndarray:
    """The attacker's nominal velocity capped at its max speed (docs/model.md, E6).

    The paper's [0.2, −0.2] exceeds v_a,max = 0.03 m/s; an attacker cannot intend
    a speed it cannot reach, so the printed vector keeps its direction and is
    capped, giving 0.03 m/s along (1, −1)/√2.
    """
    return saturate(np.asarray(nominal_velocity, dtype=float), max_speed)


def attacker_resultant(
    p_a: np.ndarray,
    defenders: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    *,
    nominal: np.ndarray,
    perception_radius: float,
    protective_distance: float,
    eta: float,
    k_d: float,
    k_o: float,
) -> np.ndarray:
    """The resultant on the attacker (Eq. 9 plus its nominal intent, Eq. 2).

    u = v_nom + k_d Σ_i H(p_a − p_di) + k_o Σ_o H(r_ao).
    """
    p_a = np.asarray(p_a, dtype=float)
    push_d = repulsion(p_a - np.asarray(defenders, dtype=float).reshape(-1, 2), perception_radius, eta).sum(axis=0)
    push_o = obstacle_repulsion(p_a, centres, radii, protective_distance, eta)
    return nominal + k_d * push_d + k_o * push_o

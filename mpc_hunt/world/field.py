"""The artificial potential field (Eqs. 2, 3 and 9), compiled (:mod:`mpc_hunt.compiled`).

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

import math

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.geometry import saturate

FIELD_FLOOR = 1e-3


def repulsion_gain(d, length, radius: float, eta: float, select):
    """H(r)/|r| of Eq. 2: η (R³/d³ − 1) d/|r| for the floored distance d < R, else 0, with |r| = ``length``.

    ``select`` is casadi.if_else in the optimiser's field (:mod:`mpc_hunt.formulations.field`); the world's
    compiled :func:`push` is this expression in the same order of operations (a test holds the two to the bit).
    """
    return select(d < radius, eta * (radius**3 / d**3 - 1.0), 0.0) * d / length


@kernel
def push(rx: float, ry: float, radius: float, eta: float) -> tuple[float, float]:
    """H(r) of Eq. 2 for one vector r = (rx, ry): :func:`repulsion_gain` with the floored distance."""
    length = math.sqrt(rx * rx + ry * ry)
    d = max(length, FIELD_FLOOR)
    gain = (eta * (math.pow(radius, 3.0) / math.pow(d, 3.0) - 1.0) if d < radius else 0.0) * d
    gain = gain / (length if length > 0 else 1.0)
    return rx * gain, ry * gain


@kernel
def pushes(p: np.ndarray, sources: np.ndarray, radius: float, eta: float) -> tuple[float, float]:
    """Σ H(p − s) over the rows s of ``sources`` (k, 2): the defenders' field on the attacker (Eq. 9)."""
    x = y = 0.0
    for i in range(sources.shape[0]):
        hx, hy = push(p[0] - sources[i, 0], p[1] - sources[i, 1], radius, eta)
        x += hx
        y += hy
    return x, y


@kernel
def obstacle_push(p: np.ndarray, centres: np.ndarray, radii: np.ndarray, radius: float, eta: float):
    """Σ_o H(r_o) of Eq. 3 at ``p`` (docs/model.md, E2: from the surface; inside an obstacle, the offset keeps the
    outward direction with length ``FIELD_FLOOR``, so its field pushes the point back out)."""
    x = y = 0.0
    for j in range(radii.shape[0]):
        vx, vy = p[0] - centres[j, 0], p[1] - centres[j, 1]
        dc = math.sqrt(vx * vx + vy * vy)
        scale = dc if dc > 0 else 1.0
        clearance = max(dc - radii[j], FIELD_FLOOR)
        hx, hy = push(vx / scale * clearance, vy / scale * clearance, radius, eta)
        x += hx
        y += hy
    return x, y


def repulsion(r: np.ndarray, radius: float, eta: float) -> np.ndarray:
    """H(r) of Eq. 2 for vectors ``r`` of shape (..., 2): repulsive, zero for |r| ≥ radius."""
    r = np.asarray(r, dtype=float)
    out = np.empty_like(r)
    for index in np.ndindex(r.shape[:-1]):
        out[index] = push(float(r[index][0]), float(r[index][1]), radius, eta)
    return out


def obstacle_repulsion(p: np.ndarray, centres: np.ndarray, radii: np.ndarray, radius: float, eta: float) -> np.ndarray:
    """Σ_o H(r_o) of Eq. 3 (docs/model.md, E2: distances from the surface)."""
    p = np.asarray(p, dtype=float)
    c = np.asarray(centres, dtype=float).reshape(-1, 2)
    return np.array(obstacle_push(p, c, np.asarray(radii, dtype=float).reshape(-1), radius, eta))


def nominal_intent(nominal_velocity: np.ndarray, max_speed: float) -> np.ndarray:
    """The attacker's nominal velocity capped at its max speed (docs/model.md, E6).

    The paper's [0.2, −0.2] exceeds v_a,max = 0.03 m/s; an attacker cannot intend
    a speed it cannot reach, so the printed vector keeps its direction and is
    capped, giving 0.03 m/s along (1, −1)/√2.
    """
    return saturate(np.asarray(nominal_velocity, dtype=float), max_speed)

"""Trajectory prediction (Eqs. 7–8): where a defender can meet the attacker.

The attacker is assumed to keep its current velocity v_a (Eq. 7: the intercept
lies on its line of motion). The intercept is the earliest point the defender,
moving straight at speed s_d, reaches at the same time as the attacker (Eq. 8,
read with speeds, docs/model.md, E8): the smallest t ≥ 0 with |w + v_a t| = s_d t,
w = p_a − p_d, i.e. (|v_a|² − s_d²) t² + 2 (w·v_a) t + |w|² = 0.

When no such t exists (an attacker at least as fast as the defender and moving
away), :func:`intercept_point` returns ``None`` and the approach law pursues
the attacker's current position instead.
"""

from __future__ import annotations

import math

import numpy as np

from mpc_hunt.compiled import kernel


@kernel
def meeting(p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, speed: float) -> tuple[bool, float]:
    """(whether the defender can meet the attacker, the earliest meeting time of Eq. 8)."""
    wx, wy = p_a[0] - p_d[0], p_a[1] - p_d[1]
    a = (v_a[0] * v_a[0] + v_a[1] * v_a[1]) - speed**2
    b = 2.0 * (wx * v_a[0] + wy * v_a[1])
    c = wx * wx + wy * wy
    if c == 0.0:
        return True, 0.0
    if abs(a) < 1e-12 * max(speed**2, 1e-300):  # equal speeds: linear equation b t + c = 0
        return (True, -c / b) if b < 0 else (False, 0.0)
    disc = b * b - 4.0 * a * c
    if disc < 0:
        return False, 0.0
    root = math.sqrt(disc)
    # Stable roots of a t² + b t + c = 0.
    q = -0.5 * (b + math.copysign(root, b))
    found, best = False, math.inf
    for t in (q / a, c / q if q != 0 else math.inf):
        if t >= 0 and math.isfinite(t) and t < best:
            found, best = True, t
    return found, best


@kernel
def meeting_point(p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, speed: float) -> tuple[bool, float, float]:
    """(found, x, y): p'_di of Eq. 6, the attacker's position at the intercept time."""
    found, t = meeting(p_a, v_a, p_d, speed)
    return found, p_a[0] + t * v_a[0], p_a[1] + t * v_a[1]


def intercept_time(p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, speed: float) -> float | None:
    """Earliest meeting time of Eq. 8, or ``None`` when the defender cannot meet the attacker."""
    a, v, d = _vectors(p_a, v_a, p_d)
    found, t = meeting(a, v, d, float(speed))
    return float(t) if found else None


def intercept_point(p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, speed: float) -> np.ndarray | None:
    """p'_di of Eq. 6: the attacker's position at the intercept time, or ``None`` (no intercept)."""
    a, v, d = _vectors(p_a, v_a, p_d)
    found, x, y = meeting_point(a, v, d, float(speed))
    return np.array([x, y]) if found else None


def _vectors(p_a, v_a, p_d) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return tuple(np.asarray(v, dtype=float).reshape(2) for v in (p_a, v_a, p_d))  # type: ignore[return-value]

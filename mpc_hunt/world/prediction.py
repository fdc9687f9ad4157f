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

from mpc_hunt.world.geometry import dot2


def intercept_time(p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, speed: float) -> float | None:
    """Earliest meeting time of Eq. 8, or ``None`` when the defender cannot meet the attacker."""
    w = np.asarray(p_a, dtype=float) - np.asarray(p_d, dtype=float)
    v = np.asarray(v_a, dtype=float)
    a = dot2(v, v) - speed**2
    b = 2.0 * dot2(w, v)
    c = dot2(w, w)
    if c == 0.0:
        return 0.0
    if abs(a) < 1e-12 * max(speed**2, 1e-300):  # equal speeds: linear equation b t + c = 0
        return -c / b if b < 0 else None
    disc = b * b - 4.0 * a * c
    if disc < 0:
        return None
    root = math.sqrt(disc)
    # Stable roots of a t² + b t + c = 0.
    q = -0.5 * (b + math.copysign(root, b))
    candidates = [t for t in (q / a, c / q if q != 0 else math.inf) if t >= 0 and math.isfinite(t)]
    return min(candidates) if candidates else None


def intercept_point(p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, speed: float) -> np.ndarray | None:
    """p'_di of Eq. 6: the attacker's position at the intercept time, or ``None`` (no intercept)."""
    t = intercept_time(p_a, v_a, p_d, speed)
    if t is None:
        return None
    return np.asarray(p_a, dtype=float) + t * np.asarray(v_a, dtype=float)

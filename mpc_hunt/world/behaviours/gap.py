"""``gap``: through the widest angular gap between the defenders it senses.

A gap-seeking evader, common among the baselines of multi-agent pursuit
benchmarks: the bearings of the sensed defenders, seen from the attacker, split
the turn into gaps; the attacker runs at full speed along the bisector of the
widest, unless its intent already points into that gap at least
``GAP_MARGIN`` from both edges, in which case it keeps its intent's heading.
With one defender sensed the gap is the whole turn but that defender's bearing;
with none, it follows its intent.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.behaviours.base import CompiledBehaviour, calm, headed, near
from mpc_hunt.world.packed import NOMINAL_X, NOMINAL_Y, SENSING

if TYPE_CHECKING:
    pass

GAP_MARGIN = math.pi / 6  # rad: how far inside the widest gap the intent must point to be kept


@kernel
def widest_gap(p_a: np.ndarray, near: np.ndarray) -> tuple[float, float]:
    """(the bearing of the gap's first edge, its width), counter-clockwise, among the bearings of ``near``."""
    k = near.shape[0]
    bearings = np.empty(k)
    for i in range(k):
        bearings[i] = math.atan2(near[i, 1] - p_a[1], near[i, 0] - p_a[0])
    bearings.sort()
    start, width = 0.0, -1.0
    for i in range(k):  # the first of equally wide gaps
        gap = (bearings[i + 1] if i + 1 < k else bearings[0] + 2 * math.pi) - bearings[i]
        if gap > width:
            start, width = bearings[i], gap
    return start, width


@kernel
def gap_heading(p_a: np.ndarray, near: np.ndarray, ix: float, iy: float) -> float:
    """The bearing the attacker runs along: its intent's (ix, iy) if inside the widest gap with the margin, else
    the gap's bisector."""
    start, width = widest_gap(p_a, near)
    if math.hypot(ix, iy) > 0:
        into = (math.atan2(iy, ix) - start) % (2 * math.pi)
        if GAP_MARGIN <= into <= width - GAP_MARGIN:
            return start + into
    return start + 0.5 * width


@kernel
def gap_velocity(p_a: np.ndarray, p_d: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """The ``gap`` attacker's velocity (the module's docstring)."""
    sensed = near(p_a, p_d, prm[SENSING])
    if sensed.shape[0] == 0:
        return calm(p_a, centres, radii, prm)
    angle = gap_heading(p_a, sensed, prm[NOMINAL_X], prm[NOMINAL_Y])
    return headed(p_a, math.cos(angle), math.sin(angle), centres, radii, prm)


class GapAttacker(CompiledBehaviour):
    """Through the widest gap between the sensed defenders (the module's docstring)."""

    rule = staticmethod(gap_velocity)

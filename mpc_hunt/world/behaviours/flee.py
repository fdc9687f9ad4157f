"""``flee``: full speed away from the defenders it senses, each weighted by its inverse square distance.

The repulsion-from-every-pursuer evader of de Souza et al. (RA-L 2021, arXiv
2010.08193), with a sensing radius: the heading is Σ (p_a − p_i) / |p_a − p_i|³
over the sensed defenders; with none sensed, its intent.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.behaviours.base import CompiledBehaviour, calm, headed, near
from mpc_hunt.world.geometry import length
from mpc_hunt.world.packed import SENSING

if TYPE_CHECKING:
    pass


@kernel
def flee_direction(p_a: np.ndarray, near: np.ndarray) -> np.ndarray:
    """Σ (p_a − p_i) / |p_a − p_i|³: away from each defender, the nearest weighing most."""
    out = np.zeros(2)
    for i in range(near.shape[0]):
        ax, ay = p_a[0] - near[i, 0], p_a[1] - near[i, 1]
        cube = math.pow(length(ax, ay), 3.0)
        out[0] += ax / cube
        out[1] += ay / cube
    return out


@kernel
def flee_velocity(p_a: np.ndarray, p_d: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """The ``flee`` attacker's velocity (the module's docstring)."""
    sensed = near(p_a, p_d, prm[SENSING])
    if sensed.shape[0] == 0:
        return calm(p_a, centres, radii, prm)
    away = flee_direction(p_a, sensed)
    return headed(p_a, away[0], away[1], centres, radii, prm)


class FleeingAttacker(CompiledBehaviour):
    """Away from the sensed defenders at full speed (the module's docstring)."""

    rule = staticmethod(flee_velocity)

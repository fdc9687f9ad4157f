"""``flee``: full speed away from the defenders it senses, each weighted by its inverse square distance.

The repulsion-from-every-pursuer evader of de Souza et al. (RA-L 2021, arXiv
2010.08193), with a sensing radius: the heading is Σ (p_a − p_i) / |p_a − p_i|³
over the sensed defenders; with none sensed, its intent.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.world.behaviours.base import heading, sensed, sensing_radius, undisturbed
from mpc_hunt.world.geometry import norm

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario


def flee_direction(p_a: np.ndarray, near: np.ndarray) -> np.ndarray:
    """Σ (p_a − p_i) / |p_a − p_i|³: away from each defender, the nearest weighing most."""
    away = p_a - near
    return np.sum(away / norm(away)[:, None] ** 3, axis=0)


class FleeingAttacker:
    """Away from the sensed defenders at full speed (the module's docstring)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator):
        self.scenario = scenario
        self.radius = sensing_radius(scenario)

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        near = sensed(p_a, p_d, self.radius)
        if not len(near):
            return undisturbed(self.scenario, p_a)
        return heading(self.scenario, p_a, flee_direction(p_a, near))

"""``voronoi``: towards the centroid of its Voronoi cell among the defenders it senses.

The Voronoi evader of Pierson et al. ("Intercepting rogue robots", RA-L 2017):
the attacker's cell is the set of points it reaches before any sensed defender
(:mod:`mpc_hunt.world.voronoi_cell`), bounded by the arena, by the square of
half-side the sensing radius round it (it knows nothing farther) and by the
obstacles' tangents; it moves at full speed towards the cell's centroid, more
slowly within one step of it. With no defender sensed it follows its intent.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.world.behaviours.base import sensed, sensing_radius, steered, undisturbed
from mpc_hunt.world.geometry import saturate
from mpc_hunt.world.voronoi_cell import attacker_cell

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario


def centroid(vertices: np.ndarray) -> np.ndarray:
    """The area centroid of a simple polygon (its vertices in order); the vertices' mean if it has no area."""
    x, y = vertices[:, 0], vertices[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * float(np.sum(cross))
    if abs(area) < 1e-12:
        return vertices.mean(axis=0)
    return np.array([np.sum((x + xn) * cross), np.sum((y + yn) * cross)]) / (6.0 * area)


class VoronoiAttacker:
    """Towards its Voronoi cell's centroid (the module's docstring)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator):
        self.scenario = scenario
        self.radius = sensing_radius(scenario)

    def box(self, p_a: np.ndarray) -> tuple[float, float, float, float]:
        """The square of half-side the sensing radius round ``p_a``, cut to the arena if there is one."""
        r = self.radius
        x_min, y_min, x_max, y_max = p_a[0] - r, p_a[1] - r, p_a[0] + r, p_a[1] + r
        if self.scenario.arena is not None:
            ax0, ay0, ax1, ay1 = self.scenario.arena
            x_min, y_min, x_max, y_max = max(x_min, ax0), max(y_min, ay0), min(x_max, ax1), min(y_max, ay1)
        return (x_min, y_min, max(x_max, x_min), max(y_max, y_min))

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        s = self.scenario
        near = sensed(p_a, p_d, self.radius)
        if not len(near):
            return undisturbed(s, p_a)
        cell = attacker_cell(p_a, near, s.obstacle_centres, s.obstacle_radii, self.box(p_a))
        if not len(cell.vertices):
            return np.zeros(2)
        return steered(s, p_a, saturate((centroid(cell.vertices) - p_a) / s.hunt.time_step, s.attacker.max_speed))

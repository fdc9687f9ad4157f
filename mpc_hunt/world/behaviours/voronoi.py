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

from mpc_hunt.compiled import kernel
from mpc_hunt.world.behaviours.base import CompiledBehaviour, calm, near, wished
from mpc_hunt.world.geometry import capped
from mpc_hunt.world.packed import SENSING, V_A, X_MAX, X_MIN, Y_MAX, Y_MIN, T
from mpc_hunt.world.voronoi_cell import cell_of

if TYPE_CHECKING:
    pass


@kernel
def centroid(vertices: np.ndarray) -> tuple[float, float]:
    """The area centroid of a simple polygon (its vertices in order); the vertices' mean if it has no area."""
    m = vertices.shape[0]
    area = cx = cy = 0.0
    for k in range(m):
        x, y = vertices[k, 0], vertices[k, 1]
        xn, yn = vertices[(k + 1) % m, 0], vertices[(k + 1) % m, 1]
        cross = x * yn - xn * y
        area += cross
        cx += (x + xn) * cross
        cy += (y + yn) * cross
    area *= 0.5
    if abs(area) < 1e-12:
        return vertices[:, 0].mean(), vertices[:, 1].mean()
    return cx / (6.0 * area), cy / (6.0 * area)


@kernel
def sensed_box(p_a: np.ndarray, prm: np.ndarray) -> np.ndarray:
    """The square of half-side the sensing radius round ``p_a``, cut to the arena (whose edges are infinite when
    there is none)."""
    r = prm[SENSING]
    x_min, y_min = max(p_a[0] - r, prm[X_MIN]), max(p_a[1] - r, prm[Y_MIN])
    x_max, y_max = min(p_a[0] + r, prm[X_MAX]), min(p_a[1] + r, prm[Y_MAX])
    return np.array([x_min, y_min, max(x_max, x_min), max(y_max, y_min)])


@kernel
def voronoi_velocity(p_a: np.ndarray, p_d: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """The ``voronoi`` attacker's velocity (the module's docstring)."""
    sensed = near(p_a, p_d, prm[SENSING])
    if sensed.shape[0] == 0:
        return calm(p_a, centres, radii, prm)
    vertices, _ = cell_of(p_a, sensed, centres, radii, sensed_box(p_a, prm))
    if vertices.shape[0] == 0:
        return 0.0, 0.0
    cx, cy = centroid(vertices)
    wx, wy = capped((cx - p_a[0]) / prm[T], (cy - p_a[1]) / prm[T], prm[V_A])
    return wished(p_a, wx, wy, centres, radii, prm)


class VoronoiAttacker(CompiledBehaviour):
    """Towards its Voronoi cell's centroid (the module's docstring)."""

    rule = staticmethod(voronoi_velocity)

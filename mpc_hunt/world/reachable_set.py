"""The attacker's dominance region: the points it can reach before any defender, ray by ray.

What the defenders know of an attacker whose law they are not given is its top
speed v_a. Along a straight ray p_a + s·u, the attacker is at distance s after
s / v_a; defender i, at its top speed v_i in a straight line, comes within
``reach`` of that point after (|p_a + s·u − p_i| − reach) / v_i. The attacker
gets there first while s < s_i(u), the positive root of

    |p_a + s·u − p_i| = reach + s / κ_i,       κ_i = v_a / v_i < 1,

which for κ_i < 1 always exists: the ray's crossing of defender i's Apollonius
circle (grown by ``reach``). The region the attacker dominates is the star
{p_a + s·u : s < min_i s_i(u)} (Pierson et al., "Intercepting rogue robots",
RA-L 2017; Apollonius circles for a slower evader). An obstacle blocks the ray
at its surface: the attacker cannot pass through, so the obstacle closes that
direction as a stationary defender does (the paper's obstacles as members of
the hunting circle). The arena's edge is the way out: a ray whose dominated
part reaches the edge before any obstacle is an *escape* direction, along which
an attacker that runs now leaves whatever the defenders do.

Everything here is straight-line and worst-case for the defenders' timing
(obstacles only lengthen their ways); the rules are compiled (:mod:`mpc_hunt.compiled`) loops over rays and
defenders.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mpc_hunt.compiled import kernel

RAYS = 72  # directions round the attacker (5° apart)


def ray_directions(count: int = RAYS) -> np.ndarray:
    """``count`` unit vectors evenly round the turn, shape (count, 2)."""
    angles = 2 * np.pi * np.arange(count) / count
    return np.column_stack([np.cos(angles), np.sin(angles)])


@kernel
def defender_reach(p_a, rays, defenders, ratios, reach):
    """s_i(u) of the module's docstring, shape (rays, defenders): how far along each ray the attacker gets
    before defender i can be within ``reach`` of it; ``ratios`` are κ_i = v_a / v_i, each in (0, 1)."""
    m, n = rays.shape[0], defenders.shape[0]
    out = np.empty((m, n))
    for i in range(n):
        dx, dy = p_a[0] - defenders[i, 0], p_a[1] - defenders[i, 1]
        c = 1.0 / (ratios[i] * ratios[i]) - 1.0
        for k in range(m):
            b = reach / ratios[i] - (rays[k, 0] * dx + rays[k, 1] * dy)
            disc = b * b - c * (reach * reach - (dx * dx + dy * dy))
            out[k, i] = max((math.sqrt(max(disc, 0.0)) - b) / c, 0.0)
    return out


@kernel
def obstacle_block(p_a, rays, centres, radii):
    """How far along each ray the attacker goes before it meets an obstacle's surface (inf where none), (m,)."""
    out = np.full(rays.shape[0], np.inf)
    for j in range(radii.shape[0]):
        fx, fy = p_a[0] - centres[j, 0], p_a[1] - centres[j, 1]
        for k in range(rays.shape[0]):
            fu = rays[k, 0] * fx + rays[k, 1] * fy
            disc = fu * fu - ((fx * fx + fy * fy) - radii[j] * radii[j])
            entry = -fu - math.sqrt(max(disc, 0.0))
            if disc >= 0 and entry >= 0:
                out[k] = min(out[k], entry)
    return out


@kernel
def edge_along(p_a, rays, x_min, y_min, x_max, y_max):
    """How far along each ray the edge of the arena (x_min, y_min, x_max, y_max) is, (m,): inf along a ray that
    meets none (an edge at infinity, as an arena that is not there)."""
    out = np.empty(rays.shape[0])
    for k in range(rays.shape[0]):
        ux, uy = rays[k, 0], rays[k, 1]
        tx = (x_max - p_a[0]) / ux if ux > 0 else ((x_min - p_a[0]) / ux if ux < 0 else np.inf)
        ty = (y_max - p_a[1]) / uy if uy > 0 else ((y_min - p_a[1]) / uy if uy < 0 else np.inf)
        out[k] = max(min(tx, ty), 0.0)
    return out


def edge_distance(p_a: np.ndarray, rays: np.ndarray, arena: tuple[float, float, float, float] | None) -> np.ndarray:
    """How far along each ray the arena's edge is (inf without an arena), (m,)."""
    x_min, y_min, x_max, y_max = (-np.inf, -np.inf, np.inf, np.inf) if arena is None else arena
    return edge_along(np.asarray(p_a, dtype=float), rays, float(x_min), float(y_min), float(x_max), float(y_max))


@dataclass(frozen=True)
class Dominance:
    """The attacker's dominance region along ``rays``: ``defended`` (min_i s_i), ``blocked`` (the nearest
    obstacle's surface), ``edge`` (the arena's edge), each (m,)."""

    rays: np.ndarray
    defended: np.ndarray
    blocked: np.ndarray
    edge: np.ndarray

    @property
    def extent(self) -> np.ndarray:
        """How far along each ray the attacker gets first: the defenders', an obstacle's or the edge's limit."""
        return np.minimum(self.defended, np.minimum(self.blocked, self.edge))

    @property
    def escapes(self) -> np.ndarray:
        """The rays along which the attacker reaches the arena's edge before every defender and obstacle."""
        return (self.defended > self.edge) & (self.blocked > self.edge)

    def area(self) -> float:
        """The region's area (the star's, ray by ray: ½ Σ s² Δθ)."""
        return float(0.5 * np.sum(self.extent**2) * 2 * np.pi / len(self.rays))


def dominance(
    p_a: np.ndarray,
    defenders: np.ndarray,
    defender_speeds: np.ndarray,
    attacker_speed: float,
    centres: np.ndarray,
    radii: np.ndarray,
    arena,
    *,
    reach: float = 0.0,
    rays: np.ndarray | None = None,
) -> Dominance:
    """The attacker's :class:`Dominance` (the module's docstring) against ``defenders``."""
    p_a = np.asarray(p_a, dtype=float)
    rays = ray_directions() if rays is None else rays
    defenders = np.asarray(defenders, dtype=float).reshape(-1, 2)
    if len(defenders):
        ratios = attacker_speed / np.asarray(defender_speeds, dtype=float)
        defended = np.min(defender_reach(p_a, rays, defenders, ratios, float(reach)), axis=1)
    else:
        defended = np.full(len(rays), np.inf)
    centres, radii = np.asarray(centres, dtype=float).reshape(-1, 2), np.asarray(radii, dtype=float).reshape(-1)
    return Dominance(rays, defended, obstacle_block(p_a, rays, centres, radii), edge_distance(p_a, rays, arena))

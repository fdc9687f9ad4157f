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
(obstacles only lengthen their ways), and vectorised over rays and defenders.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

RAYS = 72  # directions round the attacker (5° apart)


def ray_directions(count: int = RAYS) -> np.ndarray:
    """``count`` unit vectors evenly round the turn, shape (count, 2)."""
    angles = 2 * np.pi * np.arange(count) / count
    return np.column_stack([np.cos(angles), np.sin(angles)])


def defender_reach(
    p_a: np.ndarray, rays: np.ndarray, defenders: np.ndarray, ratios: np.ndarray, reach: float
) -> np.ndarray:
    """s_i(u) of the module's docstring, shape (rays, defenders): how far along each ray the attacker gets
    before defender i can be within ``reach`` of it; ``ratios`` are κ_i = v_a / v_i, each in (0, 1)."""
    d = p_a - defenders  # (n, 2)
    du = rays @ d.T  # (m, n): d·u
    c = 1.0 / ratios**2 - 1.0  # (n,)
    b = reach / ratios - du
    disc = b**2 - c * (reach**2 - np.sum(d**2, axis=1))
    return np.maximum((np.sqrt(np.maximum(disc, 0.0)) - b) / c, 0.0)


def obstacle_block(p_a: np.ndarray, rays: np.ndarray, centres: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """How far along each ray the attacker goes before it meets an obstacle's surface (inf where none), (m,)."""
    if not len(radii):
        return np.full(len(rays), np.inf)
    f = p_a - centres  # (q, 2)
    fu = rays @ f.T  # (m, q)
    disc = fu**2 - (np.sum(f**2, axis=1) - radii**2)
    entry = -fu - np.sqrt(np.maximum(disc, 0.0))
    hit = (disc >= 0) & (entry >= 0)
    return np.min(np.where(hit, entry, np.inf), axis=1)


def edge_distance(p_a: np.ndarray, rays: np.ndarray, arena: tuple[float, float, float, float] | None) -> np.ndarray:
    """How far along each ray the arena's edge is (inf without an arena), (m,)."""
    if arena is None:
        return np.full(len(rays), np.inf)
    x_min, y_min, x_max, y_max = arena
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = np.where(
            rays[:, 0] > 0,
            (x_max - p_a[0]) / rays[:, 0],
            np.where(rays[:, 0] < 0, (x_min - p_a[0]) / rays[:, 0], np.inf),
        )
        ty = np.where(
            rays[:, 1] > 0,
            (y_max - p_a[1]) / rays[:, 1],
            np.where(rays[:, 1] < 0, (y_min - p_a[1]) / rays[:, 1], np.inf),
        )
    return np.maximum(np.minimum(tx, ty), 0.0)


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
        defended = np.min(
            defender_reach(p_a, rays, defenders, attacker_speed / np.asarray(defender_speeds), reach), axis=1
        )
    else:
        defended = np.full(len(rays), np.inf)
    return Dominance(
        rays,
        defended,
        obstacle_block(p_a, rays, np.asarray(centres, dtype=float).reshape(-1, 2), np.asarray(radii, dtype=float)),
        edge_distance(p_a, rays, arena),
    )

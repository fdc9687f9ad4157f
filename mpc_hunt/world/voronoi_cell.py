"""The attacker's bounded Voronoi cell: the points it reaches before any defender, clipped to a box and obstacles.

The cell is the box (the arena, or a box round the robots when there is none)
cut by one half-plane per site: for a defender at q, the attacker's side of
their perpendicular bisector, {x : (q − p_a)·x ≤ (q − p_a)·(p_a + q)/2}; for an
obstacle, the attacker's side of the tangent at the surface point nearest the
attacker, which it cannot pass straight through (the obstacle as a cell
boundary, as in the obstacle-aware evader-centred bounded Voronoi cell of Wang
et al., arXiv 2312.01326). Each half-plane clips the polygon in turn
(Sutherland–Hodgman), and every edge keeps the label of the site that made it,
so the edge a defender shares with the attacker's cell is read off the result.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mpc_hunt.world.geometry import dot2, norm, unit


@dataclass(frozen=True)
class Cell:
    """A convex polygon, counter-clockwise; ``labels[k]`` names the site of the edge from vertex k to k + 1.

    Labels: a defender's index (≥ 0), ``-1 - j`` for obstacle j, ``None`` for the box.
    """

    vertices: np.ndarray
    labels: tuple

    def shared_edge(self, label: int) -> tuple[np.ndarray, np.ndarray] | None:
        """The edge the site ``label`` shares with the cell (it is convex: at most one), or None."""
        m = len(self.vertices)
        for k, own in enumerate(self.labels):
            a, b = self.vertices[k], self.vertices[(k + 1) % m]
            if own == label and norm(b - a) > 0:
                return a, b
        return None


def box_cell(box: tuple[float, float, float, float]) -> Cell:
    """The box (x_min, y_min, x_max, y_max) as a cell with unlabelled edges."""
    x_min, y_min, x_max, y_max = box
    vertices = np.array([[x_min, y_min], [x_max, y_min], [x_max, y_max], [x_min, y_max]], dtype=float)
    return Cell(vertices, (None,) * 4)


def clip(cell: Cell, normal: np.ndarray, offset: float, label: int) -> Cell:
    """``cell`` ∩ {x : normal·x ≤ offset}; the new edge along the line is labelled ``label``."""
    vertices, labels = [], []
    m = len(cell.vertices)
    for k in range(m):
        p, q, own = cell.vertices[k], cell.vertices[(k + 1) % m], cell.labels[k]
        sp, sq = dot2(normal, p) - offset, dot2(normal, q) - offset
        if sp <= 0:
            vertices.append(p)
            labels.append(own)
        if (sp <= 0) != (sq <= 0):
            crossing = p + (sp / (sp - sq)) * (q - p)
            vertices.append(crossing)
            labels.append(label if sp <= 0 else own)
    return Cell(np.array(vertices, dtype=float).reshape(-1, 2), tuple(labels))


def attacker_cell(
    p_a: np.ndarray,
    defenders: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    box: tuple[float, float, float, float],
) -> Cell:
    """The attacker's cell w.r.t. every defender and obstacle, within ``box`` (see the module's docstring)."""
    p_a = np.asarray(p_a, dtype=float)
    cell = box_cell(box)
    for i, q in enumerate(np.asarray(defenders, dtype=float).reshape(-1, 2)):
        n = q - p_a
        if norm(n) > 0:
            cell = clip(cell, n, dot2(n, 0.5 * (p_a + q)), i)
    for j, (c, r) in enumerate(zip(np.asarray(centres, dtype=float).reshape(-1, 2), radii)):
        n = unit(c - p_a)
        cell = clip(cell, n, dot2(n, c - r * n), -1 - j)
    return cell

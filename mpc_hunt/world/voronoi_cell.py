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

from mpc_hunt.compiled import kernel
from mpc_hunt.world.geometry import length

BOX = -(2**30)  # the label of a box edge in the compiled cell (``None`` in a :class:`Cell`)


@dataclass(frozen=True)
class Cell:
    """A convex polygon, counter-clockwise; ``labels[k]`` names the site of the edge from vertex k to k + 1.

    Labels: a defender's index (≥ 0), ``-1 - j`` for obstacle j, ``None`` for the box.
    """

    vertices: np.ndarray
    labels: tuple

    def shared_edge(self, label: int) -> tuple[np.ndarray, np.ndarray] | None:
        """The edge the site ``label`` shares with the cell (it is convex: at most one), or None."""
        found, a, b = shared_edge(self.vertices, np.array([BOX if x is None else x for x in self.labels]), label)
        return (a, b) if found else None


@kernel
def shared_edge(vertices: np.ndarray, labels: np.ndarray, label: int) -> tuple[bool, np.ndarray, np.ndarray]:
    """(found, a, b): the edge from a to b the site ``label`` shares with the cell (at most one: it is convex)."""
    m = vertices.shape[0]
    for k in range(m):
        a, b = vertices[k], vertices[(k + 1) % m]
        if labels[k] == label and length(b[0] - a[0], b[1] - a[1]) > 0:
            return True, a.copy(), b.copy()
    return False, np.zeros(2), np.zeros(2)


@kernel
def clip(
    vertices: np.ndarray, labels: np.ndarray, nx: float, ny: float, offset: float, label: int
) -> tuple[np.ndarray, np.ndarray]:
    """The polygon ∩ {x : (nx, ny)·x ≤ offset} (Sutherland–Hodgman); the new edge along the line is labelled
    ``label``."""
    m = vertices.shape[0]
    out = np.empty((m + 1, 2))
    out_labels = np.empty(m + 1, dtype=np.int64)
    count = 0
    for k in range(m):
        p, q, own = vertices[k], vertices[(k + 1) % m], labels[k]
        sp, sq = nx * p[0] + ny * p[1] - offset, nx * q[0] + ny * q[1] - offset
        if sp <= 0:
            out[count] = p
            out_labels[count] = own
            count += 1
        if (sp <= 0) != (sq <= 0):
            t = sp / (sp - sq)
            out[count, 0] = p[0] + t * (q[0] - p[0])
            out[count, 1] = p[1] + t * (q[1] - p[1])
            out_labels[count] = label if sp <= 0 else own
            count += 1
    return out[:count], out_labels[:count]


@kernel
def cell_of(
    p_a: np.ndarray, defenders: np.ndarray, centres: np.ndarray, radii: np.ndarray, box: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, labels) of the attacker's cell w.r.t. every defender and obstacle, within ``box``
    (x_min, y_min, x_max, y_max): the module's docstring; box edges are labelled :data:`BOX`."""
    x_min, y_min, x_max, y_max = box[0], box[1], box[2], box[3]
    vertices = np.array([[x_min, y_min], [x_max, y_min], [x_max, y_max], [x_min, y_max]])
    labels = np.full(4, BOX, dtype=np.int64)
    for i in range(defenders.shape[0]):
        nx, ny = defenders[i, 0] - p_a[0], defenders[i, 1] - p_a[1]
        if length(nx, ny) > 0:
            mx, my = 0.5 * (p_a[0] + defenders[i, 0]), 0.5 * (p_a[1] + defenders[i, 1])
            vertices, labels = clip(vertices, labels, nx, ny, nx * mx + ny * my, i)
    for j in range(radii.shape[0]):
        nx, ny = centres[j, 0] - p_a[0], centres[j, 1] - p_a[1]
        scale = length(nx, ny)
        scale = scale if scale > 0 else 1.0
        nx, ny = nx / scale, ny / scale
        tx, ty = centres[j, 0] - radii[j] * nx, centres[j, 1] - radii[j] * ny
        vertices, labels = clip(vertices, labels, nx, ny, nx * tx + ny * ty, -1 - j)
    return vertices, labels


def attacker_cell(
    p_a: np.ndarray,
    defenders: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    box: tuple[float, float, float, float],
) -> Cell:
    """The attacker's cell w.r.t. every defender and obstacle, within ``box`` (see the module's docstring)."""
    vertices, labels = cell_of(
        np.asarray(p_a, dtype=float),
        np.asarray(defenders, dtype=float).reshape(-1, 2),
        np.asarray(centres, dtype=float).reshape(-1, 2),
        np.asarray(radii, dtype=float).reshape(-1),
        np.array(box, dtype=float),
    )
    return Cell(vertices, tuple(None if x == BOX else int(x) for x in labels))

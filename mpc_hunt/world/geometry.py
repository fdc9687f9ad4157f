"""Small vector helpers shared by the model, the strategy and the metrics."""

from __future__ import annotations

import math

import numpy as np

from mpc_hunt.compiled import kernel


def norm(v: np.ndarray) -> np.ndarray:
    """Euclidean norm over the last axis."""
    return np.sqrt(np.sum(np.asarray(v, dtype=float) ** 2, axis=-1))


def saturate(v: np.ndarray, max_norm: float | np.ndarray) -> np.ndarray:
    """Scale ``v`` (last axis) down so that its norm is at most ``max_norm``.

    A finite vector whose squared norm overflows (a component beyond about 1e154) is scaled by its largest
    component before it is measured, so it saturates to ``max_norm`` in its direction rather than to zero; every
    other vector is scaled as before, to the bit."""
    v = np.asarray(v, dtype=float)
    if v.shape == (2,) and np.ndim(max_norm) == 0:  # one vector: the compiled rule's own
        return np.array(capped(float(v[0]), float(v[1]), float(max_norm)))
    with np.errstate(over="ignore"):
        n = norm(v)
    scale = np.where(n > max_norm, np.asarray(max_norm) / np.where(n > 0, n, 1.0), 1.0)
    out = v * np.expand_dims(scale, -1)
    huge = np.isinf(n) & np.all(np.isfinite(v), axis=-1)
    if np.any(huge):
        largest = np.max(np.abs(v), axis=-1, keepdims=True)
        scaled = unit(v / np.where(largest > 0, largest, 1.0)) * np.expand_dims(np.asarray(max_norm, dtype=float), -1)
        out = np.where(np.expand_dims(huge, -1), scaled, out)
    return out


def direction(angle) -> np.ndarray:
    """The unit vector (cos θ, sin θ) of ``angle``; for an array of angles, one per row."""
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def unit(v: np.ndarray) -> np.ndarray:
    """``v`` divided by its norm over the last axis; a zero vector has no direction and stays zero."""
    v = np.asarray(v, dtype=float)
    n = norm(v)
    return v / np.expand_dims(np.where(n > 0, n, 1.0), -1)


@kernel
def length(x: float, y: float) -> float:
    """|(x, y)|, as :func:`norm` computes it (the same bits)."""
    return math.sqrt(x * x + y * y)


@kernel
def capped(x: float, y: float, max_norm: float) -> tuple[float, float]:
    """The 2-vector (x, y) scaled down to norm ``max_norm`` if longer: :func:`saturate` of one vector."""
    n = math.sqrt(x * x + y * y)
    if not math.isfinite(n) and math.isfinite(x) and math.isfinite(y):  # the squares overflow: measure it scaled
        largest = max(abs(x), abs(y))
        x, y = x / largest, y / largest
        n = math.sqrt(x * x + y * y)
        return x / n * max_norm, y / n * max_norm
    scale = max_norm / n if n > max_norm else 1.0
    return x * scale, y * scale


@kernel
def encloses(point: np.ndarray, anchors: np.ndarray) -> bool:
    """True when ``point`` lies strictly inside the convex hull of ``anchors`` (k, 2).

    Equivalent test: the directions from the point to the anchors leave no
    angular gap of half a turn or more (no half-plane through the point holds
    every anchor), so the point cannot leave without passing between them.
    """
    k = anchors.shape[0]
    if k < 3:
        return False
    angles = np.empty(k)
    for i in range(k):
        dx, dy = anchors[i, 0] - point[0], anchors[i, 1] - point[1]
        if math.sqrt(dx * dx + dy * dy) == 0:
            return False
        angles[i] = math.atan2(dy, dx)
    angles.sort()
    widest = angles[0] + 2 * math.pi - angles[k - 1]
    for i in range(k - 1):
        widest = max(widest, angles[i + 1] - angles[i])
    return widest < math.pi


@kernel
def run_towards(qx: float, qy: float, tx: float, ty: float, reach: float) -> tuple[float, float]:
    """(qx, qy) moved straight towards (tx, ty) by at most ``reach``."""
    wx, wy = tx - qx, ty - qy
    way = math.hypot(wx, wy)
    scale = min(1.0, reach / way) if way > 0 else 0.0
    return qx + wx * scale, qy + wy * scale

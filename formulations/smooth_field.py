"""The optimiser's field: H of Eq. 2 with its kink at |r| = R rounded off (docs/model.md, E11).

H(r) = η (R³/d³ − 1) r = η (R − d)₊ (R² + R d + d²)/d² · r/d for d = |r|: the
only non-smooth part is the ramp (R − d)₊, which is zero outside R and has
slope −1 inside. :func:`ramp` replaces it, on |R − d| < w only, by the quartic
that meets both sides with equal value, slope and curvature (C²), so Newton
steps see a continuous Hessian. Outside that band the field is the paper's
exactly; inside it differs by at most 3w/16 · η (R² + R d + d²)/d². The
simulated world and the evaluator keep the paper's field.
"""

from __future__ import annotations

import casadi as ca

from mpc_hunt.world.field import FIELD_FLOOR

_TINY = 1e-18


def ramp(z, w):
    """C² approximation of max(z, 0): (z + w)³ (3w − z) / (16 w³) on |z| < w, exact outside; w = 0 is exact."""
    width = ca.fmax(w, 1e-12)
    blend = (z + width) ** 3 * (3 * width - z) / (16 * width ** 3)
    return ca.if_else(z >= width, z, ca.if_else(z <= -width, 0, blend))


def norm(v):
    return ca.sqrt(ca.dot(v, v) + _TINY)


def repulsion(r, radius, eta, w):
    """The smoothed H(r) of Eq. 2 (repulsive sign, E1), range ``radius``, band half-width ``w``."""
    length = norm(r)
    d = ca.fmax(length, FIELD_FLOOR)
    return eta * ramp(radius - d, w) * (radius**2 + radius * d + d**2) / d**2 * r / length


def obstacle_repulsion(p, centre, radius, reach, eta, w):
    """The smoothed H of one obstacle, measured from its surface (E2)."""
    v = p - centre
    dc = norm(v)
    s = ca.fmax(dc - radius, FIELD_FLOOR)
    return eta * ramp(reach - s, w) * (reach**2 + reach * s + s**2) / s**2 * v / dc

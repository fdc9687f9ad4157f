"""The attacker's field H of Eqs. 2 and 3 in CasADi: the paper's, or rounded at its kink (docs/model.md, E11).

H(r) = η (R³/d³ − 1) r = η (R − d)₊ (R² + R d + d²)/d² · r/d for d = |r|
(repulsive, docs/model.md E1); an obstacle's H is measured from its surface
(E2). The only non-smooth part is the ramp (R − d)₊, which is zero outside R
and has slope −1 inside. Without a width (``w=None``) :func:`ramp` is that
ramp and the field is the paper's, as the condensed formulations (``nlp``,
``qp``, ``sqp``, ``socp``) pose it. With a half-width w it is replaced, on
|R − d| < w only, by the quartic that meets both sides with equal value, slope
and curvature (C²), so Newton steps see a continuous Hessian (the stage model,
hence ``rti``, ``stage-sqp``, ``ms-nlp``). Outside that band the field is the
paper's; inside it differs by at most 3w/16 · η (R² + R d + d²)/d². The
simulated world (:mod:`mpc_hunt.world.field`) and the evaluator keep the
paper's field, in NumPy.
"""

from __future__ import annotations

import casadi as ca

from mpc_hunt.world.field import FIELD_FLOOR

_TINY = 1e-18


def ramp(z, w=None):
    """max(z, 0); for a half-width w its C² approximation (z + w)³ (3w − z) / (16 w³) on |z| < w, exact outside."""
    if w is None:
        return ca.fmax(z, 0)
    width = ca.fmax(w, 1e-12)
    blend = (z + width) ** 3 * (3 * width - z) / (16 * width ** 3)
    return ca.if_else(z >= width, z, ca.if_else(z <= -width, 0, blend))


def norm(v):
    return ca.sqrt(ca.dot(v, v) + _TINY)


def _push(distance, direction, reach, eta, w):
    """η ρ(R − d) (R² + R d + d²)/d² along ``direction`` (a unit vector's numerator, divided last)."""
    return eta * ramp(reach - distance, w) * (reach**2 + reach * distance + distance**2) / distance**2 * direction


def repulsion(r, radius, eta, w=None):
    """H(r) of Eq. 2, range ``radius``; rounded on a band of half-width ``w`` if given."""
    length = norm(r)
    return _push(ca.fmax(length, FIELD_FLOOR), r, radius, eta, w) / length


def obstacle_repulsion(p, centre, radius, reach, eta, w=None):
    """H of one obstacle, measured from its surface (Eq. 3), range ``reach``; rounded if ``w`` is given."""
    v = p - centre
    dc = norm(v)
    return _push(ca.fmax(dc - radius, FIELD_FLOOR), v, reach, eta, w) / dc


def saturate(v, max_norm):
    """``v`` scaled down to norm ``max_norm`` at most (the attacker's speed limit)."""
    return v * ca.fmin(1, max_norm / norm(v))

"""The attacker's field H of Eqs. 2 and 3 in CasADi: the paper's, or rounded at its kink (docs/model.md, E11).

At the distance d from its source (d = |r|; an obstacle's is measured from
its surface, docs/model.md E2) the repulsive H (E1) has the magnitude

    |H| = η (R³/d² − d) = η (R − d)₊ (R² + R d + d²)/d²,

zero beyond R. Its only non-smooth part is the ramp (R − d)₊, zero outside R
with slope −1 inside. Without a width (``w=None``) the field is the paper's,
as the condensed formulations (``nlp``, ``qp``, ``sqp``, ``socp``) pose it.
With a half-width w, :func:`ramp` replaces (R − d)₊ on |R − d| < w only by the
quartic that meets both sides with equal value, slope and curvature (C²), so
Newton steps see a continuous Hessian (the stage model, hence ``rti``,
``stage-sqp``, ``ms-nlp``). Outside that band the field is the paper's; inside
it differs by at most 3w/16 · η (R² + R d + d²)/d². The simulated world
(:mod:`mpc_hunt.world.field`) and the evaluator keep the paper's field, in
NumPy; the paper's H between robots is the world's expression
(:func:`~mpc_hunt.world.field.repulsion_gain`), to the last bit.
"""

from __future__ import annotations

import casadi as ca

from mpc_hunt.world.field import FIELD_FLOOR, repulsion_gain

_TINY = 1e-18


def ramp(z, w):
    """C² approximation of max(z, 0): (z + w)³ (3w − z) / (16 w³) on |z| < w, exact outside; w = 0 is exact."""
    width = ca.fmax(w, 1e-12)
    blend = (z + width) ** 3 * (3 * width - z) / (16 * width**3)
    return ca.if_else(z >= width, z, ca.if_else(z <= -width, 0, blend))


def norm(v):
    return ca.sqrt(ca.dot(v, v) + _TINY)


def unit(v):
    """``v`` / |v|, regularised: a zero vector stays zero (as :func:`mpc_hunt.world.geometry.unit`)."""
    return v / norm(v)


def _magnitude(d, reach, eta, w):
    """|H| at the distance ``d`` from the source, range ``reach``: η (R³/d² − d) within it, or with
    ``w`` given η ρ_w(R − d) (R² + R d + d²)/d², its ramp (R − d)₊ rounded."""
    if w is None:
        return ca.if_else(d < reach, eta * (reach**3 / d**2 - d), 0)
    return eta * ramp(reach - d, w) * (reach**2 + reach * d + d**2) / d**2


def repulsion(r, radius, eta, w=None):
    """H(r) of Eq. 2, range ``radius``; rounded on a band of half-width ``w`` if given."""
    length = norm(r)
    d = ca.fmax(length, FIELD_FLOOR)
    if w is None:
        return repulsion_gain(d, length, radius, eta, ca.if_else) * r
    return _magnitude(d, radius, eta, w) * r / length


def obstacle_repulsion(p, centre, radius, reach, eta, w=None):
    """H of one obstacle, measured from its surface (Eq. 3), range ``reach``; rounded if ``w`` is given."""
    v = p - centre
    dc = norm(v)
    return _magnitude(ca.fmax(dc - radius, FIELD_FLOOR), reach, eta, w) * v / dc


def saturate(v, max_norm):
    """``v`` scaled down to norm ``max_norm`` at most (the attacker's speed limit)."""
    return v * ca.fmin(1, max_norm / norm(v))

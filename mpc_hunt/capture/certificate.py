"""Certificates of a solve, computed by us from the problem's own data and the solver's returned vectors.

A solver's status says what the solver believes; a certificate says how well the point it returned solves the
problem it was handed, as qpbenchmark computes it rather than trusting each solver's report. For the QP
min ½xᵀPx + qᵀx s.t. l ≤ Ax ≤ u with multipliers y (y > 0 on a row at its upper bound, y < 0 at its lower):

* primal residual: the largest amount by which Ax leaves [l, u] (for a second-order cone's rows t ≥ |v|, by
  which |v| exceeds t), in the rows' units;
* dual residual: |Px + q + Aᵀy|_∞, stationarity of the Lagrangian;
* duality gap: |xᵀPx + qᵀx + Σ u_i y_i⁺ − Σ l_i y_i⁻| over the finite bounds, the primal objective minus the
  dual's (cone rows: u_i y_i).

They certify the solve of the problem the solver was handed: for a linearised formulation that is the QP at the
linearisation point, not the capture problem itself, whose true violations the evaluator reports apart
(:mod:`mpc_hunt.capture.evaluator`). So "the solver was inaccurate" (large residuals) and "the linearisation was
wrong" (small residuals, true violations) are two different columns. For IPOPT the same three names hold its
final primal infeasibility (of g's bounds and x's, computed here), its own dual infeasibility and the
complementarity of the returned multipliers (``kind = "nlp"``).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
import scipy.sparse as sp


@dataclass(frozen=True)
class Certificate:
    """Primal residual, dual residual and duality gap of a returned point (the module's docstring); ``kind`` is
    ``qp`` (the QP's data) or ``nlp`` (IPOPT's measures)."""

    primal_residual: float
    dual_residual: float
    duality_gap: float
    kind: str = "qp"

    def to_dict(self) -> dict:
        """Plain JSON-ready data; an infinite residual or gap (a multiplier on an infinite bound) is written as the
        string "inf", which JSON has no number for."""
        return {k: (v if not isinstance(v, float) or math.isfinite(v) else str(v)) for k, v in asdict(self).items()}

    def within(self, tolerance: float) -> bool:
        """Whether every residual and the gap are at most ``tolerance``."""
        return max(self.primal_residual, self.dual_residual, self.duality_gap) <= tolerance


def _bound_terms(bound: np.ndarray, multiplier: np.ndarray) -> np.ndarray:
    """bound_i · multiplier_i on the finite bounds (0 on an infinite one: a multiplier there, which should be 0, is
    the dual residual's to report, not a gap of infinity)."""
    out = np.zeros_like(multiplier)
    finite = np.isfinite(bound) & (multiplier != 0)
    out[finite] = bound[finite] * multiplier[finite]
    return out


def qp_certificate(
    P: sp.csc_matrix,
    q: np.ndarray,
    A: sp.csc_matrix,
    l: np.ndarray,
    u: np.ndarray,
    x: np.ndarray,
    y: np.ndarray,
    cones: tuple[tuple[int, int], ...] = (),
    upper: bool = True,
) -> Certificate:
    """The certificate of ``(x, y)`` for min ½xᵀPx + qᵀx s.t. l ≤ Ax ≤ u (rows in ``cones``: (start, size) of
    second-order cones t ≥ |v| written u − Ax), ``P`` given as its upper triangle when ``upper``."""
    P = P if isinstance(P, sp.csc_matrix) else sp.csc_matrix(P)
    Px = P @ x + (P.T @ x - P.diagonal() * x if upper else 0.0)
    Ax = A @ x
    cone = np.zeros(len(Ax), dtype=bool)
    worst = 0.0
    for start, size in cones:
        cone[start : start + size] = True
        s = u[start : start + size] - Ax[start : start + size]
        worst = max(worst, float(np.linalg.norm(s[1:]) - s[0]))
    linear = ~cone
    with np.errstate(invalid="ignore"):
        over = np.concatenate([(Ax - u)[linear], (l - Ax)[linear], [0.0]])
    worst = max(worst, float(np.max(np.nan_to_num(over, nan=0.0, neginf=0.0))))
    dual = float(np.max(np.abs(Px + q + A.T @ y), initial=0.0))
    y_lin = np.where(linear, y, 0.0)
    bounds = (
        _bound_terms(u, np.maximum(y_lin, 0.0))
        - _bound_terms(l, np.maximum(-y_lin, 0.0))
        + _bound_terms(u, np.where(cone, y, 0.0))
    )
    gap = float(x @ Px + q @ x) + float(np.sum(bounds))
    return Certificate(max(worst, 0.0), dual, abs(gap))


def complementarity(value: np.ndarray, lower: np.ndarray, upper: np.ndarray, multiplier: np.ndarray) -> float:
    """max_i |multiplier_i| × the distance of ``value_i`` to the bound it is for (upper when > 0, lower when < 0)."""
    m = np.asarray(multiplier, dtype=float)
    with np.errstate(invalid="ignore"):
        slack = np.where(m > 0, upper - value, np.where(m < 0, value - lower, 0.0))
    terms = np.abs(m) * np.abs(np.nan_to_num(slack, nan=0.0, posinf=0.0, neginf=0.0))
    return float(np.max(terms, initial=0.0))


def bound_violation(value: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> float:
    """The largest amount by which ``value`` leaves [lower, upper]."""
    over = np.concatenate([np.asarray(value - upper, dtype=float), np.asarray(lower - value, dtype=float), [0.0]])
    return float(np.max(np.nan_to_num(over, nan=0.0, neginf=0.0)))

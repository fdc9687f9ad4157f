"""A solver benchmark's metrics on plain numbers: shifted geometric mean, success, gap, performance profile.

The definitions follow qpbenchmark (success: a success status *and* residuals
within tolerance; the shifted geometric mean of times) and Dolan & Moré,
"Benchmarking optimization software with performance profiles" (2002).
"""

from __future__ import annotations

import math

import numpy as np

from mpc_hunt.capture.evaluator import hard_violation
from mpc_hunt.errors import BenchmarkError

TIME_SHIFT = 0.01  # s: qpbenchmark's 10 ms


def shifted_geometric_mean(values, shift: float = TIME_SHIFT) -> float:
    """exp(mean(log(v + shift))) − shift: neither large nor tiny outliers dominate it."""
    v = np.asarray(values, dtype=float)
    if v.size == 0:
        raise BenchmarkError("values: empty, nothing to average")
    if np.any(v < 0) or not np.all(np.isfinite(v)):
        raise BenchmarkError(f"values: must be finite and non-negative, got {v[(v < 0) | ~np.isfinite(v)][:3]}")
    if not shift > 0:
        raise BenchmarkError(f"shift: must be positive, got {shift}")
    return float(np.exp(np.mean(np.log(v + shift))) - shift)


def is_success(usable: bool, violation: dict[str, float] | None, tolerance: float) -> bool:
    """A success status and every hard constraint's true violation within ``tolerance``: the rule by which a loop
    applies a plan (:class:`mpc_hunt.solving.mpc.CaptureMPC`); Eq. 14, elastic in every formulation, is reported
    beside it, not in it."""
    return bool(usable and violation is not None and hard_violation(violation) <= tolerance)


def relative_gap(objective: float, best: float) -> float:
    """(J − J*) / |J*|: how far above the best known objective; 0 (or inf) when J* = 0."""
    if best == 0:
        return 0.0 if objective == 0 else math.inf
    return (objective - best) / abs(best)


def performance_profile(times: dict[str, np.ndarray]) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Dolan–Moré profile: for each solver s, ρ_s(τ) = share of problems with t_ps ≤ τ · min_s' t_ps'.

    ``times`` maps each solver to its times on the same problems, in the same
    order, ``inf`` where it failed. Returns the ratios τ at which some profile
    steps (from 1) and each solver's ρ_s at those τ.
    """
    if not times:
        raise BenchmarkError("times: no solver given")
    matrix = np.array([np.asarray(t, dtype=float) for t in times.values()])
    if matrix.ndim != 2 or matrix.shape[1] == 0:
        raise BenchmarkError("times: every solver needs a time for each of the same, non-empty, problems")
    if np.any(np.isnan(matrix)) or np.any(matrix < 0):
        raise BenchmarkError("times: must be non-negative (inf for a failure), not NaN")
    best = matrix.min(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratios = np.where(np.isfinite(matrix), matrix / np.where(best > 0, best, 1.0), np.inf)
    ratios = np.where((best == 0) & np.isfinite(matrix), np.where(matrix == 0, 1.0, np.inf), ratios)
    taus = np.unique(np.concatenate([[1.0], ratios[np.isfinite(ratios)]]))
    profile = {s: np.array([(row <= tau).mean() for tau in taus]) for s, row in zip(times, ratios)}
    return taus, profile

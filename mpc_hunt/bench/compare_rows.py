"""Score a compare run: one row per (formulation, backend, mode, horizon), as ``mpc-hunt compare`` reports it.

``success_rate``: the share of solves with a success status and every hard
constraint's true violation within the accuracy's tolerance
(:func:`mpc_hunt.bench.metrics.is_success`, the loop's rule).
Times, in seconds, over every solve (a failed solve is waited for too):
``solve_time_*`` all-in (median, 95th percentile, shifted geometric mean with
a 10 ms shift, a failed solve counted at the time limit when there is one, as
qpbenchmark does), ``solver_time_median_s`` inside the solver,
``overhead_time_median_s`` ours; set-up apart (``setup_time_median_s`` and
``_max_s`` over the solves that set something up) and the evaluator's scoring
apart (``score_time_median_s``). ``optimality_gap_*``: over
the solves with a success status, the evaluator's objective against the best
known for that problem and horizon (the lowest objective that passes the
success rule, over every pair, both modes and the multi-start NLP), relative;
it is negative when a plan that breaks a constraint beats every feasible one.
``max_violation`` and ``max_violation_<family>``: the largest true violation,
in metres, over every plan returned; ``max_primal_residual``, ``max_dual_residual``
and ``max_duality_gap``: the largest of the usable solves' certificates, of the
problem each solver was handed (:mod:`mpc_hunt.capture.certificate`): the solver's
inaccuracy, beside the true violations that the linearisation adds.
``warm_speedup``: on a replayed row, the median over the states both modes
solved of the cold time over the warm-started one.
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np

from mpc_hunt.bench.compare import CompareRun, SolveRecord
from mpc_hunt.bench.metrics import relative_gap, shifted_geometric_mean
from mpc_hunt.capture.evaluator import VIOLATION_NAMES

USABLE = ("optimal", "optimal_inaccurate")


def best_known(run: CompareRun) -> dict[tuple[str, int], float]:
    """The lowest objective passing the success rule, per (problem, horizon), over references and records."""
    best = {key: value for key, value in run.references.items() if value is not None}
    for r in run.records:
        if r.success and r.objective is not None:
            key = (r.problem, r.horizon)
            best[key] = min(best.get(key, math.inf), r.objective)
    return best


def gap(record: SolveRecord, best: dict[tuple[str, int], float]) -> float | None:
    """The record's relative optimality gap, or None without a usable plan or a best known."""
    key = (record.problem, record.horizon)
    if record.status not in USABLE or record.objective is None or key not in best:
        return None
    return relative_gap(record.objective, best[key])


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def _stat(values: list[float], how) -> float | None:
    return _finite(how(np.asarray(values, dtype=float))) if values else None


def score(
    records: list[SolveRecord], best: dict[tuple[str, int], float], accuracy: str, time_limit: float | None
) -> dict:
    """The row of one (formulation, backend, mode, horizon) from its records."""
    first = records[0]
    times = [r.solve_time for r in records]
    penalised = [r.solve_time if r.success or time_limit is None else max(r.solve_time, time_limit) for r in records]
    setups = [r.setup_time for r in records if r.setup_time > 0]
    gaps = [g for g in (gap(r, best) for r in records) if g is not None]
    plans = [r.violation for r in records if r.violation is not None]
    row = {
        "formulation": first.formulation,
        "backend": first.backend,
        "mode": first.mode,
        "horizon": first.horizon,
        "accuracy": accuracy,
        "solves": len(records),
        "success_rate": sum(r.success for r in records) / len(records),
        "solve_time_median_s": _stat(times, np.median),
        "solve_time_p95_s": _stat(times, lambda t: np.percentile(t, 95)),
        "solve_time_shifted_geomean_s": shifted_geometric_mean(penalised),
        "solver_time_median_s": _stat([r.solver_time for r in records], np.median),
        "overhead_time_median_s": _stat([r.overhead_time for r in records], np.median),
        "setup_time_median_s": _stat(setups, np.median),
        "setup_time_max_s": _stat(setups, np.max),
        "score_time_median_s": _stat([r.score_time for r in records], np.median),
        "iterations_median": _stat([r.iterations for r in records], np.median),
        "optimality_gap_median": _stat(gaps, np.median),
        "optimality_gap_p95": _stat(gaps, lambda g: np.percentile(g, 95)),
        "gap_solves": len(gaps),
        "max_violation": max((max(v.values()) for v in plans), default=None),
    }
    for name in VIOLATION_NAMES:
        row[f"max_violation_{name}"] = max((v[name] for v in plans), default=None)
    for name in ("primal_residual", "dual_residual", "duality_gap"):  # over the usable solves' certificates
        row[f"max_{name}"] = max(
            (getattr(r, name) for r in records if r.status in USABLE and getattr(r, name) is not None), default=None
        )
    row["statuses"] = ", ".join(f"{s} {n}" for s, n in sorted(Counter(r.status for r in records).items()))
    row["warm_started"] = sum(r.warm_started for r in records)
    return row


def warm_speedup(closed: list[SolveRecord], cold: list[SolveRecord]) -> tuple[float | None, int]:
    """The median, over the states both modes solved, of the cold solve's time over the warm-started one's: the
    same-state speed-up of the replayed mode; and on how many states."""
    cold_time = {r.problem: r.solve_time for r in cold}
    ratios = [cold_time[r.problem] / r.solve_time for r in closed if r.problem in cold_time and r.solve_time > 0]
    return (float(np.median(ratios)) if ratios else None), len(ratios)


def rows(run: CompareRun) -> list[dict]:
    """Every row, by horizon, mode, then the pairs in the run's order (a row for each with finished solves). A
    replayed row also holds its same-state speed-up over the cold mode (:func:`warm_speedup`)."""
    best = best_known(run)
    groups: dict[tuple, list[SolveRecord]] = {}
    for r in run.records:
        groups.setdefault((r.horizon, r.mode, r.formulation, r.backend), []).append(r)
    order = {pair: i for i, pair in enumerate(run.pairs)}
    keys = sorted(groups, key=lambda k: (run.horizons.index(k[0]), run.modes.index(k[1]), order[k[2:]]))
    out = []
    for k in keys:
        row = score(groups[k], best, run.accuracy, run.time_limit)
        speedup, states = (
            warm_speedup(groups[k], groups.get((k[0], "cold", *k[2:]), [])) if k[1] == "replayed" else (None, 0)
        )
        out.append(row | {"warm_speedup": speedup, "warm_speedup_states": states})
    return out

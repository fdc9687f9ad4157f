"""``mpc-hunt compare --mode own-loop``: every pair in its own receding-horizon loop, hunt by hunt, under a deadline.

The replayed modes (``cold``, ``closed-loop``) hand every pair the same recorded states; a control engineer
embedding a step needs what happens when the pair meets the states its own plans lead to. Here each pair drives
the capture stage of a solving controller (the paper's by default) through whole hunts, from the same starting
hunts (scenarios: data, drawn by the caller), pairs taking turns on each hunt so that load on the machine falls on
all of them alike. Every plan is scored by the evaluator (its time kept apart from the step's); the step's time
is what the controller waited for its plan: the solve and any set-up it did.

Per pair and horizon, over its hunts: captures and capture time; the step's time p50, p95, p99 and max; deadline
misses against the time step T and against the given ``deadline``; solves stopped by their budget (time limit,
iteration cap); failed solves, fallbacks and the longest run of failed solves; iterations; the applied plans'
true violations (how many exceed the tolerance, and the largest of each family) and the certificates' largest
residuals over the usable solves (:mod:`mpc_hunt.capture.certificate`): the solver's inaccuracy and the
linearisation's error side by side. Ctrl-C stops between two hunts and keeps every hunt finished.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from mpc_hunt.capture.evaluator import VIOLATION_NAMES
from mpc_hunt.control.controllers import make_controller
from mpc_hunt.errors import BenchmarkError
from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.solving.accuracy import VIOLATION_TOLERANCE
from mpc_hunt.world.scenario import Scenario

HARD = tuple(name for name in VIOLATION_NAMES if name != "equal_distance")   # Eq. 14 is elastic in every formulation
USABLE = ("optimal", "optimal_inaccurate")


@dataclass(frozen=True)
class LoopHunt:
    """One hunt of one pair at one horizon, as its own loop ran it."""

    formulation: str
    backend: str
    horizon: int
    scenario: str
    result: HuntResult
    wall: float              # the whole hunt's wall-clock time (s)


@dataclass
class OwnLoopRun:
    """What an own-loop run did: its settings and every finished hunt."""

    scenarios: list[Scenario]
    pairs: list[tuple[str, str]]
    horizons: list[int]
    controller: str
    accuracy: str
    time_limit: float | None
    max_iter: int | None
    deadline: float | None
    hunts: list[LoopHunt] = field(default_factory=list)
    interrupted: bool = False

    @property
    def tolerance(self) -> float:
        return VIOLATION_TOLERANCE[self.accuracy]


def run_own_loop(scenarios: list[Scenario], pairs: list[tuple[str, str]], horizons: list[int], *,
                 controller: str = "paper", accuracy: str = "default", time_limit: float | None = None,
                 max_iter: int | None = None, deadline: float | None = None,
                 progress: Callable[[], None] | None = None) -> OwnLoopRun:
    """Every pair × horizon through every scenario's hunt with ``controller`` (a solving one); ``progress()`` is
    called per hunt."""
    if not scenarios:
        raise BenchmarkError("scenarios: none to hunt in")
    if not pairs:
        raise BenchmarkError("pairs: none to run")
    if accuracy not in VIOLATION_TOLERANCE:
        raise BenchmarkError(f"accuracy: unknown {accuracy!r} (known: {', '.join(VIOLATION_TOLERANCE)})")
    if deadline is not None and not (isinstance(deadline, (int, float)) and 0 < deadline < math.inf):
        raise BenchmarkError(f"deadline: a positive number of seconds, got {deadline!r}")
    run = OwnLoopRun(list(scenarios), list(pairs), list(horizons), controller, accuracy, time_limit, max_iter,
                     deadline)
    budget = {k: v for k, v in (("time_limit", time_limit), ("max_iter", max_iter)) if v is not None}
    tick = progress or (lambda: None)
    try:
        for horizon in run.horizons:
            for scenario in run.scenarios:
                for formulation, backend in run.pairs:
                    hunter = make_controller(controller, scenario, formulation=formulation, backend=backend,
                                             horizon=horizon, score=True, accuracy=accuracy, **budget)
                    t0 = time.perf_counter()
                    result = simulate(scenario, hunter, deadline=deadline, rng=np.random.default_rng(0))
                    run.hunts.append(LoopHunt(formulation, backend, horizon, scenario.name, result,
                                              time.perf_counter() - t0))
                    tick()
    except KeyboardInterrupt:
        run.interrupted = True
    return run


def _stat(values: np.ndarray, how) -> float | None:
    return float(how(values)) if len(values) else None


def score(hunts: list[LoopHunt], tolerance: float, deadline: float | None) -> dict:
    """The row of one pair at one horizon from its hunts."""
    first = hunts[0]
    results = [h.result for h in hunts]
    waits = np.concatenate([r.step_times for r in results])
    statuses = [s for r in results for s in r.solve_statuses]
    applied = np.concatenate([r.applied_violations for r in results]).reshape(-1, len(VIOLATION_NAMES))
    certificates = np.concatenate([r.certificates for r in results]).reshape(-1, 3)
    usable = np.array([s in USABLE for s in statuses], dtype=bool)
    certified = certificates[usable & ~np.any(np.isnan(certificates), axis=1)]
    scored = applied[~np.any(np.isnan(applied), axis=1)]
    hard = scored[:, [VIOLATION_NAMES.index(n) for n in HARD]]
    captured = [r for r in results if r.captured]
    T = results[0].time_step
    row = {
        "formulation": first.formulation, "backend": first.backend, "horizon": first.horizon,
        "hunts": len(results), "captured": len(captured),
        "capture_time_median_s": _stat(np.array([r.capture_time for r in captured]), np.median),
        "solves": len(waits),
        "step_time_p50_s": _stat(waits, np.median),
        "step_time_p95_s": _stat(waits, lambda t: np.percentile(t, 95)),
        "step_time_p99_s": _stat(waits, lambda t: np.percentile(t, 99)),
        "step_time_max_s": _stat(waits, np.max),
        "deadline_misses_T": int(np.sum(waits > T)),
        "deadline_misses": None if deadline is None else int(np.sum(waits > deadline)),
        "budget_hits": sum(r.budget_hits for r in results),
        "failed_solves": sum(r.failed_solves for r in results),
        "fallbacks": sum(r.fallbacks for r in results),
        "longest_failure_streak": max(r.longest_failure_streak for r in results),
        "iterations_median": _stat(np.concatenate([r.solve_iterations for r in results]), np.median),
        "applied_plans_scored": len(scored),
        "violating_plans": int(np.sum(np.any(hard > tolerance, axis=1))),
        "wall_s": sum(h.wall for h in hunts),
    }
    for i, name in enumerate(VIOLATION_NAMES):
        row[f"max_violation_{name}"] = _stat(scored[:, i], np.max)
    for i, name in enumerate(("primal_residual", "dual_residual", "duality_gap")):
        row[f"max_{name}"] = _stat(certified[:, i], np.max)
    return row


def rows(run: OwnLoopRun) -> list[dict]:
    """One row per pair × horizon with finished hunts, by horizon then the pairs in the run's order."""
    groups: dict[tuple, list[LoopHunt]] = {}
    for h in run.hunts:
        groups.setdefault((h.horizon, h.formulation, h.backend), []).append(h)
    order = {pair: i for i, pair in enumerate(run.pairs)}
    keys = sorted(groups, key=lambda k: (run.horizons.index(k[0]), order[k[1:]]))
    return [score(groups[k], run.tolerance, run.deadline) for k in keys]


def _ms(x: float | None) -> str:
    return "–" if x is None else f"{x * 1e3:.1f}"


def _g(x: float | None) -> str:
    return "–" if x is None else f"{x:.1e}"


COLUMNS = ("pair", "N", "captured", "p50 ms", "p95 ms", "max ms", "> T", "> deadline", "budget hits",
           "fallbacks", "streak", "iters", "violating", "max hard viol m", "max primal res", "max dual res",
           "max gap")


def _cells(r: dict) -> list[str]:
    hard = [r[f"max_violation_{n}"] for n in HARD if r[f"max_violation_{n}"] is not None]
    return [f"{r['formulation']}/{r['backend']}", str(r["horizon"]), f"{r['captured']}/{r['hunts']}",
            _ms(r["step_time_p50_s"]), _ms(r["step_time_p95_s"]), _ms(r["step_time_max_s"]),
            str(r["deadline_misses_T"]), "–" if r["deadline_misses"] is None else str(r["deadline_misses"]),
            str(r["budget_hits"]), str(r["fallbacks"]), str(r["longest_failure_streak"]),
            "–" if r["iterations_median"] is None else f"{r['iterations_median']:g}",
            f"{r['violating_plans']}/{r['applied_plans_scored']}", _g(max(hard) if hard else None),
            _g(r["max_primal_residual"]), _g(r["max_dual_residual"]), _g(r["max_duality_gap"])]


def table(rows: list[dict]) -> str:
    """The rows as a plain-text table."""
    body = [list(COLUMNS)] + [_cells(r) for r in rows]
    widths = [max(len(line[i]) for line in body) for i in range(len(COLUMNS))]
    return "\n".join("  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(line, widths)))
                     for line in body)


def markdown_table(rows: list[dict]) -> list[str]:
    """The rows as a Markdown table."""
    return ["| " + " | ".join(COLUMNS) + " |", "| --- | " + " | ".join("---:" for _ in COLUMNS[1:]) + " |"] \
        + ["| " + " | ".join(_cells(r)) + " |" for r in rows]

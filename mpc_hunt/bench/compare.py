"""``mpc-hunt compare``: every (formulation, backend) pair over a problem set, scored like a solver benchmark.

Two modes, each a :class:`~mpc_hunt.solving.mpc.CaptureMPC` stepping, as a
controller does. ``cold``: each problem alone, a fresh one's first step.
``replayed``: each recorded sequence of consecutive states in order with one, its
memory warm-starting each step (the plan it applied, shifted one step, and the
duals, while the same defenders are controlled). Pairs take turns on each problem (or
sequence), so that load on the machine falls on all of them alike. Each pair
runs as a controller runs it (the stage-form steps as a control loop). A solve's all-in time runs from the
state handed over to the plan returned, as the controller waits for it (posing
the problem, the solver, our overhead), with any set-up it did and the
evaluator's scoring taken out and reported apart. Every plan is scored by the
evaluator (:data:`mpc_hunt.capture.evaluator.OBJECTIVE`). Ctrl-C stops the run
between two solves and keeps every solve finished so far.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field
from typing import Any, Callable

import numpy as np

from mpc_hunt.bench.best_known import MultiStartNLP
from mpc_hunt.bench.metrics import is_success
from mpc_hunt.bench.problem_set import ProblemEntry, ProblemSet
from mpc_hunt.capture.problem import OBJECTIVES, CaptureProblem
from mpc_hunt.errors import BenchmarkError, field_name
from mpc_hunt.solving import registry
from mpc_hunt.solving.accuracy import VIOLATION_TOLERANCE
from mpc_hunt.solving.mpc import CaptureMPC

MODES = ("cold", "replayed")


@dataclass(frozen=True)
class SolveRecord:
    """One solve of one problem by one pair: its status, score and times (seconds)."""

    formulation: str
    backend: str
    mode: str
    horizon: int
    problem: str
    status: str
    success: bool
    objective: float | None
    violation: dict[str, float] | None
    solve_time: float  # all-in, set-up excluded
    solver_time: float  # inside the solver
    overhead_time: float  # ours: posing the problem, building data, reading back
    setup_time: float
    score_time: float  # the evaluator's, outside the all-in time
    iterations: int
    warm_started: bool
    primal_residual: float | None = None  # the certificate of the QP (or NLP) the solver was handed
    dual_residual: float | None = None
    duality_gap: float | None = None

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass
class CompareRun:
    """What a run did: its settings, every finished solve and the multi-start references."""

    problem_set: ProblemSet
    pairs: list[tuple[str, str]]
    horizons: list[int]
    modes: list[str]
    accuracy: str
    time_limit: float | None
    starts: int
    records: list[SolveRecord] = field(default_factory=list)
    references: dict[tuple[str, int], float | None] = field(default_factory=dict)
    interrupted: bool = False
    objective: str = "paper"
    max_iter: int | None = None

    @property
    def tolerance(self) -> float:
        return VIOLATION_TOLERANCE[self.accuracy]


def planned_solves(problem_set: ProblemSet, pairs: int, horizons: list[int], modes: list[str], starts: int) -> int:
    """How many solves a full run makes, the reference's starts included: a progress bar's total."""
    cold = len(problem_set.problems) if "cold" in modes else 0
    loop = sum(map(len, problem_set.sequences().values())) if "replayed" in modes else 0
    return (starts * len(problem_set.problems) + pairs * (cold + loop)) * len(horizons)


def check_pairs(pairs: list[str] | None, objective: str = "paper") -> list[tuple[str, str]]:
    """The pairs ``pairs`` names, each ``formulation:backend`` or ``formulation`` (all its installed backends that pose
    ``objective``); None: every installed pair that poses ``objective``
    (:func:`~mpc_hunt.solving.registry.objective_refusal`)."""
    if not pairs:
        return registry.pairs(objective=objective)
    out: list[tuple[str, str]] = []
    for text in pairs:
        formulation, _, named = text.partition(":")
        backend = registry.check_pair(formulation, named) if named else None
        refusal = registry.objective_refusal(formulation, backend, objective)
        if refusal is not None:
            raise BenchmarkError(
                f"{field_name('pairs')}: {text}: {refusal.reason} (pick another "
                f"{refusal.fields[0]}, or another {field_name('objective')})"
            )
        chosen = (
            [(formulation, backend)]
            if backend
            else [p for p in registry.pairs(objective=objective) if p[0] == formulation]
        )
        out += [p for p in chosen if p not in out]
    return out


def timed_step(
    mpc: CaptureMPC, pose: Callable[[], CaptureProblem], tolerance: float, mode: str = "replayed", problem: str = ""
) -> SolveRecord:
    """One step of ``mpc`` on the problem ``pose()`` makes, timed as a controller waits for it: from the state
    handed over (the problem posed) to the plan returned, with any set-up and the evaluator's scoring taken out
    and reported apart; a success is a usable plan within ``tolerance`` (m,
    :func:`~mpc_hunt.bench.metrics.is_success`). ``mode`` and ``problem`` (an id) label the record."""
    t0 = time.perf_counter()
    posed = pose()
    solution = mpc.step(posed).solution
    elapsed = time.perf_counter() - t0
    all_in = max(elapsed - solution.setup_time - solution.score_time, 0.0)
    return SolveRecord(
        mpc.solver.formulation.name,
        mpc.solver.backend.name,
        mode,
        posed.horizon,
        problem,
        solution.status.value,
        is_success(solution.success, solution.violation, tolerance),
        solution.objective,
        solution.violation,
        all_in,
        solution.solver_time,
        max(all_in - solution.solver_time, 0.0),
        solution.setup_time,
        solution.score_time,
        solution.iterations,
        solution.warm_started,
        *(
            (None,) * 3
            if solution.certificate is None
            else (
                solution.certificate.primal_residual,
                solution.certificate.dual_residual,
                solution.certificate.duality_gap,
            )
        ),
    )


def _solve(run: CompareRun, mpc: CaptureMPC, mode: str, entry: ProblemEntry, horizon: int) -> SolveRecord:
    return timed_step(
        mpc, lambda: run.problem_set.problem(entry, horizon, run.objective), run.tolerance, mode, entry.id
    )


def _new_mpc(run: CompareRun, pair: tuple[str, str]) -> CaptureMPC:
    budget: dict[str, Any] = {} if run.max_iter is None else {"max_iter": run.max_iter}
    return CaptureMPC(*pair, time_limit=run.time_limit, accuracy=run.accuracy, score=True, **budget)


def _horizon(run: CompareRun, horizon: int, rng: np.random.Generator, tick: Callable[[], None]) -> None:
    reference = MultiStartNLP(run.starts, run.tolerance)
    for entry in run.problem_set.problems:
        run.references[(entry.id, horizon)] = reference.best(
            run.problem_set.problem(entry, horizon, run.objective), rng, tick
        )
    if "cold" in run.modes:
        for entry in run.problem_set.problems:
            for pair in run.pairs:
                run.records.append(_solve(run, _new_mpc(run, pair), "cold", entry, horizon))
                tick()
    if "replayed" in run.modes:
        for sequence in run.problem_set.sequences().values():
            for pair in run.pairs:
                mpc = _new_mpc(run, pair)
                for entry in sequence:
                    run.records.append(_solve(run, mpc, "replayed", entry, horizon))
                    tick()


def run_compare(
    problem_set: ProblemSet,
    pairs: list[tuple[str, str]],
    horizons: list[int],
    modes: list[str],
    rng: np.random.Generator,
    *,
    accuracy: str = "default",
    time_limit: float | None = None,
    max_iter: int | None = None,
    starts: int = 4,
    objective: str = "paper",
    progress: Callable[[], None] | None = None,
) -> CompareRun:
    """Run every pair over ``problem_set`` at each horizon in each mode, each problem posed with ``objective``
    (``paper`` or ``enclose``); ``progress()`` is called per solve."""
    if not problem_set.problems:
        raise BenchmarkError("problems: the selection is empty")
    unknown = [m for m in modes if m not in MODES]
    if unknown:
        raise BenchmarkError(f"modes: unknown {unknown[0]!r} (known: {', '.join(MODES)})")
    if accuracy not in VIOLATION_TOLERANCE:
        raise BenchmarkError(f"accuracy: unknown {accuracy!r} (known: {', '.join(VIOLATION_TOLERANCE)})")
    if objective not in OBJECTIVES:
        raise BenchmarkError(f"objective: unknown {objective!r} (known: {', '.join(OBJECTIVES)})")
    if starts < 1:
        raise BenchmarkError(f"starts: must be at least 1, got {starts}")
    untimed = [b for _, b in pairs if time_limit is not None and not registry.backend_class(b).TIME_LIMIT]
    if untimed:
        raise BenchmarkError(
            f"{field_name('time_limit')}: backend {untimed[0]} takes none; leave it out of the "
            f"pairs, or drop {field_name('time_limit')}"
        )
    run = CompareRun(
        problem_set,
        list(pairs),
        list(horizons),
        list(modes),
        accuracy,
        time_limit,
        starts,
        max_iter=max_iter,
        objective=objective,
    )
    tick = progress or (lambda: None)
    try:
        for horizon in run.horizons:
            _horizon(run, horizon, rng, tick)
    except KeyboardInterrupt:
        run.interrupted = True
    return run

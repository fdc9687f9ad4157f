"""``mpc-hunt compare --mode own-loop``: every pair in its own receding-horizon loop, hunt by hunt, under a deadline.

The modes ``cold`` and ``replayed`` hand every pair the same recorded states; a control engineer
embedding a step needs what happens when the pair meets the states its own plans lead to. Here each pair drives
the capture stage of a solving controller (the paper's by default) through hunts, from the same starts (scenarios:
data, drawn by the caller; :func:`capture_stage_hunts` starts each where the paper's strategy first reaches the
capture stage), pairs taking turns on each hunt so that load on the machine falls on all of them alike. Every plan
is scored by the evaluator (its time kept apart from the step's); the step's time is the solve's, as the
controller waits for it, and a new structure's one-off set-up (building its functions; compiling a codegen step)
is counted apart: set-ups and the longest, since a robot builds its structures before its loop (or loads them
from the cache).

A hunt whose capture stage has failed for ``abandon_after`` seconds in a row (:data:`ABANDON_AFTER`) is stopped and
counted *abandoned* (not captured): from there on it would measure the fallback, not the pair, at the pair's full
budget a step. Hunts run one after another, or on worker processes (``workers``), each hunt whole on one.

Per pair and horizon, over its hunts: captures, abandoned hunts and capture time; the step's time p50, p95, p99
and max; deadline
misses against the time step T and against the given ``deadline``; solves stopped by their budget (time limit,
iteration cap); failed solves, fallbacks and the longest run of failed solves; iterations; the usable plans the
loop refused as violating (:class:`~mpc_hunt.solving.mpc.CaptureMPC`'s rule) and the applied plans' true
violations (how many exceed the tolerance: none, by that rule; the largest of each family); the certificates'
largest residuals over the usable solves (:mod:`mpc_hunt.capture.certificate`): the solver's inaccuracy and the
linearisation's error side by side. Under a time limit, the steps that took longer than it plus their own overhead,
counted twice: on the wall clock, and on the time the process ran (:mod:`mpc_hunt.solving.step_timing`), which
tells a step whose code ran long from one whose core the machine gave to another process. Ctrl-C stops the run
and keeps every hunt finished.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Callable, Iterable, Iterator

import numpy as np

from mpc_hunt import markdown
from mpc_hunt.capture.evaluator import HARD_CONSTRAINTS as HARD
from mpc_hunt.capture.evaluator import VIOLATION_NAMES
from mpc_hunt.capture.solution import Status
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.spec import make_controller
from mpc_hunt.errors import BenchmarkError
from mpc_hunt.markdown import Column, figure
from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.sim.simulator import check_seconds, simulate
from mpc_hunt.solving.accuracy import VIOLATION_TOLERANCE
from mpc_hunt.workers import run_local
from mpc_hunt.world.attacker import perceives
from mpc_hunt.world.scenario import Scenario


@dataclass(frozen=True)
class LoopHunt:
    """One hunt of one pair at one horizon, as its own loop ran it."""

    formulation: str
    backend: str
    horizon: int
    scenario: str
    result: HuntResult
    wall: float  # the whole hunt's wall-clock time (s)
    time_limit: float | None = None  # each step's (s), if one was given


ABANDON_AFTER = 10.0  # s: a hunt whose capture stage has failed this long in a row stops, "abandoned" (100 steps
# at T = 0.1 s, twenty times the longest streak a pair fit to embed may have: what follows
# is the fallback's hunt, not the pair's, and would only cost the run its time)


@dataclass
class OwnLoopRun:
    """An own-loop run: its settings (every pair × horizon through every scenario's hunt, with ``controller``, a
    solving one), then what it did (every finished hunt, whether Ctrl-C stopped it)."""

    scenarios: list[Scenario]
    pairs: list[tuple[str, str]]
    horizons: list[int]
    controller: str = "paper"
    accuracy: str = "default"
    time_limit: float | None = None
    max_iter: int | None = None
    deadline: float | None = None
    abandon_after: float | None = ABANDON_AFTER
    hunts: list[LoopHunt] = field(default_factory=list)
    interrupted: bool = False

    @property
    def tolerance(self) -> float:
        return VIOLATION_TOLERANCE[self.accuracy]

    def tasks(self) -> list[LoopTask]:
        """Its hunts, its settings checked: by horizon, then hunt, the pairs taking turns on each hunt (so that
        load on the machine falls on all of them alike)."""
        if not self.scenarios:
            raise BenchmarkError("scenarios: none to hunt in")
        if not self.pairs:
            raise BenchmarkError("pairs: none to run")
        if self.accuracy not in VIOLATION_TOLERANCE:
            raise BenchmarkError(f"accuracy: unknown {self.accuracy!r} (known: {', '.join(VIOLATION_TOLERANCE)})")
        check_seconds("deadline", self.deadline, BenchmarkError)
        check_seconds("abandon_after", self.abandon_after, BenchmarkError)
        given = (("time_limit", self.time_limit), ("max_iter", self.max_iter))
        budget = tuple((k, v) for k, v in given if v is not None)
        settings = (self.controller, self.accuracy, budget, self.deadline, self.abandon_after)
        return [
            LoopTask(scenario, formulation, backend, horizon, *settings)
            for horizon in self.horizons
            for scenario in self.scenarios
            for formulation, backend in self.pairs
        ]


def from_capture_stage(scenario: Scenario, window: float) -> Scenario | None:
    """``scenario`` started where its hunt under the paper's strategy (one-step NLP, prediction on) first has a
    defender in the capture stage (within R_agg of the attacker), run for at most ``window`` seconds from there:
    the part of a hunt a capture stage is compared on, every pair then meeting the states its own plans lead to.
    None when that hunt never reaches the capture stage (the attacker escaped first). Robot failures keep their
    times from the hunt's start."""
    found: list[Observation] = []

    def reached(obs: Observation) -> bool:
        if perceives(scenario, obs.attacker, obs.defenders).any():
            found.append(obs)
            return True
        return False

    simulate(scenario, until=reached)
    if not found:
        return None
    obs = found[0]
    defenders = tuple(
        replace(
            d,
            start=(float(p[0]), float(p[1])),
            fails_at=None if d.fails_at is None else max(d.fails_at - obs.time, 0.0),
        )
        for d, p in zip(scenario.defenders, obs.defenders)
    )
    hunt = replace(scenario.hunt, time_limit=min(window, scenario.hunt.time_limit))
    return replace(
        scenario,
        attacker=replace(scenario.attacker, start=(float(obs.attacker[0]), float(obs.attacker[1]))),
        defenders=defenders,
        hunt=hunt,
        description=f"{scenario.name} from t = {obs.time:.1f} s, its capture stage's start, "
        f"for at most {hunt.time_limit:g} s",
    )


WINDOW = 120.0  # s: how long each hunt runs from its capture stage's start (the paper's scenarios capture in 41
# and 110 s from there under the paper's strategy)
DRAWS_PER_HUNT = 5  # random hunts drawn at most per hunt kept (some never reach the capture stage)


def capture_stage_hunts(
    named: list[Scenario], random: Iterable[Scenario], count: int, window: float = WINDOW
) -> list[Scenario]:
    """The hunts an own-loop run starts from: each of ``named`` and the first ``count`` of ``random`` that reach
    the capture stage (:func:`from_capture_stage`), at most ``DRAWS_PER_HUNT × count`` of them drawn."""
    hunts = []
    for scenario in named:
        start = from_capture_stage(scenario, window)
        if start is None:
            raise BenchmarkError(f"scenarios: {scenario.name}'s hunt never reaches the capture stage")
        hunts.append(start)
    kept = 0
    for drawn, scenario in enumerate(random):
        if kept == count or drawn >= DRAWS_PER_HUNT * max(count, 1):
            break
        start = from_capture_stage(scenario, window)
        if start is not None:
            hunts.append(start)
            kept += 1
    if kept < count:
        raise BenchmarkError(f"hunts: only {kept} of the random hunts drawn reach the capture stage, {count} asked")
    return hunts


@dataclass(frozen=True)
class LoopTask:
    """One hunt of one pair at one horizon, as a worker runs it (:func:`run_hunt`)."""

    scenario: Scenario
    formulation: str
    backend: str
    horizon: int
    controller: str
    accuracy: str
    budget: tuple  # (("time_limit", s), ("max_iter", n)): the ones given
    deadline: float | None
    abandon_after: float | None


def run_hunt(task: LoopTask) -> LoopHunt:
    """The task's hunt, its pair driving ``task.controller``'s capture stage, every plan scored."""
    hunter = make_controller(
        task.controller,
        task.scenario,
        formulation=task.formulation,
        backend=task.backend,
        horizon=task.horizon,
        score=True,
        accuracy=task.accuracy,
        **dict(task.budget),
    )
    t0 = time.perf_counter()
    result = simulate(
        task.scenario, hunter, deadline=task.deadline, abandon_after=task.abandon_after, rng=np.random.default_rng(0)
    )
    wall = time.perf_counter() - t0
    limit = dict(task.budget).get("time_limit")
    return LoopHunt(task.formulation, task.backend, task.horizon, task.scenario.name, result, wall, limit)


def run_tasks(tasks: Iterable[LoopTask], workers: int = 1) -> Iterator[LoopHunt]:
    """Each task's hunt as it finishes: in this process (``workers`` = 1, in order) or on ``workers`` local
    processes (:func:`mpc_hunt.workers.run_local`; each hunt's times then taken beside the others')."""
    if workers == 1:
        return map(run_hunt, tasks)
    return run_local(tasks, run_hunt, workers)


def run_own_loop(run: OwnLoopRun, workers: int = 1, progress: Callable[[LoopHunt], None] | None = None) -> OwnLoopRun:
    """``run``'s hunts (its settings checked before any), on ``workers`` processes (:func:`run_tasks`), each kept
    in ``run.hunts`` as it finishes and ``progress(hunt)`` called with it; Ctrl-C stops the run, keeping them."""
    tasks = run.tasks()
    tick = progress or (lambda hunt: None)
    try:
        for hunt in run_tasks(tasks, workers):
            run.hunts.append(hunt)
            tick(hunt)
    except KeyboardInterrupt:
        run.interrupted = True
    return run


def _stat(values, how) -> float | None:
    values = np.asarray(values, dtype=float)
    return float(how(values)) if len(values) else None


def hunt_summary(hunt: LoopHunt) -> dict:
    """One hunt as plain data (JSON-ready): its keys, counts and per-step waits and iterations, what :func:`score`
    aggregates (a study keeps it as it goes)."""
    r = hunt.result
    usable = np.array([Status(s).usable for s in r.solve_statuses], dtype=bool)
    certified = r.certificates[usable & ~np.any(np.isnan(r.certificates), axis=1)] if len(usable) else np.zeros((0, 3))
    scored = r.applied_violations[~np.any(np.isnan(r.applied_violations), axis=1)]
    hard = scored[:, [VIOLATION_NAMES.index(n) for n in HARD]]
    over = r.solve_times - r.overhead_times - (hunt.time_limit or 0.0)  # past the limit, beyond our own overhead
    # the same, counting only the time the process ran, neither off the CPU nor stolen (mpc_hunt.solving.step_timing)
    on_cpu = over - r.off_cpu_times - r.stolen_times
    return {
        "formulation": hunt.formulation,
        "backend": hunt.backend,
        "horizon": hunt.horizon,
        "scenario": hunt.scenario,
        "captured": r.captured,
        "abandoned": r.termination == "abandoned",
        "capture_time_s": r.capture_time,
        "time_step_s": r.time_step,
        "simulated_s": r.steps * r.time_step,
        "wall_s": hunt.wall,
        "solve_times_s": [float(t) for t in r.solve_times],
        "iterations": [int(i) for i in r.solve_iterations],
        "setups": int(np.sum(r.setup_times > 0)),
        "setup_max_s": _stat(r.setup_times, np.max),
        "overhead_max_s": _stat(r.overhead_times, np.max),
        "time_limit_s": hunt.time_limit,
        "past_limit_and_overhead": None if hunt.time_limit is None else int(np.sum(over > 0)),
        "largest_overrun_s": None if hunt.time_limit is None else _stat(over, np.max),
        "past_limit_on_cpu": None if hunt.time_limit is None else int(np.sum(on_cpu > 0)),
        "largest_overrun_on_cpu_s": None if hunt.time_limit is None else _stat(on_cpu, np.max),
        "past_limit_stolen": None if hunt.time_limit is None else int(np.sum((over > 0) & (r.stolen_times > 0))),
        "budget_hits": r.budget_hits,
        "failed_solves": r.failed_solves,
        "fallbacks": r.fallbacks,
        "longest_failure_streak": r.longest_failure_streak,
        "violating_plans": r.violating_plans,
        "applied_plans_scored": len(scored),
        "applied_beyond": {str(t): int(np.sum(np.any(hard > t, axis=1))) for t in VIOLATION_TOLERANCE.values()},
        "max_violation": {name: _stat(scored[:, i], np.max) for i, name in enumerate(VIOLATION_NAMES)},
        "max_certificate": {
            name: _stat(certified[:, i], np.max)
            for i, name in enumerate(("primal_residual", "dual_residual", "duality_gap"))
        },
    }


def _largest(values: list) -> float | None:
    values = [v for v in values if v is not None]
    return max(values) if values else None


def score(hunts: list[dict], tolerance: float, deadline: float | None) -> dict:
    """The row of one pair at one horizon from its hunts' summaries (:func:`hunt_summary`)."""
    first = hunts[0]
    waits = np.concatenate([np.asarray(h["solve_times_s"], dtype=float) for h in hunts])
    captured = [h for h in hunts if h["captured"]]
    T = first["time_step_s"]
    simulated, wall = sum(h["simulated_s"] for h in hunts), sum(h["wall_s"] for h in hunts)
    row = {
        "formulation": first["formulation"],
        "backend": first["backend"],
        "horizon": first["horizon"],
        "hunts": len(hunts),
        "captured": len(captured),
        "abandoned": sum(h["abandoned"] for h in hunts),
        "capture_time_median_s": _stat([h["capture_time_s"] for h in captured], np.median),
        "solves": len(waits),
        "step_time_p50_s": _stat(waits, np.median),
        "step_time_p95_s": _stat(waits, lambda t: np.percentile(t, 95)),
        "step_time_p99_s": _stat(waits, lambda t: np.percentile(t, 99)),
        "step_time_max_s": _stat(waits, np.max),
        "deadline_misses_T": int(np.sum(waits > T)),
        "deadline_misses": None if deadline is None else int(np.sum(waits > deadline)),
        "setups": sum(h["setups"] for h in hunts),
        "setup_max_s": _largest([h["setup_max_s"] for h in hunts]),
        "overhead_max_s": _largest([h["overhead_max_s"] for h in hunts]),
        "past_limit_and_overhead": None
        if first["time_limit_s"] is None
        else sum(h["past_limit_and_overhead"] for h in hunts),
        "largest_overrun_s": _largest([h["largest_overrun_s"] for h in hunts]),
        "past_limit_on_cpu": None if first["time_limit_s"] is None else sum(h["past_limit_on_cpu"] for h in hunts),
        "largest_overrun_on_cpu_s": _largest([h["largest_overrun_on_cpu_s"] for h in hunts]),
        "budget_hits": sum(h["budget_hits"] for h in hunts),
        "failed_solves": sum(h["failed_solves"] for h in hunts),
        "fallbacks": sum(h["fallbacks"] for h in hunts),
        "longest_failure_streak": max(h["longest_failure_streak"] for h in hunts),
        "iterations_median": _stat(
            np.concatenate([np.asarray(h["iterations"], dtype=float) for h in hunts]), np.median
        ),
        "applied_plans_scored": sum(h["applied_plans_scored"] for h in hunts),
        "violating_plans": sum(h["violating_plans"] for h in hunts),
        "applied_beyond_tolerance": sum(h["applied_beyond"][str(tolerance)] for h in hunts),
        "wall_s": wall,
        "real_time_factor": simulated / wall if wall > 0 else None,
    }
    for name in VIOLATION_NAMES:
        row[f"max_violation_{name}"] = _largest([h["max_violation"][name] for h in hunts])
    for name in ("primal_residual", "dual_residual", "duality_gap"):
        row[f"max_{name}"] = _largest([h["max_certificate"][name] for h in hunts])
    return row


def rows_of(
    summaries: list[dict], pairs: list[tuple[str, str]], horizons: list[int], tolerance: float, deadline: float | None
) -> list[dict]:
    """One row per pair × horizon with finished hunts, by horizon then the pairs in ``pairs``' order."""
    groups: dict[tuple, list[dict]] = {}
    for h in summaries:
        groups.setdefault((h["horizon"], h["formulation"], h["backend"]), []).append(h)
    order = {tuple(pair): i for i, pair in enumerate(pairs)}
    keys = sorted(groups, key=lambda k: (horizons.index(k[0]), order[k[1:]]))
    return [score(groups[k], tolerance, deadline) for k in keys]


def rows(run: OwnLoopRun) -> list[dict]:
    """The run's rows (:func:`rows_of`)."""
    return rows_of([hunt_summary(h) for h in run.hunts], run.pairs, run.horizons, run.tolerance, run.deadline)


def _hard_violation(r: dict) -> str:
    hard = [r[f"max_violation_{n}"] for n in HARD if r[f"max_violation_{n}"] is not None]
    return "–" if not hard else f"{max(hard):.1e}"


COLUMNS = (
    Column("pair", lambda r: f"{r['formulation']}/{r['backend']}", "l"),
    Column("N", figure("horizon")),
    Column("captured", lambda r: f"{r['captured']}/{r['hunts']}"),
    Column("abandoned", figure("abandoned")),
    Column("p50 ms", figure("step_time_p50_s", ".1f", 1e3)),
    Column("p95 ms", figure("step_time_p95_s", ".1f", 1e3)),
    Column("p99 ms", figure("step_time_p99_s", ".1f", 1e3)),
    Column("max ms", figure("step_time_max_s", ".1f", 1e3)),
    Column("> T", figure("deadline_misses_T")),
    Column("> deadline", figure("deadline_misses")),
    Column("> limit", figure("past_limit_and_overhead")),
    Column("> limit on CPU", figure("past_limit_on_cpu")),
    Column("set-ups", figure("setups")),
    Column("max set-up ms", figure("setup_max_s", ".1f", 1e3)),
    Column("budget hits", figure("budget_hits")),
    Column("fallbacks", figure("fallbacks")),
    Column("streak", figure("longest_failure_streak")),
    Column("iters", figure("iterations_median", "g")),
    Column("violating", figure("violating_plans")),
    Column("max hard viol m", _hard_violation),
    Column("max primal res", figure("max_primal_residual", ".1e")),
    Column("max dual res", figure("max_dual_residual", ".1e")),
    Column("max gap", figure("max_duality_gap", ".1e")),
)


def table(rows: list[dict]) -> str:
    """The rows as a plain-text table."""
    return markdown.columns_plain(COLUMNS, rows)


def markdown_table(rows: list[dict], extra: Column | None = None) -> list[str]:
    """The rows as a Markdown table; ``extra``: a last column."""
    return markdown.columns_table(COLUMNS if extra is None else (*COLUMNS, extra), rows)

"""Monte Carlo sweeps: many random hunts for one or more strategies, on local processes or a Dask cluster.

A strategy is a controller spec written ``controller[:formulation[:backend[:horizon]]]``
(:class:`mpc_hunt.control.spec.ControllerSpec`), e.g. ``paper:nlp:ipopt:1`` (the
paper's), ``paper:qp:daqp:5`` or ``apf``; a field left out is what ``mpc-hunt
simulate --controller`` takes for it (``enclose`` is ``enclose:rti:hpipm:10``),
and a sweep stores it as its :attr:`~mpc_hunt.control.spec.ControllerSpec.label`. Every
strategy runs against every attacker behaviour
(:data:`mpc_hunt.world.behaviours.BEHAVIOURS`) with every belief of the
defenders (:mod:`mpc_hunt.world.belief`, written as its label). Hunt i of a
sweep with seed s uses the scenario ``random_scenario.sweep_scenario(s, i,
ranges)`` with its attacker's behaviour replaced, and the random generators of
:func:`hunt_rngs`, for every strategy, so strategies meet the same hunts and the
same belief errors. Each finished hunt is one row (:func:`run_hunt`), stored at
once (:mod:`mpc_hunt.sweep.store`), so an interrupted sweep loses nothing
finished and resumes where it stopped.

A worker that dies loses only the hunts it was running. On local processes a
death breaks the whole pool: the hunts then running go to a new pool, and after
``MAX_WORKER_DEATHS`` deaths (:mod:`mpc_hunt.workers`) the sweep stops (:class:`SweepStopped`). On Dask the
scheduler reruns them; a hunt whose workers died too often (Dask's
``allowed-failures``) is a row with cause ``error``.
"""

from __future__ import annotations

import itertools
import time
from dataclasses import dataclass
from typing import Any, Callable, Generator, Iterable, Iterator, Sequence

import numpy as np

from mpc_hunt.control.controllers import CONTROLLERS
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.errors import MpcHuntError, SettingError, SweepStopped, WorkersDied
from mpc_hunt.sim.batch import simulate_batch
from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.sweep.outcome import failure_cause, safety_breaches
from mpc_hunt.sweep.random_scenario import ScenarioRanges, ranges_from_dict, ranges_to_dict, sweep_scenario
from mpc_hunt.sweep.scenario_row import capturable_by_definition, scenario_row
from mpc_hunt.workers import run_local as workers_run_local
from mpc_hunt.world.behaviours import DEFAULT_BEHAVIOUR, make_behaviour, with_behaviour
from mpc_hunt.world.belief import WORLD, Belief, belief_rng, parse_belief
from mpc_hunt.world.ensemble import perturbed

# The one-step NLP with the optimiser's field smoothed (docs/model.md, E11), the fastest QP strategy (one
# Gauss-Newton QP per step on HPIPM), and the no-optimisation baseline. The paper's own one-step NLP
# (paper:nlp:ipopt:1) stalls at IPOPT's iteration limit on the field's kink in many random hunts, at up
# to 0.2 s a solve, which makes it the slowest strategy to sweep; name it to include it.
DEFAULT_STRATEGIES = ("enclose:rti:hpipm:10", "paper:rti:hpipm:5", "voronoi", "apf")
BATCH = 32  # hunts of a batched controller run together in one task (docs/engine.md: the batch size measured)
MAX_TASKS = 10_000_000  # hunts in one sweep, every strategy, attacker and belief (a row each in its SQLite file)
DASK_IN_FLIGHT = 100  # batches of hunts (:func:`batches`) handed to a Dask cluster at once (more as they finish)
EXACT = Belief().label()


def hunt_rngs(seed: int, index: int, member: int = 0) -> tuple[np.random.Generator, np.random.Generator]:
    """The world's generator (the attacker's behaviour) and the belief's (its heading error,
    :func:`~mpc_hunt.world.belief.belief_rng`) for hunt ``index`` of the sweep ``seed``, ensemble member
    ``member``: children ``WORLD`` and ``BELIEF`` of child ``member`` of child ``index`` of ``SeedSequence(seed)``,
    i.e. ``SeedSequence(seed, spawn_key=(index, member, k))``.

    Spawned as the scenario's own generator is (``random_scenario.sweep_rng``, spawn key ``(index,)``), apart
    from it and from each other; the same for every strategy. Not ``default_rng([seed, index, member, k])``:
    numpy pads a short seed list with zeros, so ``[seed, index, member, 0]`` is the stream of
    ``[seed, index, member]``, which moves an ensemble member's starts (``_drawn``).
    """
    world = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index, member, WORLD)))
    return world, belief_rng(seed, index, member)


@dataclass(frozen=True)
class Hunt:
    """One task of a sweep: a strategy on the scenario (seed, index) drawn from ``ranges``, whose attacker moves
    by the behaviour ``attacker``, with the defenders' belief ``belief`` (a :meth:`Belief.label`).

    ``member`` 0 is the scenario as drawn; member k > 0 moves each start by at most a nanometre
    (:func:`mpc_hunt.world.ensemble.perturbed`, its RNG seeded by seed, index and k), to measure a row's spread.
    """

    strategy: str
    seed: int
    index: int
    ranges: dict
    member: int = 0
    attacker: str = DEFAULT_BEHAVIOUR
    belief: str = EXACT


def run_hunt(task: Hunt) -> dict:
    """Run one hunt; its row (plain data). An unexpected exception is a row with cause ``error``."""
    return run_hunts([task])[0]


def run_hunts(batch: Sequence[Hunt]) -> list[dict]:
    """Run hunts together, one batch of the engine (:func:`mpc_hunt.sim.batch.simulate_batch`); their rows, in
    order, each as :func:`run_hunt` would give it alone (a batch changes no hunt). A hunt's ``wall_time_s`` is its
    share of the batch's time, by its steps. A hunt whose controller cannot be built is a row with cause
    ``error``; if the batch raises, its hunts run again one by one, so that one hunt's crash is its own row."""
    rows: list[dict | None] = [None] * len(batch)
    ready = []  # (place, scenario, row, controller, world)
    for place, task in enumerate(batch):
        scenario, row = _drawn(task)
        world, belief_rng = hunt_rngs(task.seed, task.index, task.member)
        start = time.perf_counter()
        try:
            spec, belief = ControllerSpec.parse(task.strategy), parse_belief(task.belief)
            ready.append((place, scenario, row, spec.build(scenario, belief=belief, rng=belief_rng), world))
        except Exception as exc:  # noqa: BLE001 - one hunt's crash is its row, never the sweep's end
            rows[place] = row | _error(exc, time.perf_counter() - start)
    if not ready:
        return [row for row in rows if row is not None]
    start = time.perf_counter()
    try:
        results = simulate_batch([r[1] for r in ready], [r[3] for r in ready], [r[4] for r in ready])
    except Exception as exc:  # noqa: BLE001 - whose crash: each hunt alone tells
        if len(batch) == 1:
            return [ready[0][2] | _error(exc, time.perf_counter() - start)]
        return [row if row is not None else run_hunt(task) for row, task in zip(rows, batch)]
    elapsed, total = time.perf_counter() - start, max(1, sum(r.steps for r in results))
    for (place, scenario, row, _, _), result in zip(ready, results):
        rows[place] = row | _row(result, scenario, elapsed * result.steps / total)
    return [row for row in rows if row is not None]


def _row(result: HuntResult, scenario, wall_time: float) -> dict:
    """The result part of a hunt's row."""
    cause = failure_cause(result, scenario)
    breach_approach, breach_capture = safety_breaches(result, scenario)
    times = result.solve_times
    T = scenario.hunt.time_step
    outcome = "captured" if cause is None else ("uncapturable" if not capturable_by_definition(scenario) else "failed")
    return {
        "outcome": outcome,
        "cause": cause,
        "message": None,
        "termination": result.termination,
        "capture_time_s": result.capture_time,
        "path_length_m": float(np.sum(result.path_lengths)),
        "min_obstacle_clearance_m": result.min_obstacle_clearance,
        "min_defender_separation_m": result.min_defender_separation,
        "min_attacker_distance_m": result.min_attacker_distance,
        "min_arena_margin_m": result.min_arena_margin,
        "safety_breach_approach": breach_approach,
        "safety_breach_capture": breach_capture,
        "steps": result.steps,
        "solves": int(len(times)),
        "failed_solves": result.failed_solves,
        "fallbacks": result.fallbacks,
        "longest_failure_streak": result.longest_failure_streak,
        "solve_time_p50_s": float(np.median(times)) if len(times) else None,
        "solve_time_p95_s": float(np.percentile(times, 95)) if len(times) else None,
        "solve_time_max_s": float(np.max(times)) if len(times) else None,
        "solves_over_time_step": int(np.sum(times > T)),
        "wall_time_s": wall_time,
    }


def batches(todo: Iterable[Hunt], size: int = BATCH) -> Iterator[list[Hunt]]:
    """``todo`` in consecutive batches of up to ``size`` hunts whose controllers command a batch in one call
    (:class:`~mpc_hunt.control.controller.BatchedController`); any other hunt is a batch of its own, so that a
    stop loses no more than before."""
    batch: list[Hunt] = []
    for task in todo:
        if not _batched(task.strategy):
            yield [task]
            continue
        batch.append(task)
        if len(batch) == size:
            yield batch
            batch = []
    if batch:
        yield batch


def _batched(strategy: str) -> bool:
    """Does the controller of ``strategy`` command a batch in one call?"""
    try:
        return callable(getattr(CONTROLLERS.get(ControllerSpec.parse(strategy).controller), "batched", None))
    except MpcHuntError:  # its hunts' rows say what is wrong
        return False


def _drawn(task: Hunt) -> tuple:
    """The task's scenario, its attacker moving by the task's behaviour, and the start of its row: the strategy,
    attacker, belief and the scenario's parameters."""
    scenario = with_behaviour(sweep_scenario(task.seed, task.index, ranges_from_dict(task.ranges)), task.attacker)
    if task.member:
        scenario = perturbed(scenario, np.random.default_rng([task.seed, task.index, task.member]))
    return scenario, {
        "strategy": task.strategy,
        "attacker": task.attacker,
        "belief": task.belief,
        **scenario_row(scenario, seed=task.seed, index=task.index),
    }


def _error(exc: BaseException, wall_time: float | None) -> dict:
    """The result part of a row for a hunt that raised ``exc``."""
    return {"outcome": "failed", "cause": "error", "message": one_line(exc), "wall_time_s": wall_time}


def one_line(exc: BaseException) -> str:
    """``exc`` named, on one line of at most 500 characters."""
    return " ".join(f"{type(exc).__name__}: {exc}".split())[:500]


@dataclass(frozen=True)
class Tasks:
    """A sweep's hunts not yet in ``done``: every (strategy, attacker, belief, hunt) in hunt-major order, made one
    at a time as they are iterated (never the whole list in memory); ``len`` is how many are left."""

    strategies: tuple[str, ...]
    hunts: int
    seed: int
    ranges: dict
    done: frozenset
    attackers: tuple[str, ...]
    beliefs: tuple[str, ...]

    def __iter__(self) -> Iterator[Hunt]:
        for i in range(self.hunts):
            for s in self.strategies:
                for a in self.attackers:
                    for b in self.beliefs:
                        if (s, a, b, self.seed, i) not in self.done:
                            yield Hunt(s, self.seed, i, self.ranges, attacker=a, belief=b)

    def __len__(self) -> int:
        finished = sum(
            1
            for s, a, b, seed, i in self.done
            if seed == self.seed
            and 0 <= i < self.hunts
            and s in self.strategies
            and a in self.attackers
            and b in self.beliefs
        )
        return total_tasks(self.strategies, self.hunts, self.attackers, self.beliefs) - finished


def total_tasks(strategies: Sequence[str], hunts: int, attackers: Sequence[str], beliefs: Sequence[str]) -> int:
    """The hunts of a sweep, finished or not: strategies × attackers × beliefs × hunts; more than MAX_TASKS is
    refused (:class:`SettingError` naming ``hunts``)."""
    total = len(strategies) * len(attackers) * len(beliefs) * hunts
    if total > MAX_TASKS:
        raise SettingError(
            "hunts",
            f"{len(strategies)} strategies x {len(attackers)} attackers x {len(beliefs)} "
            f"beliefs x {hunts} hunts = {total} hunts: at most {MAX_TASKS} in one sweep "
            "(docs/robustness.md, Limits); give fewer hunts, or split the sweep",
        )
    return total


def check_buildable(strategies: Sequence[str], attackers: Sequence[str], seed: int, ranges: ScenarioRanges) -> None:
    """Each strategy's controller and each attacker's behaviour built once, on the sweep's first hunt, before any
    hunt runs: one that cannot be built (a damaged policy file, ...) would fail every hunt alike, so it is refused
    (:class:`SettingError` naming ``strategies`` or ``attackers``) rather than stored as every hunt's error, and not
    loaded once per hunt to find out."""
    scenario = sweep_scenario(seed, 0, ranges)
    for field, names, build in (
        ("strategies", strategies, lambda name: ControllerSpec.parse(name).build(scenario)),
        ("attackers", attackers, lambda name: make_behaviour(with_behaviour(scenario, name), np.random.default_rng(0))),
    ):
        for name in names:
            try:
                build(name)
            except MpcHuntError as exc:
                raise SettingError(field, f"{name} cannot be built: {exc}") from None


def tasks(
    strategies: list[str],
    hunts: int,
    seed: int,
    ranges: ScenarioRanges,
    done: set,
    attackers: Sequence[str] = (DEFAULT_BEHAVIOUR,),
    beliefs: Sequence[str] = (EXACT,),
) -> Tasks:
    """Every (strategy, attacker, belief, hunt) not yet in ``done`` (keys (strategy, attacker, belief, seed,
    index)), hunt-major order, made as iterated; ``beliefs`` are labels (:meth:`Belief.label`). A sweep of more
    than MAX_TASKS hunts in all is refused before any."""
    total_tasks(strategies, hunts, attackers, beliefs)
    return Tasks(
        tuple(strategies), hunts, seed, ranges_to_dict(ranges), frozenset(done), tuple(attackers), tuple(beliefs)
    )


def run_local(
    todo: Iterable, workers: int | None = None, work: Callable[[Any], dict] | None = None
) -> Generator[dict, None, None]:
    """Rows as hunts finish, on local worker processes (:func:`mpc_hunt.workers.run_local`); stops cleanly when the
    caller stops iterating. ``work`` (a module-level function, so that it pickles) turns a task into its row;
    without it, the hunts run in :func:`batches` (:func:`run_hunts`)."""
    try:
        if work is not None:
            yield from workers_run_local(todo, work, workers)
            return
        for rows in workers_run_local(batches(todo), run_hunts, workers):
            yield from rows
    except WorkersDied as exc:
        raise SweepStopped(str(exc)) from None


def connect_dask(scheduler: str):
    """A client of the Dask scheduler at the address ``scheduler``; a :class:`SettingError` naming it if Dask is
    missing or the scheduler cannot be reached."""
    try:
        from distributed import Client
    except ImportError:
        raise SettingError("scheduler", 'needs Dask: pip install "mpc-hunt[dask]"') from None
    try:
        return Client(scheduler, timeout="10s")
    except Exception as exc:  # noqa: BLE001 - a malformed address raises ValueError or TypeError, not OSError
        raise SettingError(
            "scheduler",
            f"cannot connect to {scheduler} ({one_line(exc)}); give the scheduler's address, e.g. tcp://127.0.0.1:8786",
        ) from None


def run_dask(todo: Iterable[Hunt], client) -> Generator[dict, None, None]:
    """Rows as hunts finish, on the Dask cluster of ``client`` (:func:`connect_dask`), which it closes. At most
    DASK_IN_FLIGHT batches of hunts (:func:`batches`) are handed over at once; ``todo`` is read as they finish."""
    from distributed import KilledWorker, as_completed

    address = client.scheduler.address
    pending = batches(todo)
    task_of: dict = {}
    finishing = as_completed()

    def hand_over(n: int) -> None:
        for batch in itertools.islice(pending, n):
            future = client.submit(run_hunts, batch, pure=False)
            task_of[future.key] = (future, batch)
            finishing.add(future)

    with client:
        try:
            hand_over(DASK_IN_FLIGHT)
            for future in finishing:
                try:
                    rows = future.result()
                except KilledWorker as exc:  # the workers running it died too often: suspect its hunts
                    rows = [_drawn(task)[1] | _error(exc, None) for task in task_of[future.key][1]]
                except MpcHuntError:  # the scenario could not be drawn: the ranges are at fault
                    raise
                except Exception as exc:  # noqa: BLE001 - anything else is the cluster failing, not a hunt
                    raise SweepStopped(f"the Dask scheduler at {address}: {one_line(exc)}") from None
                del task_of[future.key]
                hand_over(1)
                yield from rows
        finally:
            client.cancel([future for future, _ in task_of.values()])

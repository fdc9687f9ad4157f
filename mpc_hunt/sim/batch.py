"""The closed loop over a batch of hunts at once: the world's rules compiled, each hunt's its own.

A batch is many scenarios stepped together: positions, obstacles and parameters as arrays with a leading hunt
axis, padded to the batch's largest team and obstacle set (``n`` and ``m`` count each hunt's own). Each step,
every running hunt's controller commands (the hunts of a batched controller,
:class:`~mpc_hunt.control.controller.BatchedController`, in one call of its compiled rule; any other controller
hunt by hunt), the attackers move (the compiled behaviours in one call, :mod:`mpc_hunt.world.behaviours.batch`;
the others hunt by hunt), and the world steps and judges every hunt in one call
(:func:`mpc_hunt.sim.world_step.step_batch`). A hunt that ends stops there while the others go on. Every rule
reads one hunt's rows only, in the same order of operations whatever the batch, so a hunt's trajectory is the
same bits alone (a batch of one: :func:`mpc_hunt.sim.simulator.simulate`) and in any batch.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from mpc_hunt.control.controller import BatchRule, Controller, Observation
from mpc_hunt.errors import OptionError
from mpc_hunt.sim.collector import collecting_between_steps
from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.sim.hunt_summary import hunt_result
from mpc_hunt.sim.solve_record import SolveRecord
from mpc_hunt.sim.world_step import ENDS, RUNNING, step_batch, steps
from mpc_hunt.solving.step_timing import stolen
from mpc_hunt.world.behaviours import make_behaviour
from mpc_hunt.world.behaviours.base import Behaviour
from mpc_hunt.world.behaviours.batch import CODES, PYTHON, attacker_velocities
from mpc_hunt.world.behaviours.minimax import DIRECTIONS
from mpc_hunt.world.behaviours.noisy import draw
from mpc_hunt.world.packed import SIZE, T
from mpc_hunt.world.scenario import Scenario


class Batch:
    """The world of a batch of hunts as arrays (the module's docstring); the state moves in place. ``N`` and ``M``
    (default: the largest team and obstacle set of ``scenarios``) size the padded arrays; a slot takes another
    hunt with :meth:`put`."""

    def __init__(
        self,
        scenarios: Sequence[Scenario],
        behaviours: Sequence[Behaviour | None],
        N: int | None = None,
        M: int | None = None,
    ):
        B = len(scenarios)
        N = max(len(s.defenders) for s in scenarios) if N is None else N
        M = max(len(s.obstacles) for s in scenarios) if M is None else M
        self.scenarios = list(scenarios)
        self.n, self.m = np.zeros(B, dtype=np.int64), np.zeros(B, dtype=np.int64)
        self.p_a, self.previous = np.zeros((B, 2)), np.zeros((B, 2))
        self.p_d, self.speeds, self.fails_at = np.zeros((B, N, 2)), np.ones((B, N)), np.full((B, N), np.inf)
        self.centres, self.radii = np.zeros((B, M, 2)), np.zeros((B, M))
        self.prm = np.empty((B, SIZE))
        self.codes = np.zeros(B, dtype=np.int64)
        self.max_steps, self.hold = np.zeros(B, dtype=np.int64), np.zeros(B, dtype=np.int64)
        for b, (scenario, given) in enumerate(zip(scenarios, behaviours)):
            self.put(b, scenario, given is not None)

    def put(self, b: int, s: Scenario, moved_from_python: bool = False) -> None:
        """Slot b takes the hunt of ``s`` at its start (its attacker moved from Python if ``moved_from_python``,
        else by its behaviour's compiled rule where there is one)."""
        n, m = len(s.defenders), len(s.obstacles)
        self.scenarios[b] = s
        self.n[b], self.m[b] = n, m
        self.p_a[b], self.previous[b] = s.attacker.start, np.nan  # no last position before the first step
        self.p_d[b] = 0.0
        self.p_d[b, :n], self.speeds[b, :n] = s.defender_starts, s.defender_max_speeds
        self.fails_at[b] = np.inf
        self.fails_at[b, :n] = [np.inf if d.fails_at is None else d.fails_at for d in s.defenders]
        self.centres[b], self.radii[b] = 0.0, 0.0
        self.centres[b, :m], self.radii[b, :m] = s.obstacle_centres, s.obstacle_radii
        self.prm[b] = s.packed
        self.codes[b] = PYTHON if moved_from_python else CODES.get(s.attacker.behaviour, PYTHON)
        self.max_steps[b], self.hold[b] = steps(s)

    def __len__(self) -> int:
        return len(self.scenarios)

    def failed(self, b: int, k: int) -> np.ndarray:
        """Hunt b's defenders stopped for good at step ``k``."""
        return k * self.prm[b, T] >= self.fails_at[b, : self.n[b]]

    def observation(self, b: int, k: int) -> Observation:
        """What hunt b's defenders know at its step ``k``."""
        stopped, n = self.failed(b, k), self.n[b]
        previous = None if k == 0 else self.previous[b].copy()
        return Observation(k * float(self.prm[b, T]), self.p_a[b].copy(), previous, self.p_d[b, :n].copy(),
                           stopped if stopped.any() else None)  # fmt: skip


class Commands:
    """One step's commands for a batch: velocities (B, N, 2), capture-stage flags (B, N), intercepts (B, N, 2)."""

    def __init__(self, B: int, N: int):
        self.velocities = np.zeros((B, N, 2))
        self.capture_stage = np.zeros((B, N), dtype=bool)
        self.intercepts = np.full((B, N, 2), np.nan)


class Paths:
    """Everybody's positions (steps 0..k), and each step's capture-stage flags and intercepts, of a batch's hunts:
    arrays grown as the hunts go on (doubled when full), since a hunt's time limit may allow far more steps than it
    takes."""

    def __init__(self, p_a: np.ndarray, p_d: np.ndarray, room: int = 1024):
        B, N = p_d.shape[:2]
        self.attacker, self.defenders = np.full((B, room + 1, 2), np.nan), np.full((B, room + 1, N, 2), np.nan)
        self.stages, self.intercepts = np.zeros((B, room, N), dtype=bool), np.full((B, room, N, 2), np.nan)
        self.attacker[:, 0], self.defenders[:, 0] = p_a, p_d

    def record(self, k: int, running: np.ndarray, p_a: np.ndarray, p_d: np.ndarray, out: Commands) -> None:
        """Step k of the ``running`` hunts: the positions it led to, its commands' flags and intercepts."""
        if k == self.stages.shape[1]:
            self.attacker, self.defenders = _doubled(self.attacker, np.nan), _doubled(self.defenders, np.nan)
            self.stages, self.intercepts = _doubled(self.stages, False), _doubled(self.intercepts, np.nan)
        self.attacker[running, k + 1], self.defenders[running, k + 1] = p_a[running], p_d[running]
        self.stages[running, k], self.intercepts[running, k] = out.capture_stage[running], out.intercepts[running]


def _doubled(array: np.ndarray, fill) -> np.ndarray:
    """``array`` with as many more steps (axis 1) again, filled with ``fill``."""
    return np.concatenate([array, np.full_like(array[:, -array.shape[1] :], fill)], axis=1)


def simulate_batch(
    scenarios: Sequence[Scenario],
    controllers: Sequence[Controller],
    rngs: Sequence[np.random.Generator],
    *,
    behaviours: Sequence[Behaviour | None] | None = None,
    until: Callable[[Observation], bool] | None = None,
    progress: Callable[[float], None] | None = None,
    deadline: float | None = None,
    abandon_after: float | None = None,
) -> list[HuntResult]:
    """Run the hunts of ``scenarios`` together, hunt b by ``controllers[b]``, its attacker by ``behaviours[b]``
    if given, else by its scenario's behaviour drawing from ``rngs[b]``; :func:`~mpc_hunt.sim.simulator.simulate`
    says what ``until``, ``progress`` (the simulated time of the batch's step), ``deadline`` and
    ``abandon_after`` do to each hunt."""
    B = len(scenarios)
    if B == 0 or len(controllers) != B or len(rngs) != B or (behaviours is not None and len(behaviours) != B):
        raise OptionError(
            f"scenarios: a batch of {B} hunts with {len(controllers)} controllers and {len(rngs)} generators; give "
            "at least one hunt, and a controller and a generator (and a behaviour, if any) for each"
        )
    given = list(behaviours) if behaviours is not None else [None] * B
    batch = Batch(scenarios, given)
    moved_by: dict[int, Behaviour] = {  # the attackers moved from Python, hunt by hunt
        b: given[b] or make_behaviour(scenarios[b], rngs[b]) for b in range(B) if batch.codes[b] == PYTHON
    }
    noisy = [b for b in range(B) if batch.codes[b] == CODES["noisy"]]
    N, K = batch.p_d.shape[1], int(batch.max_steps.max())
    paths = Paths(batch.p_a, batch.p_d)
    records = [SolveRecord() for _ in range(B)]
    running = np.ones(B, dtype=bool)
    taken = np.zeros(B, dtype=np.int64)  # steps each hunt took
    held = np.zeros(B, dtype=np.int64)
    status = np.zeros(B, dtype=np.int64)
    termination = ["time_limit"] * B
    draws = np.zeros((B, 2))
    attacker_v = np.zeros((B, 2))
    batched = batched_groups(controllers)
    one_by_one = [b for b in range(B) if b not in batched.members]
    with collecting_between_steps() as collect:  # (mpc_hunt.sim.collector)
        for k in range(K):
            running &= k < batch.max_steps
            if not running.any():
                break
            out = Commands(B, N)
            if until is not None:
                for b in np.flatnonzero(running).tolist():
                    if until(batch.observation(b, k)):
                        termination[b], running[b] = "stopped", False
            for b in one_by_one:
                if not running[b]:
                    continue
                before = stolen() if deadline is not None else 0.0
                cmd = controllers[b].command(batch.observation(b, k))
                records[b].add(cmd, stolen() - before if deadline is not None else 0.0)
                n = batch.n[b]
                out.velocities[b, :n], out.capture_stage[b, :n], out.intercepts[b, :n] = (
                    cmd.velocities,
                    cmd.capture_stage,
                    cmd.intercepts,
                )
            failed = k * batch.prm[:, T, None] >= batch.fails_at
            for rule, mine in batched.groups:
                rule.commands(
                    mine & running,
                    batch.p_a,
                    batch.previous,
                    batch.p_d,
                    batch.n,
                    failed,
                    out.velocities,
                    out.capture_stage,
                    out.intercepts,
                )
            for b in noisy:
                if running[b]:
                    draws[b] = draw(rngs[b])
            attacker_velocities(
                batch.codes,
                running,
                batch.p_a,
                batch.p_d,
                batch.n,
                batch.speeds,
                batch.centres,
                batch.radii,
                batch.m,
                batch.prm,
                draws,
                DIRECTIONS,
                attacker_v,
            )
            for b in moved_by:
                if running[b]:
                    attacker_v[b] = moved_by[b].velocity(batch.p_a[b].copy(), batch.p_d[b, : batch.n[b]].copy())
            batch.previous[running] = batch.p_a[running]
            step_batch(
                running,
                taken,
                batch.p_a,
                batch.p_d,
                batch.n,
                out.velocities,
                attacker_v,
                batch.fails_at,
                batch.speeds,
                batch.centres,
                batch.radii,
                batch.m,
                batch.prm,
                held,
                batch.hold,
                status,
            )
            paths.record(k, running, batch.p_a, batch.p_d, out)
            taken[running] = k + 1
            collect()  # the commands sent: the collector's work of this step, outside its solves' time
            if progress is not None:
                progress((k + 1) * float(batch.prm[0, T]))
            for b in np.flatnonzero(running & (status != RUNNING)).tolist():
                termination[b], running[b] = ENDS[int(status[b])], False
            if abandon_after is not None:
                for b in one_by_one:
                    if running[b] and records[b].streak * batch.prm[b, T] >= abandon_after - 1e-9:
                        termination[b], running[b] = "abandoned", False
    results = []
    for b in range(B):
        k, n = int(taken[b]), int(batch.n[b])
        result = hunt_result(
            scenarios[b],
            controllers[b],
            paths.attacker[b, : k + 1],
            paths.defenders[b, : k + 1, :n],
            paths.stages[b, :k, :n],
            paths.intercepts[b, :k, :n],
            termination[b],
            int(held[b]),
        )
        results.append(records[b].into(result, deadline))
    return results


class Groups:
    """The batched controllers of a batch of ``B`` hunts: one rule per kind, with the mask of the hunts it commands;
    ``batched``, the hunts any commands."""

    def __init__(self, groups: list[tuple[BatchRule, np.ndarray]], B: int):
        self.groups = groups
        self.batched = np.zeros(B, dtype=bool)
        for _, mine in groups:
            self.batched |= mine
        self.members = set(np.flatnonzero(self.batched).tolist())


def batched_groups(controllers: Sequence[Controller | None]) -> Groups:
    """Hunts whose controllers are of one batched kind (a ``batched`` rule) share one call a step."""
    kinds = {type(c) for c in controllers if callable(getattr(type(c), "batched", None))}
    groups = []
    for kind in kinds:
        mine = np.array([type(c) is kind for c in controllers])
        groups.append((getattr(kind, "batched")([c if type(c) is kind else None for c in controllers]), mine))
    return Groups(groups, len(controllers))

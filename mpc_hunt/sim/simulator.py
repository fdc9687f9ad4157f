"""The closed loop: the world integrates Eqs. 1–2; the controller only observes and commands.

Each step of length T: the controller sees the state at t; every defender moves
at its commanded velocity capped at its max speed (Eq. 1); the attacker moves
as its scenario's behaviour says (:mod:`mpc_hunt.world.behaviours`; the
paper's, its resultant of Eq. 9 plus its nominal intent capped at its max
speed, Eq. 2, by default), both evaluated at the state at t (explicit Euler).
The controller never learns the behaviour: it was built on a belief. A hunt ends when
the success test (Eqs. 4–5) has held for ``hold_time``, at ``time_limit``, or
if the state stops being finite, when the attacker leaves the scenario's arena
(if it has one), or when ``until`` (if given) says so of an observation. The
same scenario always gives the same result. Python's garbage collector is held off while the hunt runs and
collects between steps, once a step's command is applied (:mod:`mpc_hunt.sim.collector`), as a robot's loop
collects in its idle time.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Callable

import numpy as np

from mpc_hunt.capture.evaluator import VIOLATION_NAMES
from mpc_hunt.control.controller import Command, Controller, Observation
from mpc_hunt.control.recommended import PAPER
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.errors import OptionError
from mpc_hunt.sim.collector import collecting_between_steps
from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.sim.world_step import moved, standing, steps
from mpc_hunt.solving.step_timing import stolen
from mpc_hunt.world.arena import margin
from mpc_hunt.world.behaviours import make_behaviour
from mpc_hunt.world.behaviours.base import Behaviour
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.hunting_circle import success_test
from mpc_hunt.world.scenario import Scenario

DEFAULT_SEED = 0


def check_seconds(name: str, value: object, error: type[Exception] = OptionError) -> None:
    """Refuse ``value`` for the setting ``name`` unless it is None or a positive, finite number of seconds."""
    if value is not None and not (
        isinstance(value, (int, float)) and not isinstance(value, bool) and 0 < value < float("inf")
    ):
        raise error(f"{name}: a positive, finite number of seconds or None, got {value!r}")


def simulate(
    scenario: Scenario,
    controller: Controller | None = None,
    *,
    prediction: bool = True,
    until: Callable[[Observation], bool] | None = None,
    progress: Callable[[float], None] | None = None,
    rng: np.random.Generator | None = None,
    behaviour: Behaviour | None = None,
    deadline: float | None = None,
    abandon_after: float | None = None,
) -> HuntResult:
    """Run one hunt. Without a controller, the paper's strategy as published (its capture stage
    :data:`~mpc_hunt.control.recommended.PAPER`, the one-step NLP on IPOPT) built by its spec on the defenders'
    default belief (:meth:`ControllerSpec.build <mpc_hunt.control.spec.ControllerSpec.build>`), never on the
    world's behaviour.

    ``rng`` draws whatever the attacker's behaviour draws (``noisy``); without one, a generator seeded
    with ``DEFAULT_SEED``, so the same scenario always gives the same hunt. ``behaviour`` moves the attacker
    instead of the scenario's (a policy under training, say).

    ``until`` stops the run (termination ``"stopped"``) before the first
    observation it returns true for; that observation is the last recorded state.
    ``progress``, if given, is called with the simulated time after each step. ``deadline`` (s), if given, is
    the capture stage's budget a step is counted against (:meth:`HuntResult.deadline_misses`), beside T; each
    step's time the hypervisor took from the machine is then read around it (``stolen_times``,
    :func:`~mpc_hunt.solving.step_timing.stolen`).
    ``abandon_after`` (s), if given, stops the run (termination ``"abandoned"``) once the capture stage's solves
    have failed for that long in a row: the hunt is then the fallback's, not the capture stage's.
    """
    check_seconds("deadline", deadline)
    check_seconds("abandon_after", abandon_after)
    controller = controller or ControllerSpec("paper", options={"prediction": prediction}, stage=PAPER).build(scenario)
    if behaviour is None:
        behaviour = make_behaviour(scenario, np.random.default_rng(DEFAULT_SEED) if rng is None else rng)
    T = scenario.hunt.time_step
    max_steps, hold_steps = steps(scenario)

    p_a = np.array(scenario.attacker.start, dtype=float)
    p_d = scenario.defender_starts.copy()
    attacker_path, defender_paths, stages, intercepts = [p_a.copy()], [p_d.copy()], [], []
    record = _SolveRecord()
    held = 0
    previous = None
    termination = "time_limit"
    with collecting_between_steps() as collect:  # (mpc_hunt.sim.collector)
        for step in range(max_steps):
            stopped = scenario.failed(step * T)  # robots that failed stand still for good
            observation = Observation(step * T, p_a.copy(), previous, p_d.copy(), stopped if stopped.any() else None)
            if until is not None and until(observation):
                termination = "stopped"
                break
            before = stolen() if deadline is not None else 0.0
            cmd = controller.command(observation)
            record.add(cmd, stolen() - before if deadline is not None else 0.0)
            velocity = behaviour.velocity(p_a, p_d)
            previous = p_a.copy()
            p_a, p_d = moved(scenario, p_a, p_d, cmd.velocities, velocity, stopped)
            attacker_path.append(p_a.copy())
            defender_paths.append(p_d.copy())
            stages.append(cmd.capture_stage)
            intercepts.append(cmd.intercepts)
            collect()  # the command sent: the collector's work of this step, outside its solve's time
            ended, held = standing(scenario, p_a, p_d, held, hold_steps)
            if progress is not None:
                progress((step + 1) * T)
            if ended is not None:
                termination = ended
                break
            if abandon_after is not None and record.streak * T >= abandon_after - 1e-9:
                termination = "abandoned"
                break
    result = _result(
        scenario,
        controller,
        np.array(attacker_path),
        np.array(defender_paths),
        np.array(stages),
        np.array(intercepts),
        termination,
        held,
    )
    return record.into(result, deadline)


class _SolveRecord:
    """Per capture-stage solve: its time, iterations and set-up, the status, the certificate, the applied plan's
    true violations; the failed solves, the current and the longest run of them, and the commands that fell
    back."""

    def __init__(self):
        self.times, self.iterations = [], []
        self.setups, self.overheads, self.off_cpu, self.stolen, self.statuses = [], [], [], [], []
        self.certificates, self.violations = [], []
        self.violating = self.failed = self.streak = self.longest_streak = self.fallbacks = 0

    def add(self, cmd: Command, stolen: float = 0.0) -> None:
        """A step's command: its solve, if it made one (``stolen`` s taken by the hypervisor meanwhile), and
        whether it fell back."""
        solution, fallback = cmd.solution, cmd.fallback
        self.fallbacks += fallback
        if solution is None:
            return
        self.times.append(solution.solve_time)
        self.iterations.append(solution.iterations)
        self.failed += not solution.success
        self.streak = 0 if solution.success else self.streak + 1
        self.longest_streak = max(self.longest_streak, self.streak)
        self.violating += solution.success and fallback  # usable, yet not applied: beyond the tolerance
        self.setups.append(solution.setup_time)
        self.overheads.append(solution.overhead_time)
        self.off_cpu.append(solution.off_cpu_time)
        self.stolen.append(stolen)
        self.statuses.append(solution.status.value)
        c = solution.certificate
        self.certificates.append((np.nan,) * 3 if c is None else (c.primal_residual, c.dual_residual, c.duality_gap))
        v = solution.violation
        self.violations.append(
            (np.nan,) * len(VIOLATION_NAMES) if v is None or fallback else tuple(v[name] for name in VIOLATION_NAMES)
        )

    def into(self, result: HuntResult, deadline: float | None) -> HuntResult:
        return replace(
            result,
            setup_times=np.array(self.setups),
            overhead_times=np.array(self.overheads),
            off_cpu_times=np.array(self.off_cpu),
            stolen_times=np.array(self.stolen),
            solve_statuses=tuple(self.statuses),
            certificates=np.array(self.certificates, dtype=float).reshape(-1, 3),
            applied_violations=np.array(self.violations, dtype=float).reshape(-1, len(VIOLATION_NAMES)),
            deadline=deadline,
            violating_plans=self.violating,
            solve_times=np.array(self.times),
            solve_iterations=np.array(self.iterations, dtype=int),
            failed_solves=self.failed,
            fallbacks=self.fallbacks,
            longest_failure_streak=self.longest_streak,
        )


def _result(
    scenario,
    controller,
    attacker,
    defenders,
    stages,
    intercepts,
    termination,
    held,
) -> HuntResult:
    hunt = scenario.hunt
    T = hunt.time_step
    K = len(attacker) - 1
    n = defenders.shape[1]
    finite = np.all(np.isfinite(attacker), axis=1) & np.all(np.isfinite(defenders), axis=(1, 2))
    a, d = attacker[finite], defenders[finite]
    centres, radii = scenario.obstacle_centres, scenario.obstacle_radii
    steps = np.diff(d, axis=0)
    path_lengths = norm(steps).sum(axis=0) if len(d) > 1 else np.zeros(n)
    final = success_test(a[-1], d[-1], centres, radii, hunt.hunt_radius, hunt.centre_tolerance)
    clearance = attacker_clearance = None
    # capture stage or not: the least clearance its commands led to
    by_stage: dict[bool, float | None] = {True: None, False: None}
    if len(radii):
        clearance = float(np.min(norm(d[:, :, None, :] - centres[None, None]) - radii))
        attacker_clearance = float(np.min(norm(a[:, None, :] - centres[None]) - radii))
        moved = finite[1:]  # position k + 1 is where the command of step k led
        reached = np.min(norm(defenders[1:][moved][:, :, None, :] - centres[None, None]) - radii, axis=2)
        stage = stages.reshape(K, n)[moved]
        for capture in by_stage:
            if np.any(stage == capture):
                by_stage[capture] = float(np.min(reached[stage == capture]))
    separation = None
    if n > 1:
        gaps = norm(d[:, :, None, :] - d[:, None, :, :])
        gaps[:, np.arange(n), np.arange(n)] = np.inf
        separation = float(gaps.min())
    captured = termination == "captured"
    return HuntResult(
        scenario=scenario.name,
        controller=controller.describe(),
        times=np.arange(K + 1) * T,
        attacker=attacker,
        defenders=defenders,
        capture_stage=stages.reshape(K, n),
        intercepts=intercepts.reshape(K, n, 2),
        termination=termination,
        captured=captured,
        capture_time=(K - held + 1) * T if captured else None,
        path_lengths=path_lengths,
        final_hunting_radius=final.radius,
        min_obstacle_clearance=clearance,
        min_defender_separation=separation,
        min_attacker_distance=float(np.min(norm(a[:, None, :] - d))),
        attacker_min_obstacle_clearance=attacker_clearance,
        approach_min_obstacle_clearance=by_stage[False],
        capture_min_obstacle_clearance=by_stage[True],
        min_arena_margin=None if scenario.arena is None else float(np.min(margin(scenario.arena, d))),
    )

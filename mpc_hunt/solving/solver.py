"""One solver object for every formulation × backend.

``CaptureSolver`` pairs a formulation with a persistent backend, both found by
name in :mod:`mpc_hunt.solving.registry` once, when it is made. It keeps only
solver state: the backend's set-up structures and the steps it built. A solve
is one-shot: the plan and the duals to start from are the caller's. The
receding-horizon memory (the plan applied, shifted one step, and the duals of a
usable solve, while the same defenders are controlled) is
:class:`~mpc_hunt.solving.mpc.CaptureMPC`'s, which a controller holds.

A stage-form pair (kind ``ocp-qp``: ``rti`` or ``stage-sqp`` on ``hpipm`` or
``hpipm-codegen``), whose backend closes the step into one Function, is solved
on a :class:`~mpc_hunt.solving.step.CaptureStep`, one per structure: the posed
problem is written into the step's arrays, the step runs, the plan is read
back. Its plans are the formulation's own path's (``loop=False``) to the bit.
The same solver hands a control loop that step (:meth:`CaptureSolver.step_for`) and
writes it as C for a robot's board (:meth:`CaptureSolver.export`).
``solve`` is the one-shot, cold form with a fresh solver.
"""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from mpc_hunt.capture.certificate import Certificate
from mpc_hunt.capture.evaluator import solve_scores
from mpc_hunt.capture.iteration import QPIteration
from mpc_hunt.capture.problem import OBJECTIVES, CaptureProblem
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.capture.structure import Structure
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.solving import registry
from mpc_hunt.solving.step import CaptureStep
from mpc_hunt.solving.step_timing import timed_step
from mpc_hunt.solving.team_step import TeamStep


class CaptureSolver:
    """A formulation and its backend, kept between solves.

    ``formulation`` is always named (a capture stage's defaults are the controller spec's,
    :mod:`mpc_hunt.control.recommended`); ``backend`` None is the formulation's own default.
    ``time_limit`` (seconds) is handed to the solver as its own limit,
    ``accuracy`` (``default``, ``high``, ``low``) picks its tolerances, other
    keywords are the backend's options. ``raise_on_failure`` turns a failed
    status into :class:`~mpc_hunt.errors.SolverError`. The evaluator scores
    every plan, or with ``score=False`` only a failed solve's (what a
    controller's fallback reads); its time is ``score_time``, apart. ``formulation_options`` go to the
    formulation (``distributed``: ``rounds``, ``scheme``). ``loop``
    (default: whether the pair closes its step into one Function) solves on
    its control step (:meth:`step_for`); ``loop=False`` runs the formulation's own path.
    """

    def __init__(
        self,
        formulation: str,
        backend: str | None = None,
        *,
        time_limit: float | None = None,
        accuracy: str = "default",
        raise_on_failure: bool = False,
        score: bool = True,
        loop: bool | None = None,
        formulation_options: dict | None = None,
        **backend_options,
    ):
        pair = registry.resolve(formulation, backend)
        try:
            self.formulation = pair.formulation(**(formulation_options or {}))
        except (TypeError, ValueError) as exc:
            raise MpcHuntError(f"formulation_options: {exc}") from None
        self.backend = pair.backend(time_limit=time_limit, accuracy=accuracy, **backend_options)
        self.stage_form = pair.closes_step
        if loop and not self.stage_form:
            raise MpcHuntError(registry.stage_form_message(formulation))
        self.on_steps = self.stage_form if loop is None else loop
        self.raise_on_failure = raise_on_failure
        self.score = score
        self._refusals = {
            objective: registry.objective_refusal(formulation, pair.backend_name, objective) for objective in OBJECTIVES
        }  # why an objective cannot be solved (None: it can)
        self._prepared: set[Structure] = set()  # structures whose model this solver has built
        self._steps: dict[Structure, CaptureStep | TeamStep] = {}

    def step_for(self, problem: CaptureProblem) -> CaptureStep | TeamStep:
        """The control loop's step for ``problem``'s structure, built on its first problem and kept: a
        :class:`TeamStep` (one step per robot) for a formulation that plans robot by robot."""
        if not self.stage_form:
            raise MpcHuntError(registry.stage_form_message(self.formulation.name))
        refused = self._refusal(problem)
        if refused:
            raise MpcHuntError(refused)
        step = self._steps.get(problem.structure)
        if step is None:
            kind = TeamStep if self.formulation.per_robot else CaptureStep
            step = self._steps[problem.structure] = kind(problem, self.formulation, self.backend)
        return step

    def solve(
        self, problem: CaptureProblem, warm_plan: np.ndarray | None = None, duals: WarmStart | None = None
    ) -> Solution:
        """Solve ``problem``, from ``warm_plan`` (N, n, 2) if given, else cold from every defender held, and from
        ``duals`` (an earlier solution's of a problem with the same signature) if given; a stage-form pair on its
        step reads no duals."""
        refused = self._refusal(problem)
        if refused:
            return self._finish(
                Solution(
                    status=Status.ERROR, formulation=self.formulation.name, backend=self.backend.name, message=refused
                )
            )
        if self.on_steps:
            return self._finish(self._step(problem, warm_plan))
        t0 = time.perf_counter()
        names: dict[str, Any] = dict(formulation=self.formulation.name, backend=self.backend.name)
        try:
            build_time = 0.0
            if problem.structure not in self._prepared:  # set-up time is counted once per structure
                self.formulation.prepare(problem.structure)
                self._prepared.add(problem.structure)
                build_time = time.perf_counter() - t0
            with self.backend.step_within(time.perf_counter()), timed_step() as timing:  # the limit: all its QPs'
                result = self.formulation.solve(problem, self.backend, warm_plan, duals)
        except (RuntimeError, ValueError, ArithmeticError) as exc:
            message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            solution = Solution(status=Status.ERROR, message=message, overhead_time=time.perf_counter() - t0, **names)
            return self._finish(solution)
        if result.plan is not None and not np.all(np.isfinite(result.plan)):
            result = replace(result, status=Status.ERROR, plan=None, message=f"{result.message} (non-finite plan)")
        scores = solve_scores(problem, result.plan, result.status, self.score)
        setup_time = result.setup_time + build_time
        overhead = time.perf_counter() - t0 - result.solver_time - setup_time - scores.get("score_time", 0.0)
        return self._finish(
            replace(
                result,
                **names,
                **scores,
                setup_time=setup_time,
                overhead_time=max(overhead, 0.0),
                off_cpu_time=timing.off_cpu,
                warm_started=warm_plan is not None,
            )
        )

    def _step(self, problem: CaptureProblem, warm_plan: np.ndarray | None) -> Solution:
        """One call of the structure's :class:`CaptureStep`: the problem written into its arrays, the plan read
        back. A failed step's plan is the last usable one the step kept (its reference if none)."""
        t0 = time.perf_counter()
        built = problem.structure in self._steps
        step = self.step_for(problem)
        setup_time = 0.0 if built else time.perf_counter() - t0
        step.load(problem, warm_plan)
        t1 = time.perf_counter()
        with timed_step() as timing:
            status = step.step()
        solver_time = time.perf_counter() - t1 - step.setup_time  # a rebuild for a new cap is a set-up
        setup_time += step.setup_time
        plan = problem.plan_with(step.plan)
        scores = solve_scores(problem, plan, status, self.score)
        overhead = time.perf_counter() - t0 - solver_time - setup_time - scores.get("score_time", 0.0)
        return Solution(
            status=status,
            message=step.message,
            formulation=self.formulation.name,
            backend=self.backend.name,
            x=step.plan.reshape(-1).copy(),
            plan=plan,
            formulation_objective=float(step.objective[0])
            if status.usable and np.isfinite(step.objective[0])
            else None,
            solver_time=solver_time,
            overhead_time=max(overhead, 0.0),
            setup_time=setup_time,
            off_cpu_time=timing.off_cpu,
            iterations=step.iterations,
            warm_started=warm_plan is not None,
            extras=step.extras,
            certificate=step_certificate(step),
            **scores,
        )

    def export(self, folder: Path, problem: CaptureProblem, robot: int = 0, target: str = "host") -> list[Path]:
        """The step of ``problem``'s structure, as this solver set it up, written as C sources for a robot's board
        (:mod:`mpc_hunt.solving.export`); returns the files written. For a formulation that plans robot by robot,
        the step of planned defender ``robot`` (0-based), its inputs from the team held where it stands. ``target``:
        the CPU its Makefile builds for (:data:`mpc_hunt.solving.export.TARGETS`)."""
        from mpc_hunt.solving.export import check_export, write_step

        if not self.stage_form:  # (before the formulation's iteration, which only a stage-form one has)
            raise MpcHuntError(registry.stage_form_message(self.formulation.name))
        iteration: QPIteration = getattr(self.formulation, "iteration")
        check_export(target, self.backend.exports, iteration)

        step = self.step_for(problem)
        step.load(problem)
        if isinstance(step, TeamStep):
            if not 0 <= robot < problem.structure.planned:
                raise MpcHuntError(
                    f"robot: {problem.structure.planned} defenders are planned (index 0 to "
                    f"{problem.structure.planned - 1}), not {robot}"
                )
            step = step.robot(robot)
        theta, reference = step.theta.copy(), step.reference.reshape(-1).copy()  # the step moves its reference
        if not step.step().usable:
            raise MpcHuntError(
                f"the problem's {self.formulation.name} step failed in Python ({step.message}): "
                "nothing to compare the C step with"
            )
        return write_step(
            Path(folder),
            getattr(self.backend, "generated_step")(step.step_function),  # every exporting backend's
            self.backend.exports,
            step.formulation.iteration,
            step.structure,
            theta,
            reference,
            step.plan.reshape(-1),
            target,
        )

    def _refusal(self, problem: CaptureProblem) -> str | None:
        """Why this pair cannot solve ``problem``'s objective (:func:`~mpc_hunt.solving.registry.objective_refusal`),
        None if it can."""
        refusal = self._refusals[problem.objective]
        return None if refusal is None else f"objective: {refusal.reason}"

    def _finish(self, solution: Solution) -> Solution:
        return solution.raise_for_status() if self.raise_on_failure else solution


def step_certificate(step: CaptureStep | TeamStep) -> Certificate | None:
    """The certificate of the step's last call (None where its backend writes none: NaN)."""
    values = step.certificate
    if np.any(np.isnan(values)):
        return None
    primal, dual, gap = (float(v) for v in values)
    return Certificate(primal, dual, gap)


def solve(problem: CaptureProblem, formulation: str, backend: str | None = None, **options) -> Solution:
    """Solve one capture problem cold with a fresh solver (see :class:`CaptureSolver`)."""
    return CaptureSolver(formulation, backend, **options).solve(problem)

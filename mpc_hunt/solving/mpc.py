"""The capture stage over a receding horizon: one object that keeps what carries from one control step to the next.

At every control step the capture-stage problem (Eqs. 12–15) is solved over the horizon and the plan's first
step applied. ``CaptureMPC`` holds a :class:`~mpc_hunt.solving.solver.CaptureSolver` (a formulation and its
backend, stateless between solves) and the receding-horizon memory, which lives nowhere else:

* the plan applied last step, kept with its problem's signature; shifted one step, it is the next warm start
  while the same defenders are controlled (:func:`~mpc_hunt.capture.plan.shift_plan`), else the step is cold;
* the duals of the last step's solve if it was usable, handed back only with that warm start;
* one meaning of success: a usable solve's plan is applied when its true violations of the constraints a plan
  must keep (:data:`~mpc_hunt.capture.evaluator.HARD_CONSTRAINTS`: Eqs. 13, 15, separation, attacker distance;
  Eq. 14 is elastic) are within ``tolerance`` (:data:`~mpc_hunt.solving.accuracy.VIOLATION_TOLERANCE`, the
  success rule of ``compare``); a usable plan beyond it is its own outcome, ``violating`` (counted in
  ``violating``), and the fallback below is applied. The rule reads the evaluator's violations, so it holds where
  plans are scored (``score=True``: compare, ``simulate --score``, compare's own loop); scoring costs about 60 %
  of an RTI step, so a controller built without it trusts a usable status;
* the fallback when a solve fails (counted in ``fallbacks``), in order: the solver's last iterate if the
  evaluator scored it feasible (violations ≤ :data:`FEASIBLE_TOLERANCE`; the common case of IPOPT stalling on
  the field's kink at |r_ai| = R_agg, where H is continuous but not differentiable); else the applied plan
  shifted; else holding position, which the problem's constraints always allow.

The centralised and the robot-by-robot formulations are the same object with another formulation.
:meth:`CaptureMPC.step` returns a scored :class:`~mpc_hunt.capture.solution.Solution`;
:meth:`CaptureMPC.loop_step` is the real-time form for a stage-form pair: the problem written into the arrays
of its :class:`~mpc_hunt.solving.step.CaptureStep` (a :class:`~mpc_hunt.solving.team_step.TeamStep` for
``distributed``), one step, no evaluator, so its fallback starts at the shifted plan.

    mpc = CaptureMPC("rti", "hpipm")
    for each control step:
        step = mpc.step(problem)        # step.plan[0]: every defender's next position
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from mpc_hunt.capture.evaluator import hard_violation
from mpc_hunt.capture.plan import shift_plan
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.solving.accuracy import VIOLATION_TOLERANCE
from mpc_hunt.solving.solver import CaptureSolver

FEASIBLE_TOLERANCE = 1e-6  # a failed solve's last iterate is applied when no violation exceeds it
FALLBACKS = ("last iterate", "shifted plan", "held")  # the fallbacks, in the order they are tried


@dataclass(frozen=True)
class MPCStep:
    """One control step: the solve, the plan applied (N, n, 2), which fallback it is (None: the solve's own
    plan) and the plan the solve started from (None: cold, every defender held)."""

    solution: Solution
    plan: np.ndarray
    fallback: str | None
    start: np.ndarray | None


@dataclass(frozen=True)
class _Memory:
    """What one step leaves to the next: its problem's signature, the plan applied, the duals of a usable solve."""

    signature: tuple
    plan: np.ndarray
    duals: WarmStart | None = None


class CaptureMPC:
    """The capture problem solved over a receding horizon (the module's docstring): a solver and its memory.

    ``formulation``, ``backend`` and ``options`` make the :class:`CaptureSolver` (``solver``: ``time_limit``,
    ``max_iter``, ``accuracy``, ``score``, ``loop``, the backend's options …); ``tolerance`` (m) is the largest
    true violation of a plan applied (default: the accuracy's, :data:`VIOLATION_TOLERANCE`).
    """

    def __init__(self, formulation: str, backend: str | None = None, *, tolerance: float | None = None, **options):
        self.solver = CaptureSolver(formulation, backend, **options)
        self.tolerance = VIOLATION_TOLERANCE[options.get("accuracy", "default")] if tolerance is None else tolerance
        self.fallbacks: Counter[str] = Counter()  # the fallbacks applied, by kind (:data:`FALLBACKS`)
        self.violating = 0  # usable plans not applied: beyond the tolerance
        self._memory: _Memory | None = None

    @property
    def plan(self) -> np.ndarray | None:
        """The plan applied at the last step (None before the first and after :meth:`reset`)."""
        return None if self._memory is None else self._memory.plan

    def reset(self) -> None:
        """Forget the last step: the next one starts cold (the fallback counts are kept)."""
        self._memory = None

    def follow(self, leader: CaptureMPC) -> None:
        """Start the next step where ``leader``'s would: from the plan it applied (without duals, which belong to
        this solver's own plans). For comparing solvers on the same starts along one closed loop."""
        self._memory = None if leader._memory is None else _Memory(leader._memory.signature, leader._memory.plan)

    def step(self, problem: CaptureProblem) -> MPCStep:
        """Solve ``problem`` from the memory and apply its plan, or the fallback."""
        start, memory = self._start(problem), self._memory
        duals = memory.duals if start is not None and memory is not None else None
        solution = self.solver.solve(problem, start, duals)
        if solution.success and solution.violation is not None and hard_violation(solution.violation) > self.tolerance:
            self.violating += 1
            plan, fallback = self._fallback(problem, start)
        elif solution.success and solution.plan is not None:  # (a usable solution always has its plan)
            plan, fallback = solution.plan, None
        elif (
            solution.plan is not None
            and solution.max_violation is not None
            and solution.max_violation <= FEASIBLE_TOLERANCE
        ):
            plan, fallback = solution.plan, FALLBACKS[0]
        else:
            plan, fallback = self._fallback(problem, start)
        self._keep(problem, plan, fallback, solution.duals if solution.status.usable else None)
        return MPCStep(solution, plan, fallback, start)

    def loop_step(self, problem: CaptureProblem) -> Status:
        """One real-time step on the control step of ``problem``'s structure (the solver's
        :meth:`CaptureSolver.step_for`, built on its first problem): ``problem`` and the start written into its
        arrays, one step, its plan applied if usable, else the fallback (no evaluator runs: never the last
        iterate). Returns the step's status; :attr:`plan` is the plan applied."""
        step = self.solver.step_for(problem)
        start = self._start(problem)
        step.load(problem, start)
        status = step.step()
        if status.usable:
            plan, fallback = problem.plan_with(step.plan.reshape(-1)), None
        else:
            plan, fallback = self._fallback(problem, start)
        self._keep(problem, plan, fallback, None)
        return status

    def _start(self, problem: CaptureProblem) -> np.ndarray | None:
        """The warm start: the plan applied last step, shifted one step, while the same defenders are controlled."""
        if self._memory is not None and self._memory.signature == problem.signature:
            return shift_plan(self._memory.plan)
        return None

    @staticmethod
    def _fallback(problem: CaptureProblem, start: np.ndarray | None) -> tuple[np.ndarray, str]:
        return (start, FALLBACKS[1]) if start is not None else (problem.held_plan(), FALLBACKS[2])

    def _keep(self, problem: CaptureProblem, plan: np.ndarray, fallback: str | None, duals: WarmStart | None):
        self._memory = _Memory(problem.signature, plan, duals)
        if fallback is not None:
            self.fallbacks[fallback] += 1

"""One solver interface for every formulation × backend.

``CaptureSolver`` pairs a formulation with a persistent backend, both found by
name in :mod:`mpc_hunt.solving.registry` on first use. It keeps only solver state: the
backend's set-up structures and the duals of its last usable solve. The plan to
start from is the caller's (a controller hands over the plan it applied, shifted
one step); the duals are reused only with such a plan, and only when the same
defenders are controlled. ``solve`` is the one-shot, cold form.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from mpc_hunt.solving import registry
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.evaluator import solve_scores
from mpc_hunt.capture.solution import Solution, Status, WarmStart


class CaptureSolver:
    """A formulation and its backend, kept between solves.

    ``time_limit`` (seconds) is handed to the solver as its own limit,
    ``accuracy`` (``default``, ``high``, ``low``) picks its tolerances, other
    keywords are the backend's options. ``raise_on_failure`` turns a failed
    status into :class:`~mpc_hunt.errors.SolverError`. The evaluator scores
    every plan, or with ``score=False`` only a failed solve's (what a
    controller's fallback reads); its time is ``score_time``, apart.
    """

    def __init__(self, formulation: str = "nlp", backend: str | None = None, *,
                 time_limit: float | None = None, accuracy: str = "default", raise_on_failure: bool = False,
                 score: bool = True, **backend_options):
        backend = registry.check_pair(formulation, backend)
        self.formulation = registry.formulation_class(formulation)()
        self.backend = registry.backend_class(backend)(time_limit=time_limit, accuracy=accuracy,
                                                       **backend_options)
        self.raise_on_failure = raise_on_failure
        self.score = score
        self._duals: tuple[tuple, WarmStart] | None = None   # (signature, duals) of the last usable solve
        self._prepared: set[tuple] = set()                     # structures whose model this solver has built

    def reset(self) -> None:
        """Forget the last duals: the next solve starts cold even when handed a plan."""
        self._duals = None

    def solve(self, problem: CaptureProblem, warm_plan: np.ndarray | None = None) -> Solution:
        """Solve ``problem``, from ``warm_plan`` (N, n, 2) if given, else cold from every defender held."""
        t0 = time.perf_counter()
        duals = None
        if warm_plan is not None and self._duals is not None and self._duals[0] == problem.signature:
            duals = self._duals[1]
        names = dict(formulation=self.formulation.name, backend=self.backend.name)
        try:
            build_time = 0.0
            if problem.structure not in self._prepared:     # set-up time is counted once per structure
                self.formulation.prepare(problem.structure)
                self._prepared.add(problem.structure)
                build_time = time.perf_counter() - t0
            result = self.formulation.solve(problem, self.backend, warm_plan, duals)
        except (RuntimeError, ValueError, ArithmeticError) as exc:
            message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            solution = Solution(status=Status.ERROR, message=message, overhead_time=time.perf_counter() - t0,
                                **names)
            return self._finish(solution)
        if result.plan is not None and not np.all(np.isfinite(result.plan)):
            result = replace(result, status=Status.ERROR, plan=None, message=f"{result.message} (non-finite plan)")
        scores = solve_scores(problem, result.plan, result.status, self.score)
        self._duals = (problem.signature, result.duals) if result.status.usable else None
        setup_time = result.setup_time + build_time
        overhead = time.perf_counter() - t0 - result.solver_time - setup_time - scores.get("score_time", 0.0)
        return self._finish(replace(result, **names, **scores, setup_time=setup_time,
                                    overhead_time=max(overhead, 0.0), warm_started=warm_plan is not None))

    def _finish(self, solution: Solution) -> Solution:
        return solution.raise_for_status() if self.raise_on_failure else solution


def solve(problem: CaptureProblem, formulation: str = "nlp", backend: str | None = None,
          **options) -> Solution:
    """Solve one capture problem cold with a fresh solver (see :class:`CaptureSolver`)."""
    return CaptureSolver(formulation, backend, **options).solve(problem)

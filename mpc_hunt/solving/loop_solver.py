"""``CaptureSolver``'s interface on :class:`~mpc_hunt.solving.loop.CaptureLoop`: what a controller runs.

A controller poses a :class:`~mpc_hunt.capture.problem.CaptureProblem` each
step and wants a :class:`~mpc_hunt.capture.solution.Solution` back (status,
plan, iterations, times), as from ``CaptureSolver.solve``. For a stage-form
formulation (:func:`~mpc_hunt.solving.registry.stage_formulations`), whose
backends close the step into one Function, ``LoopSolver`` does it on one
``CaptureLoop`` per structure, built on the structure's first problem: the
inputs are written into the loop's arrays, the loop steps, and the plan is
read back. Its plans are ``CaptureSolver``'s to the
bit (the loop's test holds it). The evaluator scores a failed step's plan (the
last usable one the loop kept, its reference if none), which a controller may
apply if it is feasible, and every plan only with ``score=True``: off the hot
path, a solution has no ``objective`` or ``violation``.

:func:`capture_solver` picks the one a controller should use.
"""

from __future__ import annotations

import time

import numpy as np

from mpc_hunt.solving import registry
from mpc_hunt.capture.evaluator import solve_scores
from mpc_hunt.solving.loop import CaptureLoop
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.solution import Solution
from mpc_hunt.solving.solver import CaptureSolver


class LoopSolver:
    """A stage-form formulation × backend on control loops, one per structure; a successful step's plan scored
    only with ``score``."""

    def __init__(self, formulation: str = "rti", backend: str | None = None, *, accuracy: str = "default",
                 score: bool = False, **backend_options):
        self.formulation = registry.formulation_class(formulation)()
        self.backend = registry.backend_class(registry.check_stage_pair(formulation, backend))   # built per loop
        self.score = score
        self._options = dict(accuracy=accuracy, **backend_options)
        self._loops: dict[tuple, CaptureLoop] = {}

    def solve(self, problem: CaptureProblem, warm_plan: np.ndarray | None = None) -> Solution:
        """One step at ``problem`` from ``warm_plan`` (N, n, 2), else every defender held."""
        t0 = time.perf_counter()
        loop = self._loops.get(problem.structure)
        setup_time = 0.0
        if loop is None:
            loop = self._loops[problem.structure] = CaptureLoop(problem, self.formulation.name, self.backend.name,
                                                                **self._options)
            setup_time = time.perf_counter() - t0
        loop.load(problem, warm_plan)
        t1 = time.perf_counter()
        status = loop.step()
        solver_time = time.perf_counter() - t1
        plan = problem.plan_with(loop.plan)
        scores = solve_scores(problem, plan, status, self.score)
        overhead = time.perf_counter() - t0 - solver_time - setup_time - scores.get("score_time", 0.0)
        return Solution(status=status, message=loop.message, formulation=self.formulation.name,
                        backend=self.backend.name, x=loop.plan.reshape(-1).copy(), plan=plan,
                        formulation_objective=float(loop.objective[0]) if status.usable else None,
                        solver_time=solver_time, overhead_time=max(overhead, 0.0), setup_time=setup_time,
                        iterations=loop.iterations, warm_started=warm_plan is not None,
                        extras={"qps": loop.qps}, **scores)


def capture_solver(formulation: str = "nlp", backend: str | None = None, *, time_limit: float | None = None,
                   score: bool = False, **options) -> CaptureSolver | LoopSolver:
    """The solver a controller runs: a :class:`LoopSolver` for a stage-form formulation (with no time limit:
    its solvers take none), else a :class:`CaptureSolver`; either scores every plan only with ``score``."""
    if time_limit is None and formulation in registry.stage_formulations():
        return LoopSolver(formulation, backend, score=score, **options)
    return CaptureSolver(formulation, backend, time_limit=time_limit, score=score, **options)

"""One solver interface for every formulation × backend.

``CaptureSolver`` pairs a formulation with a persistent backend: set up once,
then each ``solve`` updates numbers and warm-starts from the previous plan
shifted one step (and its duals) while the problem's structure is unchanged.
``solve`` is the one-shot, cold form.
"""

from __future__ import annotations

import time

import numpy as np

from formulations import make_formulation, shift_plan
from mpc_hunt.backends import BACKENDS, make_backend
from mpc_hunt.capture_problem import CaptureProblem
from mpc_hunt.errors import UnknownNameError
from mpc_hunt.evaluator import evaluate
from mpc_hunt.solution import Solution, Status


class CaptureSolver:
    """A formulation and its backend, kept between solves for warm starts.

    ``time_limit`` (seconds) is handed to the solver as its own limit.
    ``raise_on_failure`` turns a failed status into :class:`SolverError`.
    """

    def __init__(self, formulation: str = "nlp", backend: str | None = None, *,
                 time_limit: float | None = None, raise_on_failure: bool = False, **backend_options):
        self.formulation = make_formulation(formulation)
        backend = backend or self.formulation.default_backend
        if backend not in BACKENDS:
            raise UnknownNameError(f"unknown backend {backend!r} (available: {', '.join(BACKENDS)})")
        if backend not in self.formulation.backends:
            raise UnknownNameError(f"backend {backend!r} does not solve formulation {formulation!r} "
                                   f"(use one of: {', '.join(self.formulation.backends)})")
        self.backend = make_backend(backend, time_limit=time_limit, **backend_options)
        self.raise_on_failure = raise_on_failure
        self._previous: tuple | None = None   # (structure, plan, duals) of the last usable solve

    def reset(self) -> None:
        """Forget the previous solve: the next one starts cold."""
        self._previous = None

    def solve(self, problem: CaptureProblem, warm_plan: np.ndarray | None = None,
              warm_start: bool = True) -> Solution:
        """Solve ``problem``; warm-started from the previous plan unless told otherwise."""
        t0 = time.perf_counter()
        duals = None
        if warm_start and warm_plan is None and self._previous is not None \
                and self._previous[0] == problem.structure:
            warm_plan, duals = shift_plan(self._previous[1]), self._previous[2]
        try:
            self.formulation.prepare(problem.structure)
            build_time = time.perf_counter() - t0
            result = self.formulation.solve(problem, self.backend, warm_plan, duals)
            result.setup_time += build_time
        except (RuntimeError, ValueError, ArithmeticError) as exc:
            solution = Solution(self.formulation.name, self.backend.name, Status.ERROR,
                                str(exc).splitlines()[0] if str(exc) else type(exc).__name__,
                                None, None, None, None, 0.0, time.perf_counter() - t0)
            return solution.raise_for_status() if self.raise_on_failure else solution
        objective = violation = path = None
        if result.plan is not None:
            if np.all(np.isfinite(result.plan)):
                evaluation = evaluate(problem, result.plan)
                objective, violation, path = evaluation.objective, evaluation.violation, evaluation.attacker_path
            else:
                result.status, result.plan = Status.ERROR, None
        if result.status.usable:
            self._previous = (problem.structure, result.plan, result.duals)
        else:
            self._previous = None
        total = time.perf_counter() - t0
        solution = Solution(self.formulation.name, self.backend.name, result.status, result.message,
                            result.plan, result.objective, objective, violation, result.solver_time,
                            max(total - result.solver_time - result.setup_time, 0.0), result.setup_time,
                            result.iterations, warm_plan is not None, path)
        return solution.raise_for_status() if self.raise_on_failure else solution


def solve(problem: CaptureProblem, formulation: str = "nlp", backend: str | None = None,
          **options) -> Solution:
    """Solve one capture problem cold with a fresh solver (see :class:`CaptureSolver`)."""
    return CaptureSolver(formulation, backend, **options).solve(problem, warm_start=False)

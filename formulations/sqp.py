"""``sqp``: the ``qp`` linearisation iterated to convergence (sequential QP).

Each iterate relinearises at the previous QP's plan; it stops when no defender
position moves by more than ``tolerance`` metres, or after ``max_iterations``.
Comparing it with ``qp`` (one linearisation) and ``nlp`` (the exact problem)
shows what a single linearisation costs, and what the polygon of Eq. 13 costs.
"""

from __future__ import annotations

import numpy as np

from formulations.base import FormulationResult
from formulations.capture_model import parameter_vector, plan_from_x
from formulations.qp import QPFormulation
from mpc_hunt.solution import Status


class SQPFormulation(QPFormulation):
    name = "sqp"
    backends = ("osqp", "clarabel", "cvxpy")
    default_backend = "osqp"
    tolerance = 1e-7
    max_iterations = 30

    def solve(self, problem, backend, warm_plan, duals) -> FormulationResult:
        reference = problem.held_plan() if warm_plan is None else warm_plan
        theta = parameter_vector(problem)
        solver_time = setup_time = 0.0
        iterations = 0
        status, message = Status.ITERATION_LIMIT, f"no convergence in {self.max_iterations} QPs"
        plan, objective = None, None
        for count in range(self.max_iterations):
            raw, objective = self.solve_at(problem, backend, reference, theta, duals)
            solver_time += raw.solver_time
            setup_time += raw.setup_time
            iterations += raw.iterations
            duals = raw.duals
            if not raw.status.usable:
                status, message = raw.status, f"QP {count + 1}: {raw.message}"
                break
            plan = plan_from_x(problem, raw.x)
            if np.max(np.abs(plan - reference)) <= self.tolerance:
                status, message = raw.status, f"converged after {count + 1} QPs"
                break
            reference = plan
        return FormulationResult(status, message, plan, objective, solver_time, setup_time, iterations, duals)

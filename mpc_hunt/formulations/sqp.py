"""``sqp``: the ``qp`` linearisation iterated to convergence (sequential QP).

Each iterate relinearises at the previous QP's plan; it stops by the rule of
:class:`~mpc_hunt.capture.iteration.QPIteration` (no defender position moves by more
than 1e-7 m, or 30 QPs).
Comparing it with ``qp`` (one linearisation) and ``nlp`` (the exact problem)
shows what a single linearisation costs, and what the polygon of Eq. 13 costs.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from mpc_hunt.capture.iteration import QPIteration, another_fits
from mpc_hunt.capture.solution import Solution, Status
from mpc_hunt.formulations.capture_model import parameter_vector
from mpc_hunt.formulations.qp import QPFormulation


class SQPFormulation(QPFormulation):
    name = "sqp"
    kind = "qp"
    default_backend = "osqp"
    iteration = QPIteration(max_qps=30, tolerance=1e-7)

    def solve(self, problem, backend, warm_plan, duals) -> Solution:
        theta = parameter_vector(problem)
        return iterate(
            lambda reference, duals: self.solve_at(problem, backend, reference, theta, duals),
            problem.held_plan() if warm_plan is None else warm_plan,
            duals,
            self.iteration,
            backend.time_left,
        )


def iterate(step, reference: np.ndarray, duals, iteration: QPIteration, time_left=lambda: None) -> Solution:
    """``step(reference, duals)`` (one QP linearised at ``reference``) repeated at its own plan until ``iteration``
    says it has settled; times and iterations summed. ``time_left()`` is what is left of the step's time limit (s,
    the backend's, :meth:`~mpc_hunt.solving.backends.base.Backend.time_left`; None: no limit), each QP handed it:
    no QP is started once what is left would not fit one (:func:`~mpc_hunt.capture.iteration.another_fits`), the
    step then ending ``time_limit`` with the last usable plan."""
    solver_time = setup_time = 0.0
    iterations = 0
    last = None
    start = time.perf_counter()
    for count in range(iteration.max_qps):
        if last is not None and not another_fits(time_left(), time.perf_counter() - start, count):
            return replace(
                last,
                status=Status.TIME_LIMIT,
                message=f"{count} QPs in {solver_time:.3g} s: the step's time limit reached",
                solver_time=solver_time,
                setup_time=setup_time,
                iterations=iterations,
            )
        result = step(reference, duals)
        solver_time += result.solver_time
        setup_time += result.setup_time
        iterations += result.iterations
        totals = dict(solver_time=solver_time, setup_time=setup_time, iterations=iterations)
        if not result.status.usable:
            return replace(
                result,
                message=f"QP {count + 1}: {result.message}",
                x=None if last is None else last.x,
                plan=None if last is None else last.plan,
                formulation_objective=None if last is None else last.formulation_objective,
                **totals,
            )
        if iteration.settled(np.max(np.abs(result.plan - reference))):
            return replace(result, message=f"converged after {count + 1} QPs", **totals)
        last, duals, reference = result, result.duals, result.plan
    if last is None:  # (no QP ran)
        raise ValueError(f"an iteration of at most {iteration.max_qps} QPs runs none")
    return replace(last, status=Status.ITERATION_LIMIT, message=f"no convergence in {iteration.max_qps} QPs", **totals)

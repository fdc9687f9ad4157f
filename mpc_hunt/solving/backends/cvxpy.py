"""The QP written in CVXPY with parameters: a reference for the hand-assembled matrices.

It takes the least-squares form of the objective (|J x + c|² + lin·x) and the
constraint rows, never ``P`` or ``q``, so an assembly mistake in those shows up
as a disagreement. The problem is built once per structure (DPP), then only
parameter values change. ``A`` and ``J`` are sparse parameters on their
structural nonzeros (CVXPY's ``sparsity``): as dense parameters every entry,
zero or not, reached the solver's matrices, many times the work at N = 10.
``solver`` reaches any solver CVXPY has installed; the default, Clarabel, is an
accurate interior-point method, which a reference needs.
"""

from __future__ import annotations

import warnings
from contextlib import contextmanager
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from mpc_hunt.capture.data import QPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.errors import OptionError
from mpc_hunt.solving.backends.base import Backend
from mpc_hunt.solving.backends.clarabel import ClarabelBackend
from mpc_hunt.solving.backends.iteration_deadline import IterationDeadline, watched

if TYPE_CHECKING:
    import cvxpy as cp


@dataclass
class _Problem:
    """The parametric CVXPY problem and its parameters."""

    problem: cp.Problem
    x: cp.Variable
    J: cp.Parameter
    c: cp.Parameter
    lin: cp.Parameter
    A: cp.Parameter
    b: cp.Parameter  # u on upper and cone rows
    bl: cp.Parameter  # l on lower rows
    rows: list  # (constraint, its rows of A, sign): how each constraint's duals map onto the rows' multipliers y
    deadline: IterationDeadline | None = None  # Clarabel's, under a time limit (the class's docstring)
    called_back: object = None  # the Clarabel solver CVXPY keeps that calls the deadline back


CALLED_OFF = "CallbackTerminated"  # Clarabel's status once its termination callback has stopped it


class CvxpyBackend(Backend):
    """Persistent CVXPY problem with parameters J, c, lin, A, l, u.

    Under a time limit, Clarabel is stopped between iterations as :class:`ClarabelBackend` is (its termination
    callback, :mod:`~mpc_hunt.solving.backends.iteration_deadline`): CVXPY keeps the solver it made in the
    problem's solver cache and updates it in place for the next solve, so the callback is set on it once made
    (a solve on a solver CVXPY has just made, a structure's first or one whose sparsity changed, is stopped by
    Clarabel's own clock only). Without it, Clarabel's last iteration ran past the limit (up to 1.1 ms at N = 10,
    measured)."""

    name = "cvxpy"
    accepts = ("qp", "socp")
    package = "cvxpy"
    ACCURACY = ClarabelBackend.ACCURACY  # Clarabel's tolerances (any other solver gets the default)

    MAX_ITER = ClarabelBackend.MAX_ITER
    BUDGETED = ("CLARABEL", "OSQP")  # the solvers it hands time_limit and max_iter (both by those names)

    def __init__(
        self,
        time_limit: float | None = None,
        accuracy: str = "default",
        solver: str = "CLARABEL",
        *,
        max_iter: int | None = None,
        **options,
    ):
        self.solver = solver
        if solver not in self.BUDGETED and (time_limit is not None or max_iter is not None):
            raise OptionError(
                f"solver: CVXPY's {solver} is handed no budget here (only {', '.join(self.BUDGETED)}); "
                "drop time_limit and max_iter or pick one of those"
            )
        super().__init__(time_limit, accuracy if solver == "CLARABEL" else "default", max_iter=max_iter, **options)

    def option_names(self) -> frozenset[str] | None:  # type: ignore[override]
        """Clarabel's options when CVXPY runs Clarabel; another solver checks its own."""
        return ClarabelBackend.option_names() if self.solver == "CLARABEL" else None

    def setup(self, data: QPData) -> _Problem:
        import cvxpy as cp

        m, n = data.A.shape
        upper, lower = data.bounded_rows()
        stored = sp.coo_matrix(data.A)  # its stored entries, explicit zeros too: the structure's
        x, c, lin = cp.Variable(n), cp.Parameter(data.c.shape), cp.Parameter(n)
        J = (
            cp.Parameter(data.J.shape, sparsity=data.J_pattern)
            if data.J_pattern is not None
            else cp.Parameter(data.J.shape)
        )
        A, b, bl = cp.Parameter((m, n), sparsity=(stored.row, stored.col)), cp.Parameter(m), cp.Parameter(m)
        rows = []
        if len(upper):
            rows.append((A[upper] @ x <= b[upper], upper, 1.0))
        if len(lower):
            rows.append((A[lower] @ x >= bl[lower], lower, -1.0))
        for start, size in data.cones:
            rows.append(
                (
                    cp.SOC(b[start] - A[start] @ x, b[start + 1 : start + size] - A[start + 1 : start + size] @ x),
                    np.arange(start, start + size),
                    1.0,
                )
            )
        objective = cp.Minimize(cp.sum_squares(J @ x + c) + lin @ x)
        state = _Problem(cp.Problem(objective, [row[0] for row in rows]), x, J, c, lin, A, b, bl, rows)
        if self.solver == "CLARABEL" and self.time_limit is not None:
            state.deadline = IterationDeadline()
        self.update(state, data)
        try:  # CVXPY compiles the parametrised problem for its solver once: a structure's set-up, not a step
            with _quiet():
                state.problem.get_problem_data(self.solver)
        except (cp.error.SolverError, cp.error.DCPError) as exc:
            raise RuntimeError(str(exc)) from None
        return state

    def update(self, state: _Problem, data: QPData) -> None:
        state.c.value, state.lin.value = data.c, data.lin
        if data.J_pattern is None:
            state.J.value = data.J
        else:
            rows, cols = data.J_pattern
            state.J.value_sparse = sp.coo_array((data.J[rows, cols], (rows, cols)), shape=data.J.shape)
        state.A.value_sparse = sp.coo_array(data.A)
        state.b.value = np.where(np.isfinite(data.u), data.u, 0.0)
        state.bl.value = np.where(np.isfinite(data.l), data.l, 0.0)

    def run(self, state: _Problem, data: QPData, warm: WarmStart) -> Solution:
        import cvxpy as cp

        if warm.x is not None:
            state.x.value = warm.x
        options = dict(self.options)
        if self.solver in self.BUDGETED:
            options["max_iter"] = self.iteration_cap()
        try:
            with _quiet():
                # Problem.solve in its three documented stages (Problem.get_problem_data), so that the solver is
                # handed what is left of the step's limit once CVXPY has written its data (the parameters into
                # the cached program: up to 7 ms, measured), not before: only the read-back is outside its clock.
                program, chain, inverse = state.problem.get_problem_data(self.solver, solver_opts=options)
                left = None
                if self.solver in self.BUDGETED and self.time_limit is not None:
                    options["time_limit"], left = self.clock_limit(), self.time_left()
                with watched(state.deadline, left):
                    solution = chain.solve_via_data(state.problem, program, True, False, options)
                if state.deadline is not None:
                    _call_back(state, state.deadline)
                if str(getattr(solution, "status", "")) == CALLED_OFF:  # CVXPY reads it as a solver error
                    return Solution(
                        status=Status.TIME_LIMIT,
                        message=f"{CALLED_OFF} ({self.solver})",
                        iterations=int(solution.iterations),
                        extras={"reported_solve_time_s": float(solution.solve_time)},
                    )
                state.problem.unpack_results(solution, chain, inverse)
        except (cp.error.SolverError, cp.error.DCPError) as exc:
            raise RuntimeError(str(exc)) from None
        status = {
            cp.OPTIMAL: Status.OPTIMAL,
            cp.OPTIMAL_INACCURATE: Status.OPTIMAL_INACCURATE,
            cp.INFEASIBLE: Status.INFEASIBLE,
            cp.INFEASIBLE_INACCURATE: Status.INFEASIBLE,
            cp.UNBOUNDED: Status.INFEASIBLE,
            cp.UNBOUNDED_INACCURATE: Status.INFEASIBLE,
            cp.USER_LIMIT: Status.ITERATION_LIMIT,
        }.get(state.problem.status, Status.ERROR)
        stats = state.problem.solver_stats
        x = None if state.x.value is None else np.array(state.x.value)
        objective = None if x is None else float(state.problem.value - data.c @ data.c)
        return Solution(
            status=status,
            message=f"{state.problem.status} ({stats.solver_name})",
            x=x,
            formulation_objective=objective,
            iterations=int(stats.num_iters or 0),
            duals=WarmStart(x, _row_duals(state, data.A.shape[0])),
            extras={"reported_solve_time_s": float(stats.solve_time or 0.0)},
        )


def _call_back(state: _Problem, deadline: IterationDeadline) -> None:
    """``deadline`` set on the Clarabel solver CVXPY keeps for the next solve (its solver cache), if a new one."""
    kept = getattr(state.problem, "_solver_cache", {}).get("CLARABEL")
    if kept is not None and kept is not state.called_back:
        kept.set_termination_callback(lambda info: deadline.passed())
        state.called_back = kept


@contextmanager
def _quiet():
    """CVXPY's warnings that say nothing to a caller: "may be inaccurate" (reported through the status), and its own
    reading of a sparse parameter's dense value."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        warnings.filterwarnings("ignore", "Reading from a sparse CVXPY expression", RuntimeWarning)
        yield


def _row_duals(state: _Problem, m: int) -> np.ndarray | None:
    """The constraints' duals as multipliers of the rows of A (y > 0 at an upper bound, < 0 at a lower one; a
    cone's (λ, μ) on its rows t, v), or None if CVXPY has none. The objective is the QP's (P = 2JᵀJ), unscaled."""
    y = np.zeros(m)
    for constraint, index, sign in state.rows:
        value = constraint.dual_value
        if value is None:
            return None
        y[index] += (
            sign * np.concatenate([np.ravel(v) for v in value]) if isinstance(value, list) else sign * np.ravel(value)
        )
    return y

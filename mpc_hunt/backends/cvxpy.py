"""The QP written in CVXPY with parameters: a reference for the hand-assembled matrices.

It takes the least-squares form of the objective (|J x + c|² + lin·x) and the
constraint rows, never ``P`` or ``q``, so an assembly mistake in those shows up
as a disagreement. The problem is built once per structure (DPP), then only
parameter values change. ``solver`` reaches any solver CVXPY has installed; the
default, Clarabel, is an accurate interior-point method, which a reference needs.
"""

from __future__ import annotations

import time
import warnings

import cvxpy as cp
import numpy as np

from mpc_hunt.backends.base import BackendResult, QPData, WarmStart
from mpc_hunt.solution import Status

KIND = "qp"

_STATUS = {
    cp.OPTIMAL: Status.OPTIMAL,
    cp.OPTIMAL_INACCURATE: Status.OPTIMAL_INACCURATE,
    cp.INFEASIBLE: Status.INFEASIBLE,
    cp.INFEASIBLE_INACCURATE: Status.INFEASIBLE,
    cp.UNBOUNDED: Status.INFEASIBLE,
    cp.UNBOUNDED_INACCURATE: Status.INFEASIBLE,
    cp.USER_LIMIT: Status.ITERATION_LIMIT,
}


class CvxpyBackend:
    """Persistent CVXPY problem with parameters J, c, lin, A, l, u."""

    name = "cvxpy"
    kind = KIND

    def __init__(self, time_limit: float | None = None, solver: str = "CLARABEL"):
        self.solver = solver
        self.time_limit = time_limit
        self._key: tuple | None = None
        self.setups = 0

    def _setup(self, data: QPData) -> None:
        m, n = data.A.shape
        cone_rows = np.zeros(m, dtype=bool)
        for start, size in data.cones:
            cone_rows[start:start + size] = True
        self._upper = np.flatnonzero(np.isfinite(data.u) & ~cone_rows)
        self._lower = np.flatnonzero(np.isfinite(data.l) & ~cone_rows)
        self._x = cp.Variable(n)
        self._J = cp.Parameter(data.J.shape)
        self._c = cp.Parameter(data.c.shape)
        self._lin = cp.Parameter(n)
        self._A = cp.Parameter((m, n))
        self._b = cp.Parameter(m)   # u on upper and cone rows, l on lower rows
        self._bl = cp.Parameter(m)
        constraints = []
        if len(self._upper):
            constraints.append(self._A[self._upper] @ self._x <= self._b[self._upper])
        if len(self._lower):
            constraints.append(self._A[self._lower] @ self._x >= self._bl[self._lower])
        for start, size in data.cones:
            t = self._b[start] - self._A[start] @ self._x
            v = self._b[start + 1:start + size] - self._A[start + 1:start + size] @ self._x
            constraints.append(cp.SOC(t, v))
        objective = cp.Minimize(cp.sum_squares(self._J @ self._x + self._c) + self._lin @ self._x)
        self._problem = cp.Problem(objective, constraints)
        self._key = data.key
        self.setups += 1

    def solve(self, data: QPData, warm: WarmStart | None = None) -> BackendResult:
        setup_time = 0.0
        if self._key != data.key:
            t0 = time.perf_counter()
            self._setup(data)
            setup_time = time.perf_counter() - t0
        self._J.value, self._c.value, self._lin.value = data.J, data.c, data.lin
        self._A.value = data.A.toarray()
        self._b.value = np.where(np.isfinite(data.u), data.u, 0.0)
        self._bl.value = np.where(np.isfinite(data.l), data.l, 0.0)
        if warm is not None and warm.x is not None:
            self._x.value = warm.x
        kwargs = {"warm_start": True, "solver": self.solver}
        if self.time_limit is not None and self.solver in ("CLARABEL", "OSQP"):
            kwargs["time_limit"] = self.time_limit
        try:
            with warnings.catch_warnings():  # "may be inaccurate" is reported through the status
                warnings.simplefilter("ignore", UserWarning)
                self._problem.solve(**kwargs)
        except (cp.error.SolverError, cp.error.DCPError, ValueError) as exc:
            return BackendResult(Status.ERROR, str(exc).splitlines()[0], None, None, 0, 0.0, setup_time)
        stats = self._problem.solver_stats
        status = _STATUS.get(self._problem.status, Status.ERROR)
        x = self._x.value
        if x is None or not np.all(np.isfinite(x)):
            x = None
            if status.usable:
                status = Status.ERROR
        objective = None if x is None else float(self._problem.value - data.c @ data.c)
        return BackendResult(status, f"{self._problem.status} ({stats.solver_name})",
                             None if x is None else np.array(x), objective, int(stats.num_iters or 0),
                             float(stats.solve_time or 0.0), setup_time, WarmStart(x))

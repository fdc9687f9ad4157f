"""OSQP, persistent: ``setup`` once per structure, then ``update`` values and warm-start.

ADMM converges slowly when the cost dwarfs the constraints (the capture QP's
Hessian reaches 1e5 against constraint rows of order 1), so the backend hands
OSQP the cost divided by its largest Hessian entry: a positive factor leaves
the minimiser unchanged; the objective and the duals are scaled back.
"""

from __future__ import annotations

import time

import numpy as np
import osqp

from mpc_hunt.backends.base import BackendResult, QPData, WarmStart
from mpc_hunt.solution import Status

KIND = "qp"

_S = osqp.SolverStatus
_STATUS = {
    _S.OSQP_SOLVED: Status.OPTIMAL,
    _S.OSQP_SOLVED_INACCURATE: Status.OPTIMAL_INACCURATE,
    _S.OSQP_PRIMAL_INFEASIBLE: Status.INFEASIBLE,
    _S.OSQP_PRIMAL_INFEASIBLE_INACCURATE: Status.INFEASIBLE,
    _S.OSQP_DUAL_INFEASIBLE: Status.INFEASIBLE,
    _S.OSQP_DUAL_INFEASIBLE_INACCURATE: Status.INFEASIBLE,
    _S.OSQP_MAX_ITER_REACHED: Status.ITERATION_LIMIT,
    _S.OSQP_TIME_LIMIT_REACHED: Status.TIME_LIMIT,
}


class OsqpBackend:
    """Persistent OSQP (ADMM): warm-started from the previous plan (primal only)."""

    name = "osqp"
    kind = KIND

    def __init__(self, time_limit: float | None = None, max_iter: int = 20000, eps: float = 1e-7):
        self.settings = dict(verbose=False, eps_abs=eps, eps_rel=eps, max_iter=max_iter,
                             polishing=True, warm_starting=True)
        if time_limit is not None:
            self.settings["time_limit"] = float(time_limit)
        self._solver: osqp.OSQP | None = None
        self._key: tuple | None = None
        self.setups = 0

    def solve(self, data: QPData, warm: WarmStart | None = None) -> BackendResult:
        if data.cones:
            return BackendResult(Status.ERROR, "osqp cannot take second-order cones", None, None, 0, 0.0)
        setup_time = 0.0
        scale = 1.0 / max(1.0, float(np.max(np.abs(data.P.data), initial=0.0)))
        if self._key != data.key:
            t0 = time.perf_counter()
            self._solver = osqp.OSQP()
            self._solver.setup(data.P * scale, data.q * scale, data.A, data.l, data.u, **self.settings)
            self._key = data.key
            setup_time = time.perf_counter() - t0
            self.setups += 1
        else:
            self._solver.update(q=data.q * scale, l=data.l, u=data.u, Px=data.P.data * scale, Ax=data.A.data)
        if warm is not None and warm.x is not None:
            # Primal only: the previous step's duals belong to another linearisation and,
            # measured on closed-loop sequences, cost ADMM iterations instead of saving them.
            self._solver.warm_start(x=warm.x)
        res = self._solver.solve(raise_error=False)
        info = res.info
        status = _STATUS.get(info.status_val, Status.ERROR)
        x = None if res.x is None or not np.all(np.isfinite(res.x)) else np.array(res.x)
        if x is None and status.usable:
            status = Status.ERROR
        objective = float(info.obj_val) / scale if x is not None else None
        solver_time = float(info.solve_time + info.update_time + info.polish_time)
        y = None if res.y is None else np.array(res.y) / scale
        return BackendResult(status, info.status, x, objective, int(info.iter), solver_time,
                             setup_time, WarmStart(x, y))

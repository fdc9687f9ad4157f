"""IPOPT through CasADi's ``nlpsol``: created once per NLP structure, then reused."""

from __future__ import annotations

import time

import casadi as ca
import numpy as np

from mpc_hunt.backends.base import BackendResult, NLPData, WarmStart
from mpc_hunt.solution import Status

KIND = "nlp"

_STATUS = {
    "Solve_Succeeded": Status.OPTIMAL,
    "Solved_To_Acceptable_Level": Status.OPTIMAL_INACCURATE,
    "Infeasible_Problem_Detected": Status.INFEASIBLE,
    "Maximum_Iterations_Exceeded": Status.ITERATION_LIMIT,
    "Maximum_WallTime_Exceeded": Status.TIME_LIMIT,
    "Maximum_CpuTime_Exceeded": Status.TIME_LIMIT,
}


class IpoptBackend:
    """Persistent IPOPT: ``nlpsol`` is built for a structure once; solves pass numbers."""

    name = "ipopt"
    kind = KIND

    def __init__(self, time_limit: float | None = None, max_iter: int = 500, tol: float = 1e-8):
        self.options = {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes",
                        "ipopt.tol": tol, "ipopt.max_iter": max_iter,
                        "ipopt.warm_start_init_point": "yes", "ipopt.warm_start_bound_push": 1e-9,
                        "ipopt.warm_start_mult_bound_push": 1e-9}
        if time_limit is not None:
            self.options["ipopt.max_wall_time"] = float(time_limit)
        self._solvers: dict[tuple, ca.Function] = {}
        self.setups = 0

    def solve(self, data: NLPData, warm: WarmStart | None = None) -> BackendResult:
        setup_time = 0.0
        solver = self._solvers.get(data.key)
        if solver is None:
            t0 = time.perf_counter()
            solver = ca.nlpsol("capture", "ipopt", data.build(), self.options)
            self._solvers[data.key] = solver
            setup_time = time.perf_counter() - t0
            self.setups += 1
        args = dict(p=data.p, lbx=data.lbx, ubx=data.ubx, lbg=data.lbg, ubg=data.ubg)
        warm = warm or WarmStart()
        if warm.x is not None:
            args["x0"] = warm.x
        if warm.y is not None and warm.z is not None:
            args["lam_g0"], args["lam_x0"] = warm.y, warm.z
        t0 = time.perf_counter()
        try:
            out = solver(**args)
        except RuntimeError as exc:  # CasADi raises on evaluation errors (NaN, …)
            return BackendResult(Status.ERROR, str(exc).splitlines()[0], None, None, 0,
                                 time.perf_counter() - t0, setup_time)
        solver_time = time.perf_counter() - t0  # CasADi's stats carry no total time for IPOPT
        stats = solver.stats()
        raw = stats.get("return_status", "unknown")
        status = _STATUS.get(raw, Status.ERROR)
        x = np.array(out["x"]).ravel()
        if not np.all(np.isfinite(x)):
            status, raw = Status.ERROR, f"{raw} (non-finite iterate)"
        return BackendResult(status, raw, x, float(out["f"]), int(stats.get("iter_count", 0)),
                             solver_time, setup_time,
                             WarmStart(x, np.array(out["lam_g"]).ravel(), np.array(out["lam_x"]).ravel()))

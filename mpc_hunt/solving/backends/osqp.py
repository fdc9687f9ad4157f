"""OSQP (ADMM), persistent: ``setup`` once per structure, then ``update`` values and warm-start.

ADMM converges slowly when the cost dwarfs the constraints (the capture QP's
Hessian reaches 1e5 against constraint rows of order 1), so the backend hands
OSQP the cost divided by its largest Hessian entry: a positive factor leaves
the minimiser unchanged; the objective and the duals are scaled back.
"""

from __future__ import annotations

import time

import numpy as np

from mpc_hunt.capture.data import QPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.solving.backends.base import Backend


def _scale(data: QPData) -> float:
    return 1.0 / max(1.0, float(np.max(np.abs(data.P.data), initial=0.0)))


class OsqpBackend(Backend):
    """Persistent OSQP, warm-started from the previous plan (primal only)."""

    name = "osqp"
    accepts = ("qp",)
    package = "osqp"
    ACCURACY = {
        "default": {"eps_abs": 1e-7, "eps_rel": 1e-7},
        "high": {"eps_abs": 1e-9, "eps_rel": 1e-9},
        "low": {"eps_abs": 1e-4, "eps_rel": 1e-4},
    }
    MAX_ITER = 20000
    NATIVE = {"time_limit": "time_limit", "max_iter": "max_iter"}
    _refactorisation = 0.0  # s of CPU the last update's refactorisation took (update())

    @classmethod
    def option_names(cls) -> frozenset[str]:
        from osqp.ext_builtin import OSQPSettings

        return frozenset(name for name in dir(OSQPSettings) if not name.startswith("_"))

    def setup(self, data: QPData):
        import osqp

        settings = {
            "verbose": False,
            "polishing": True,
            "warm_starting": True,
            **self.options,
            "max_iter": self.iteration_cap(),
        }
        if self.time_limit is not None:
            settings["time_limit"] = self.time_limit
        solver = osqp.OSQP()
        scale = _scale(data)
        solver.setup(data.P * scale, data.q * scale, data.A, data.l, data.u, **settings)
        return solver

    def update(self, solver, data: QPData) -> None:
        scale = _scale(data)
        q, Px = data.q * scale, data.P.data * scale
        cpu = time.thread_time()
        solver.update(q=q, l=data.l, u=data.u, Px=Px, Ax=data.A.data)
        # New P and A refactorise the KKT matrix, as a rho update in the solve does (OSQP 1.x: after the
        # iteration's clock check, so past it): its cost, on the CPU, that of such a refactorisation.
        self._refactorisation = time.thread_time() - cpu

    def run(self, solver, data: QPData, warm: WarmStart) -> Solution:
        import osqp

        if warm.x is not None:
            # Primal only: the previous step's duals belong to another linearisation and,
            # measured on closed-loop sequences, cost ADMM iterations instead of saving them.
            solver.warm_start(x=warm.x)
        if self.time_limit is not None:  # what is left of the step's limit (Backend.clock_limit)
            solver.update_settings(time_limit=self.clock_limit())
        wall, cpu = time.perf_counter(), time.thread_time()
        res = solver.solve(raise_error=False)
        wall, cpu = time.perf_counter() - wall, time.thread_time() - cpu
        info = res.info
        if self.time_limit is not None:
            # OSQP reads its clock once an iteration, before it checks convergence and adapts rho; the polish of a
            # solved QP and a rho update's refactorisation run after that check (osqp_solve): its tail, on the CPU
            # (the polish's wall time scaled by the solve's share of the CPU: a polish held up is not a dearer one).
            if info.polish_time > 0:
                self.record_tail(info.polish_time * min(1.0, cpu / wall) if wall > 0 else info.polish_time)
            if info.rho_updates > 0:
                self.record_tail(self._refactorisation)
        S = osqp.SolverStatus
        status = {
            S.OSQP_SOLVED: Status.OPTIMAL,
            S.OSQP_SOLVED_INACCURATE: Status.OPTIMAL_INACCURATE,
            S.OSQP_PRIMAL_INFEASIBLE: Status.INFEASIBLE,
            S.OSQP_PRIMAL_INFEASIBLE_INACCURATE: Status.INFEASIBLE,
            S.OSQP_DUAL_INFEASIBLE: Status.INFEASIBLE,
            S.OSQP_DUAL_INFEASIBLE_INACCURATE: Status.INFEASIBLE,
            S.OSQP_MAX_ITER_REACHED: Status.ITERATION_LIMIT,
            S.OSQP_TIME_LIMIT_REACHED: Status.TIME_LIMIT,
        }.get(info.status_val, Status.ERROR)
        x = None if res.x is None else np.array(res.x)
        scale = _scale(data)
        y = None if res.y is None else np.array(res.y) / scale
        return Solution(
            status=status,
            message=info.status,
            x=x,
            formulation_objective=None if x is None else float(info.obj_val) / scale,
            iterations=int(info.iter),
            duals=WarmStart(x, y),
            # Its solve and polish, from the limit's read on (its update_time, new data, came before it).
            extras={"reported_solve_time_s": float(info.solve_time + info.polish_time)},
        )

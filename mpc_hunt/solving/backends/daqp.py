"""DAQP (dual active set, dense), persistent through its ``Model`` workspace.

Chosen from PyPI rather than CasADi's ``conic`` plugin: the package is newer
than the one CasADi bundles, takes NumPy arrays directly (no CasADi ``Function``
call per solve) and keeps its workspace between solves, with ``update`` for new
numbers. The capture QP is small and dense enough (n ≤ ~100) for a dense
solver. Warm start: constraints whose previous multiplier is non-zero start in
the working set. Its Hessian is singular (the slacks of Eq. 14 enter linearly);
DAQP's proximal-point iterations (``eps_prox``) handle that.

Budget: DAQP reads its clock only every 32 iterations of one inner active-set
solve, and its proximal-point loop runs many short ones, so its own time limit
can pass unnoticed for seconds (measured: 2 s against a 0.02 s limit). The time
limit is therefore also an iteration cap (``CLOCK = False``:
:meth:`~mpc_hunt.solving.backends.base.Backend.iteration_cap`), set before each solve.
Rows the formulation marks as implied by the others (``QPData.implied``: ``qp``'s
s ≥ 0) are left out: linearly dependent active rows, on which its active set
cycled for seconds (their multipliers are returned as 0).
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.capture.data import QPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.solving.backends.base import Backend

# DAQP's exit flags: the status each gives, and its name (the daqp-condensed backend's too).
EXIT_STATUS = {
    2: Status.OPTIMAL,
    1: Status.OPTIMAL,
    -1: Status.INFEASIBLE,
    -3: Status.INFEASIBLE,
    -4: Status.ITERATION_LIMIT,
    -7: Status.TIME_LIMIT,
}
EXIT_MESSAGE = {
    2: "soft optimal",
    1: "optimal",
    -1: "infeasible",
    -2: "cycling",
    -3: "unbounded",
    -4: "iteration limit",
    -5: "non-convex",
    -6: "overdetermined initial active set",
    -7: "time limit",
}
ACTIVE, LOWER = 1, 2  # DAQP's constraint flags


def _kept(data: QPData) -> np.ndarray:
    """The rows DAQP is handed: all but those the others imply (degenerate for an active-set method)."""
    return np.ones(data.A.shape[0], dtype=bool) if data.implied is None else ~data.implied


def _dense(data: QPData) -> tuple[np.ndarray, ...]:
    P = data.P.toarray()
    H = P + P.T - np.diag(np.diag(P))
    kept = _kept(data)
    return H, data.q, data.A.toarray()[kept], data.u[kept], data.l[kept]


class DaqpBackend(Backend):
    """Persistent DAQP: ``Model.setup`` per structure, ``Model.update`` after."""

    name = "daqp"
    accepts = ("qp",)
    package = "daqp"
    ACCURACY = {"default": {}, "high": {"primal_tol": 1e-9}, "low": {"primal_tol": 1e-4}}
    CLOCK = False
    MAX_ITER = 10000
    NATIVE = {"time_limit": "time_limit", "max_iter": "iter_limit"}

    @classmethod
    def option_names(cls) -> frozenset[str]:
        import daqp

        return frozenset(daqp.Model().settings)

    def setup(self, data: QPData):
        import daqp

        model = daqp.Model()
        model.setup(*_dense(data))
        settings = dict(self.options)
        if self.time_limit is not None:
            settings["time_limit"] = self.time_limit
        if settings:
            model.settings = settings
        return model

    def update(self, model, data: QPData) -> None:
        H, f, A, u, l = _dense(data)
        model.update(H=H, f=f, A=A, bupper=u, blower=l)

    def run(self, model, data: QPData, warm: WarmStart) -> Solution:
        kept = _kept(data)
        if warm.y is not None and len(warm.y) == data.A.shape[0]:
            y = warm.y[kept]
            sense = np.where(y > 0, ACTIVE, np.where(y < 0, ACTIVE | LOWER, 0)).astype(np.int32)
            model.update(sense=sense)
        model.settings = {"iter_limit": self.iteration_cap()}
        if self.time_limit is not None:  # its clock, read in long inner loops only: the cap is what holds
            model.settings = {"time_limit": self.clock_limit()}
        x, fval, flag, info = model.solve()
        x = np.array(x)
        y = np.zeros(data.A.shape[0])
        y[kept] = info["lam"]
        return Solution(
            status=EXIT_STATUS.get(int(flag), Status.ERROR),
            message=EXIT_MESSAGE.get(int(flag), str(flag)),
            x=x,
            formulation_objective=float(fval),
            iterations=int(info["iterations"]),
            duals=WarmStart(x, y),
            extras={"reported_solve_time_s": float(info["solve_time"])},
        )

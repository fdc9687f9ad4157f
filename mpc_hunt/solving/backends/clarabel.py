"""Clarabel (interior point), persistent: set up once per structure, then its update API.

``l ≤ Ax ≤ u`` becomes ``b − A'x ∈ K``: each finite upper bound a row of the
non-negative cone (u − Ax ≥ 0), each finite lower bound one more (Ax − l ≥ 0),
and the rows named in ``QPData.cones`` second-order cones (b = u). Presolve is
off so that the data can be updated in place. An interior-point method does not
take a starting point: Clarabel is never warm-started (reported as such).

Under a time limit Clarabel is handed what is left of the step's (its ``time_limit``, read once an iteration),
and its termination callback stops it first when what is left would not fit another iteration
(:mod:`~mpc_hunt.solving.backends.iteration_deadline`): ``CallbackTerminated``, a ``time_limit``. Handed the
limit less a fitted cost per iteration, its steps at N = 10 ran past their limit by up to 1.2 ms (measured).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from mpc_hunt.capture.data import QPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.solving.backends.base import Backend
from mpc_hunt.solving.backends.iteration_deadline import IterationDeadline, watched

_STATUS = {
    "Solved": Status.OPTIMAL,
    "AlmostSolved": Status.OPTIMAL_INACCURATE,
    "PrimalInfeasible": Status.INFEASIBLE,
    "AlmostPrimalInfeasible": Status.INFEASIBLE,
    "DualInfeasible": Status.INFEASIBLE,
    "AlmostDualInfeasible": Status.INFEASIBLE,
    "MaxIterations": Status.ITERATION_LIMIT,
    "MaxTime": Status.TIME_LIMIT,
    "CallbackTerminated": Status.TIME_LIMIT,  # the deadline's callback (the module's docstring)
}


class ConicLayout:
    """How the rows of ``A`` map onto stacked, signed rows ``b − A'x ∈ K`` (fixed per structure)."""

    def __init__(self, data: QPData):
        n = data.A.shape[1]
        upper, lower = data.bounded_rows()
        self.nonnegative = len(upper) + len(lower)
        # Each stacked row: the source row of A and its sign (+1: u − Ax ≥ 0 or a cone row, −1: Ax − l ≥ 0).
        rows = (
            [(r, 1.0) for r in upper]
            + [(r, -1.0) for r in lower]
            + [(r, 1.0) for start, k in data.cones for r in range(start, start + k)]
        )
        self.rows = len(rows)
        self.b_index = np.array([r for r, _ in rows], dtype=int)
        self.b_sign = np.array([sign for _, sign in rows])
        coo = data.A.tocoo()
        by_row: dict[int, list[tuple[int, float]]] = {}
        for dest, (r, sign) in enumerate(rows):
            by_row.setdefault(int(r), []).append((dest, sign))
        dst, col, src, sgn = [], [], [], []
        for k, (r, c) in enumerate(zip(coo.row, coo.col)):
            for dest, sign in by_row.get(int(r), []):
                dst.append(dest)
                col.append(c)
                src.append(k)
                sgn.append(sign)
        # The order of A.data in COO equals its CSC order (tocoo keeps stored entries in place).
        ids = sp.csc_matrix((np.arange(1, len(dst) + 1, dtype=float), (dst, col)), shape=(self.rows, n))  # type: ignore[arg-type]
        order = ids.data.astype(int) - 1
        self.pattern = ids
        self.src = np.array(src, dtype=int)[order]
        self.sign = np.array(sgn)[order]
        self.cone_sizes = tuple(k for _, k in data.cones)

    def values(self, data: QPData) -> np.ndarray:
        """The stacked matrix's non-zeros, in its CSC order (what ``update`` takes)."""
        return self.sign * data.A.data[self.src]

    def matrix(self, data: QPData) -> sp.csc_matrix:
        A = self.pattern.copy()
        A.data = self.values(data)
        return A

    def row_duals(self, z: np.ndarray, rows: int) -> np.ndarray:
        """The stacked rows' duals z ≥ 0 (∈ K*) as multipliers of the rows of A: y > 0 at an upper bound, y < 0 at
        a lower one, a cone row's own dual (:mod:`mpc_hunt.capture.certificate`'s convention)."""
        y = np.zeros(rows)
        np.add.at(y, self.b_index, self.b_sign * z)
        return y

    def vector(self, data: QPData) -> np.ndarray:
        return self.b_sign * np.where(self.b_sign > 0, data.u[self.b_index], data.l[self.b_index])


class ClarabelBackend(Backend):
    """Persistent Clarabel: ``update(P, q, A, b)`` between solves of one structure."""

    name = "clarabel"
    accepts = ("qp", "socp")
    package = "clarabel"
    ACCURACY = {
        "default": {},
        "high": {"tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10, "tol_feas": 1e-10},
        "low": {"tol_gap_abs": 1e-5, "tol_gap_rel": 1e-5, "tol_feas": 1e-5},
    }
    MAX_ITER = 200
    NATIVE = {"time_limit": "time_limit", "max_iter": "max_iter"}

    @classmethod
    def option_names(cls) -> frozenset[str]:
        import clarabel

        return frozenset(name for name in dir(clarabel.DefaultSettings()) if not name.startswith("_"))

    def setup(self, data: QPData):
        import clarabel

        settings = clarabel.DefaultSettings()
        settings.verbose = False
        settings.presolve_enable = False
        settings.input_sparse_dropzeros = False
        for key, value in self.options.items():
            setattr(settings, key, value)
        settings.max_iter = self.iteration_cap()
        if self.time_limit is not None:
            settings.time_limit = self.clock_limit()
        layout = ConicLayout(data)
        cones = ([clarabel.NonnegativeConeT(layout.nonnegative)] if layout.nonnegative else []) + [
            clarabel.SecondOrderConeT(k) for k in layout.cone_sizes
        ]
        solver = clarabel.DefaultSolver(data.P, data.q, layout.matrix(data), layout.vector(data), cones, settings)
        deadline = None
        if self.time_limit is not None:
            deadline = IterationDeadline()
            solver.set_termination_callback(lambda info: deadline.passed())
        return solver, layout, settings, deadline

    def update(self, state, data: QPData) -> None:
        solver, layout, settings, _ = state
        if self.time_limit is None:
            solver.update(P=data.P.data, q=data.q, A=layout.values(data), b=layout.vector(data))
            return
        settings.time_limit = self.clock_limit()  # what is left of the step's limit, with the numbers in one call
        solver.update(P=data.P.data, q=data.q, A=layout.values(data), b=layout.vector(data), settings=settings)

    def run(self, state, data: QPData, warm: WarmStart) -> Solution:
        solver, layout, _, deadline = state
        with watched(deadline, self.time_left()):
            sol = solver.solve()
        raw = str(sol.status).split(".")[-1]
        x = np.array(sol.x)
        return Solution(
            status=_STATUS.get(raw, Status.ERROR),
            message=raw,
            x=x,
            formulation_objective=float(sol.obj_val),
            iterations=int(sol.iterations),
            duals=WarmStart(x, layout.row_duals(np.array(sol.z), data.A.shape[0])),
            extras={"reported_solve_time_s": float(sol.solve_time)},
        )

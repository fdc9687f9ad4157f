"""Clarabel (interior point), persistent: set up once per structure, then its update API.

``l ≤ Ax ≤ u`` becomes ``b − A'x ∈ K``: each finite upper bound a row of the
non-negative cone (u − Ax ≥ 0), each finite lower bound one more (Ax − l ≥ 0),
and the rows named in ``QPData.cones`` second-order cones (b = u). Presolve is
off so that the data can be updated in place. An interior-point method does not
take a starting point: Clarabel is never warm-started (reported as such).
"""

from __future__ import annotations

import time

import clarabel
import numpy as np
import scipy.sparse as sp

from mpc_hunt.backends.base import BackendResult, QPData, WarmStart
from mpc_hunt.solution import Status

KIND = "qp"

_STATUS = {
    "Solved": Status.OPTIMAL,
    "AlmostSolved": Status.OPTIMAL_INACCURATE,
    "PrimalInfeasible": Status.INFEASIBLE,
    "AlmostPrimalInfeasible": Status.INFEASIBLE,
    "DualInfeasible": Status.INFEASIBLE,
    "AlmostDualInfeasible": Status.INFEASIBLE,
    "MaxIterations": Status.ITERATION_LIMIT,
    "MaxTime": Status.TIME_LIMIT,
}


class _ConicLayout:
    """How the rows of ``A`` map onto Clarabel's stacked, signed rows (fixed per structure)."""

    def __init__(self, data: QPData):
        m, n = data.A.shape
        cone_rows = np.zeros(m, dtype=bool)
        for start, size in data.cones:
            cone_rows[start:start + size] = True
        upper = np.flatnonzero(np.isfinite(data.u) & ~cone_rows)
        lower = np.flatnonzero(np.isfinite(data.l) & ~cone_rows)
        # Each stacked row: the source row of A and its sign (+1: u − Ax ≥ 0 or a cone row, −1: Ax − l ≥ 0).
        rows = [(r, 1.0) for r in upper] + [(r, -1.0) for r in lower] \
            + [(r, 1.0) for start, k in data.cones for r in range(start, start + k)]
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
                dst.append(dest); col.append(c); src.append(k); sgn.append(sign)
        # The order of A.data in COO equals its CSC order (tocoo keeps stored entries in place).
        ids = sp.csc_matrix((np.arange(1, len(dst) + 1, dtype=float), (dst, col)), shape=(self.rows, n))
        order = ids.data.astype(int) - 1
        self.pattern = ids
        self.src = np.array(src, dtype=int)[order]
        self.sign = np.array(sgn)[order]
        self.cones = ([clarabel.NonnegativeConeT(len(upper) + len(lower))] if len(upper) + len(lower) else []) \
            + [clarabel.SecondOrderConeT(k) for _, k in data.cones]

    def values(self, data: QPData) -> np.ndarray:
        """The stacked matrix's non-zeros, in its CSC order (what ``update`` takes)."""
        return self.sign * data.A.data[self.src]

    def matrix(self, data: QPData) -> sp.csc_matrix:
        A = self.pattern.copy()
        A.data = self.values(data)
        return A

    def vector(self, data: QPData) -> np.ndarray:
        return self.b_sign * np.where(self.b_sign > 0, data.u[self.b_index], data.l[self.b_index])


class ClarabelBackend:
    """Persistent Clarabel: ``update(P, q, A, b)`` between solves of one structure."""

    name = "clarabel"
    kind = KIND

    def __init__(self, time_limit: float | None = None, max_iter: int = 200):
        self.settings = clarabel.DefaultSettings()
        self.settings.verbose = False
        self.settings.presolve_enable = False
        self.settings.input_sparse_dropzeros = False
        self.settings.max_iter = max_iter
        if time_limit is not None:
            self.settings.time_limit = float(time_limit)
        self._solver = None
        self._key: tuple | None = None
        self._layout: _ConicLayout | None = None
        self.setups = 0

    def solve(self, data: QPData, warm: WarmStart | None = None) -> BackendResult:
        setup_time = 0.0
        if self._key != data.key:
            t0 = time.perf_counter()
            self._layout = _ConicLayout(data)
            self._solver = clarabel.DefaultSolver(data.P, data.q, self._layout.matrix(data),
                                                  self._layout.vector(data), self._layout.cones, self.settings)
            self._key = data.key
            setup_time = time.perf_counter() - t0
            self.setups += 1
        else:
            self._solver.update(P=data.P.data, q=data.q, A=self._layout.values(data), b=self._layout.vector(data))
        sol = self._solver.solve()
        raw = str(sol.status).split(".")[-1]
        status = _STATUS.get(raw, Status.ERROR)
        x = np.array(sol.x)
        if not np.all(np.isfinite(x)):
            status, x = Status.ERROR, None
        objective = float(sol.obj_val) if x is not None else None
        return BackendResult(status, raw, x, objective, int(sol.iterations), float(sol.solve_time),
                             setup_time, WarmStart(x, np.array(sol.z)))

"""What every backend takes and gives back.

A backend is a persistent solver object (osqp-style): the first ``solve`` on a
new structure sets it up, later ones only update numbers in place and
warm-start. One signature for all: ``backend.solve(data, warm_start) ->
BackendResult``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import scipy.sparse as sp

from mpc_hunt.solution import Status


@dataclass
class NLPData:
    """A parametric NLP: ``build()`` returns CasADi's {'x','p','f','g'} once per ``key``."""

    key: tuple
    build: Callable[[], dict]
    p: np.ndarray
    lbx: np.ndarray
    ubx: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray


@dataclass
class QPData:
    """min ½xᵀPx + qᵀx  s.t.  l ≤ Ax ≤ u, with the same sparsity for every ``key``.

    ``P`` holds the upper triangle. The objective is also given in its
    least-squares form |J x + c|² + lin·x (P = 2JᵀJ, q = 2Jᵀc + lin), which the
    CVXPY backend uses as an independent check of the assembled matrices.
    ``cones`` lists (start, size) of rows that form second-order cones
    (t ≥ |v|, with row ``start`` holding t), for conic backends only.
    """

    key: tuple
    P: sp.csc_matrix
    q: np.ndarray
    A: sp.csc_matrix
    l: np.ndarray
    u: np.ndarray
    J: np.ndarray
    c: np.ndarray
    lin: np.ndarray
    cones: tuple[tuple[int, int], ...] = ()


@dataclass
class WarmStart:
    x: np.ndarray | None = None
    y: np.ndarray | None = None      # constraint duals
    z: np.ndarray | None = None      # bound duals (NLP)


@dataclass
class BackendResult:
    status: Status
    message: str
    x: np.ndarray | None
    objective: float | None
    iterations: int
    solver_time: float
    setup_time: float = 0.0
    duals: WarmStart = field(default_factory=WarmStart)

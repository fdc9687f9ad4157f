"""What a formulation hands a backend: the data kinds (``NLPData``, ``QPData``, ``StageQPData``).

A formulation emits one of these (its ``kind``); a backend declares the kinds
it ``accepts``; the registry derives which pairs work from those two
declarations. The ``key`` of each names the structure: a backend sets up one
solver per key and afterwards only updates numbers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Protocol

import numpy as np
import scipy.sparse as sp

from mpc_hunt.capture.solution import Solution, WarmStart


@dataclass(frozen=True)
class NLPData:
    """A parametric NLP: ``build()`` returns CasADi's {'x','p','f','g'} once per ``key``.

    ``kind`` is ``"nlp"``, or ``"ocp-nlp"`` when x and g come stage by stage
    (x_0, u_0, …; gap_0, c_0, …) and the NLP is re-solved each control step from
    the shifted previous solution, which a backend may use to pick its settings.
    """

    key: tuple
    build: Callable[[], dict]
    p: np.ndarray
    lbx: np.ndarray
    ubx: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray
    kind: str = "nlp"


@dataclass(frozen=True)
class QPData:
    """min ½xᵀPx + qᵀx  s.t.  l ≤ Ax ≤ u, with the same sparsity for every ``key`` (``kind = "qp"``).

    ``P`` holds the upper triangle. The objective is also given in its
    least-squares form |J x + c|² + lin·x (P = 2JᵀJ, q = 2Jᵀc + lin), which the
    CVXPY backend uses as an independent check of the assembled matrices.
    ``cones`` lists (start, size) of rows that form second-order cones
    (t ≥ |v|, with row ``start`` holding t): such data is of kind ``"socp"``.
    ``implied`` marks rows that the others imply (None: none), which a backend
    may leave out (an active-set method, on which they are degenerate); their
    multipliers are then 0, a valid choice since the rest imply them.
    ``J_pattern`` is (rows, columns) of J's entries that may be nonzero, the same
    for every ``key`` (None: any), as ``A``'s stored entries are for ``A``.
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
    implied: np.ndarray | None = None
    J_pattern: tuple[np.ndarray, np.ndarray] | None = None

    def bounded_rows(self) -> tuple[np.ndarray, np.ndarray]:
        """The rows outside the cones with a finite upper bound, and those with a finite lower bound."""
        cone_rows = np.zeros(self.A.shape[0], dtype=bool)
        for start, size in self.cones:
            cone_rows[start : start + size] = True
        return (np.flatnonzero(np.isfinite(self.u) & ~cone_rows), np.flatnonzero(np.isfinite(self.l) & ~cone_rows))


@dataclass(frozen=True)
class StageQPData:
    """A stage-structured QP as a CasADi graph (kind ``ocp-qp``), which the backend closes into one Function.

    ``build()`` (once per ``key``) returns the graph: ``inputs`` (CasADi
    symbols), ``z`` (the QP's variable, stage by stage: x_0, u_0, …, x_N),
    ``qp`` (``h``, ``g``, ``a``, ``lba``, ``uba``, ``lbx``, ``ubx`` of
    min ½zᵀHz + gᵀz s.t. lba ≤ Az ≤ uba, lbx ≤ z ≤ ubx, as expressions of the
    inputs; the rows stage by stage: gap_0, c_0, …, c_N), ``plan`` and
    ``cost`` (expressions of the inputs and z: what a solve returns as ``x``,
    and the model's objective) and ``stages`` = (N, nx, nu, ng), the sizes of
    each stage. ``args`` are the inputs' numbers at this solve.
    """

    key: tuple
    build: Callable[[], Any]
    args: tuple[np.ndarray, ...]


class SolvesData(Protocol):
    """What a formulation is handed to solve its data with: a backend (:mod:`mpc_hunt.solving.backends`)."""

    @property
    def name(self) -> str: ...

    def solve(self, data: NLPData | QPData | StageQPData, warm: WarmStart | None = None) -> Solution: ...

    def time_left(self) -> float | None:
        """Seconds left of the step's time limit (None: no limit): what a formulation of several solves reads."""
        ...

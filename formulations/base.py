"""What a formulation is: it turns a capture problem into solver data and reads the answer back."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mpc_hunt.backends.base import WarmStart
from mpc_hunt.capture_problem import CaptureProblem
from mpc_hunt.solution import Status


@dataclass
class FormulationResult:
    """A formulation's answer before the shared evaluator scores it."""

    status: Status
    message: str
    plan: np.ndarray | None          # (N, n, 2), every defender
    objective: float | None          # the formulation's own objective
    solver_time: float
    setup_time: float
    iterations: int
    duals: WarmStart                 # for the next warm start


class Formulation:
    """Base class: ``name``, the backends it works with, and ``solve``."""

    name: str = ""
    backends: tuple[str, ...] = ()
    default_backend: str = ""

    def prepare(self, structure: tuple) -> None:
        """Build (once, cached) the symbolic functions for ``structure``; timed as set-up."""
        raise NotImplementedError

    def solve(self, problem: CaptureProblem, backend, warm_plan: np.ndarray | None,
              duals: WarmStart | None) -> FormulationResult:
        raise NotImplementedError


def separation_pairs(nc: int, nf: int) -> list[tuple[int, int]]:
    """Pairs (i, j) constrained apart: controlled–controlled (i < j) and controlled–held (j ≥ nc)."""
    return [(i, j) for i in range(nc) for j in range(i + 1, nc + nf)]


def shift_plan(plan: np.ndarray) -> np.ndarray:
    """A previous plan moved one step on, its last step repeated: the receding-horizon warm start."""
    return np.concatenate([plan[1:], plan[-1:]], axis=0)

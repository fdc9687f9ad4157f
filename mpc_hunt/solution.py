"""One result type for every formulation and backend (scipy.optimize style)."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from mpc_hunt.errors import SolverError


class Status(str, Enum):
    """Normalised solver status."""

    OPTIMAL = "optimal"
    OPTIMAL_INACCURATE = "optimal_inaccurate"
    INFEASIBLE = "infeasible"
    ITERATION_LIMIT = "iteration_limit"
    TIME_LIMIT = "time_limit"
    ERROR = "error"

    @property
    def usable(self) -> bool:
        """Whether the plan may be applied (a solution, possibly to reduced accuracy)."""
        return self in (Status.OPTIMAL, Status.OPTIMAL_INACCURATE)


@dataclass
class Solution:
    """What a solve returns: status, plan, objectives, violations, times and iterations.

    ``objective`` and ``violation`` come from the shared evaluator (the true
    nonlinear problem); ``formulation_objective`` is the formulation's own
    value, reported beside it. Times are in seconds: ``solver_time`` inside the
    solver, ``overhead_time`` our own work around it for this solve (building
    data, evaluating), ``setup_time`` a one-off set-up done by this call (0 when
    the persistent solver was reused). ``warm_started``: a previous plan seeded
    this solve (as the starting point and, for the QP family, the linearisation
    point; Clarabel itself takes no starting point).
    """

    formulation: str
    backend: str
    status: Status
    message: str
    plan: np.ndarray | None
    formulation_objective: float | None
    objective: float | None
    violation: dict[str, float] | None
    solver_time: float
    overhead_time: float
    setup_time: float = 0.0
    iterations: int = 0
    warm_started: bool = False
    attacker_path: np.ndarray | None = field(default=None, repr=False)

    @property
    def success(self) -> bool:
        return self.status.usable

    @property
    def solve_time(self) -> float:
        """Solver time plus our own overhead (set-up excluded)."""
        return self.solver_time + self.overhead_time

    @property
    def max_violation(self) -> float | None:
        return None if self.violation is None else max(self.violation.values())

    def raise_for_status(self) -> "Solution":
        """Raise :class:`SolverError` unless the solve succeeded; returns ``self`` otherwise."""
        if not self.success:
            raise SolverError(f"{self.formulation}/{self.backend}: {self.status.value}: {self.message}")
        return self

    def to_dict(self) -> dict:
        """Plain JSON-ready data."""
        return {
            "formulation": self.formulation,
            "backend": self.backend,
            "status": self.status.value,
            "message": self.message,
            "objective": self.objective,
            "formulation_objective": self.formulation_objective,
            "violation": self.violation,
            "solve_time_s": self.solve_time,
            "solver_time_s": self.solver_time,
            "overhead_time_s": self.overhead_time,
            "setup_time_s": self.setup_time,
            "iterations": self.iterations,
            "warm_started": self.warm_started,
            "plan": None if self.plan is None else self.plan.tolist(),
        }

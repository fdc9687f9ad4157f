"""One result type for every layer: backend, formulation and solver (scipy.optimize style).

A backend fills what the solver computed (status, message, ``x``, its own
objective, iterations, times, duals, extras); the formulation adds the ``plan``
read back from ``x``; the solver adds the evaluator's ``objective`` and
``violation`` and its own timing. Each layer builds a new value with
:func:`dataclasses.replace`, never by changing the one it was handed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from mpc_hunt.capture.certificate import Certificate
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


@dataclass(frozen=True)
class WarmStart:
    """A starting point: primal ``x``, constraint duals ``y`` and (NLP) bound duals ``z``."""

    x: np.ndarray | None = None
    y: np.ndarray | None = None
    z: np.ndarray | None = None


@dataclass(frozen=True, kw_only=True)
class Solution:
    """What a solve returns: status, plan, objectives, violations, times, iterations, duals.

    ``objective`` and ``violation`` come from the shared evaluator (the true
    nonlinear problem); ``formulation_objective`` is the formulation's own
    value, reported beside it. Times are in seconds: ``solver_time`` inside the
    solver, ``overhead_time`` our own work around it for this solve (building
    data, reading back), ``score_time`` the evaluator's (a benchmark's work,
    not the step's), ``setup_time`` a one-off set-up done by this call (0 when
    the persistent solver was reused), ``off_cpu_time`` how much of the step's wall time (its solves and our work
    between them) this process was not running (the machine gave its core to another process, or it waited):
    the wall time less the process's CPU time over the step, at least 0. ``warm_started``: a plan seeded this
    solve (as the starting point and, for the QP family, the linearisation
    point). ``duals`` are what the next warm start may reuse; ``extras`` holds
    solver-specific figures (plain numbers and strings). ``certificate``: the
    returned point's primal and dual residuals and duality gap, computed from
    the problem the solver was handed (:mod:`mpc_hunt.capture.certificate`;
    None where the backend returns no multipliers).
    """

    status: Status
    message: str = ""
    formulation: str = ""
    backend: str = ""
    x: np.ndarray | None = field(default=None, repr=False)
    plan: np.ndarray | None = field(default=None, repr=False)
    formulation_objective: float | None = None
    objective: float | None = None
    violation: dict[str, float] | None = None
    solver_time: float = 0.0
    overhead_time: float = 0.0
    score_time: float = 0.0
    setup_time: float = 0.0
    off_cpu_time: float = 0.0
    iterations: int = 0
    warm_started: bool = False
    attacker_path: np.ndarray | None = field(default=None, repr=False)
    duals: WarmStart = field(default_factory=WarmStart, repr=False)
    extras: dict = field(default_factory=dict, repr=False)
    certificate: Certificate | None = None

    @property
    def success(self) -> bool:
        return self.status.usable

    @property
    def solve_time(self) -> float:
        """Solver time plus our own overhead (set-up and scoring excluded): the time a controller waits."""
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
            "score_time_s": self.score_time,
            "setup_time_s": self.setup_time,
            "off_cpu_time_s": self.off_cpu_time,
            "iterations": self.iterations,
            "warm_started": self.warm_started,
            "extras": self.extras,
            "certificate": None if self.certificate is None else self.certificate.to_dict(),
            "plan": None if self.plan is None else self.plan.tolist(),
        }

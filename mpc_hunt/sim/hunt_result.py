"""What a closed-loop hunt records and reports."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


def _described(key: str) -> property:
    """A read-only attribute: the controller's ``key`` (of its describe()), None for a controller without one."""
    return property(lambda self: self.controller.get(key), doc=f"The controller's {key}, if it has one.")


@dataclass
class HuntResult:
    """Every trajectory of one hunt, and the figures computed from them."""

    scenario: str
    controller: dict  # the controller's describe(): name and settings
    times: np.ndarray  # (K+1,)
    attacker: np.ndarray  # (K+1, 2)
    defenders: np.ndarray  # (K+1, n, 2)
    capture_stage: np.ndarray  # (K, n) bool
    intercepts: np.ndarray  # (K, n, 2): approach targets, NaN in the capture stage
    termination: str  # "captured", "time_limit", "non_finite_state", "attacker_escaped", "stopped",
    # "abandoned"
    captured: bool
    capture_time: float | None
    path_lengths: np.ndarray  # (n,)
    final_hunting_radius: float
    min_obstacle_clearance: float | None
    min_defender_separation: float | None
    min_attacker_distance: float
    attacker_min_obstacle_clearance: float | None
    approach_min_obstacle_clearance: float | None  # over the positions approaching-stage commands led to
    capture_min_obstacle_clearance: float | None  # over the positions capture-stage commands led to
    min_arena_margin: float | None  # least distance of a defender inside the arena's edges, < 0 beyond one
    solve_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    solve_iterations: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    failed_solves: int = 0
    fallbacks: int = 0
    longest_failure_streak: int = 0  # most consecutive failed capture-stage solves
    # Per capture-stage solve, in order: the one-off set-up it did (s; 0 but on a new structure: building its
    # functions, compiling a codegen step), the status, the certificate (primal residual, dual residual, duality
    # gap; NaN where none) and the true violations of the plan applied (VIOLATION_NAMES' order, m; NaN where the
    # plan was not scored or a fallback was applied).
    setup_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # Of each solve's time, our own work around the solver (building its data, reading its answer, the certificate):
    # what a step may take past its time limit (the solver's share of the step is bounded by what is left of it).
    overhead_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # Of each solve's step, the time the process was off the CPU: the machine's, not the step's
    # (mpc_hunt.solving.step_timing).
    off_cpu_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # Of each solve's step, the time the hypervisor took from the machine's CPUs meanwhile (read only for a hunt
    # given a deadline; 10 ms ticks, summed over the CPUs: an upper bound of the step's own; 0 where unread).
    stolen_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    solve_statuses: tuple[str, ...] = ()
    certificates: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    applied_violations: np.ndarray = field(default_factory=lambda: np.zeros((0, 5)))
    deadline: float | None = None  # the step's budget given to the hunt (s), beside the time step T
    violating_plans: int = 0  # usable solves whose plan the loop did not apply: beyond its tolerance

    BUDGET_STATUSES = ("time_limit", "iteration_limit")

    formulation = _described("formulation")  # str | None
    backend = _described("backend")  # str | None
    horizon = _described("horizon")  # int | None
    prediction = _described("prediction")  # bool | None

    @property
    def steps(self) -> int:
        return len(self.times) - 1

    @property
    def time_step(self) -> float:
        return float(self.times[1] - self.times[0]) if len(self.times) > 1 else float("nan")

    @property
    def budget_hits(self) -> int:
        """Solves stopped by their time limit or iteration cap."""
        return sum(s in self.BUDGET_STATUSES for s in self.solve_statuses)

    def deadline_misses(self, deadline: float) -> int:
        """Capture-stage solves that took longer than ``deadline`` seconds (a structure's one-off set-up apart: it is
        built once, before a robot's loop, or cached)."""
        return int(np.sum(self.solve_times > deadline))

    def solve_time_stats(self) -> dict:
        """The capture-stage solves' times (s): median, p95 and max of the solve (a set-up apart: how many solves did
        one, and the longest), and the solves past T and past the hunt's deadline: every figure that reads a clock."""
        t = self.solve_times
        misses = {
            "time_step_s": self.time_step,
            "over_time_step": self.deadline_misses(self.time_step),
            "deadline_s": self.deadline,
            "over_deadline": None if self.deadline is None else self.deadline_misses(self.deadline),
        }
        if len(t) == 0:
            return {
                "count": 0,
                "median_s": None,
                "p95_s": None,
                "max_s": None,
                "setups": 0,
                "setup_max_s": None,
                "deadline_misses": misses,
            }
        return {
            "count": int(len(t)),
            "median_s": float(np.median(t)),
            "p95_s": float(np.percentile(t, 95)),
            "max_s": float(np.max(t)),
            "setups": int(np.sum(self.setup_times > 0)),
            "setup_max_s": float(np.max(self.setup_times)),
            "deadline_misses": misses,
        }

    def to_dict(self) -> dict:
        """The JSON report (``mpc-hunt simulate --json``)."""

        def opt(x):
            return None if x is None else float(x)

        return {
            "scenario": self.scenario,
            **self.controller,
            "captured": self.captured,
            "termination": self.termination,
            "capture_time_s": opt(self.capture_time),
            "path_lengths_m": [float(x) for x in self.path_lengths],
            "final_hunting_radius_m": float(self.final_hunting_radius),
            "min_obstacle_clearance_m": opt(self.min_obstacle_clearance),
            "min_defender_separation_m": opt(self.min_defender_separation),
            "min_attacker_distance_m": float(self.min_attacker_distance),
            "attacker_min_obstacle_clearance_m": opt(self.attacker_min_obstacle_clearance),
            "approach_min_obstacle_clearance_m": opt(self.approach_min_obstacle_clearance),
            "capture_min_obstacle_clearance_m": opt(self.capture_min_obstacle_clearance),
            "min_arena_margin_m": opt(self.min_arena_margin),
            "steps": self.steps,
            "solve_time": self.solve_time_stats(),
            "solve_iterations_median": (
                float(np.median(self.solve_iterations)) if len(self.solve_iterations) else None
            ),
            "failed_solves": self.failed_solves,
            "fallbacks": self.fallbacks,
            "longest_failure_streak": self.longest_failure_streak,
            "budget_hits": self.budget_hits,
            "violating_plans": self.violating_plans,
            "certificate_max": self.certificate_max(),
        }

    def certificate_max(self) -> dict | None:
        """The largest primal residual, dual residual and duality gap over the hunt's certified solves (None: none)."""
        rows = self.certificates[~np.any(np.isnan(self.certificates), axis=1)] if len(self.certificates) else []
        if not len(rows):
            return None
        top = np.max(rows, axis=0)
        return {
            k: (float(v) if np.isfinite(v) else "inf")
            for k, v in zip(("primal_residual", "dual_residual", "duality_gap"), top)
        }

"""A hunt's record of its capture-stage solves, step by step: what the closed loop adds to its result."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mpc_hunt.capture.evaluator import VIOLATION_NAMES
from mpc_hunt.control.controller import Command
from mpc_hunt.sim.hunt_result import HuntResult


class SolveRecord:
    """Per capture-stage solve: its time, iterations and set-up, the status, the certificate, the applied plan's
    true violations; the failed solves, the current and the longest run of them, and the commands that fell
    back."""

    def __init__(self):
        self.times, self.iterations = [], []
        self.setups, self.overheads, self.off_cpu, self.stolen, self.statuses = [], [], [], [], []
        self.certificates, self.violations = [], []
        self.violating = self.failed = self.streak = self.longest_streak = self.fallbacks = 0

    def add(self, cmd: Command, stolen: float = 0.0) -> None:
        """A step's command: its solve, if it made one (``stolen`` s taken by the hypervisor meanwhile), and
        whether it fell back."""
        solution, fallback = cmd.solution, cmd.fallback
        self.fallbacks += fallback
        if solution is None:
            return
        self.times.append(solution.solve_time)
        self.iterations.append(solution.iterations)
        self.failed += not solution.success
        self.streak = 0 if solution.success else self.streak + 1
        self.longest_streak = max(self.longest_streak, self.streak)
        self.violating += solution.success and fallback  # usable, yet not applied: beyond the tolerance
        self.setups.append(solution.setup_time)
        self.overheads.append(solution.overhead_time)
        self.off_cpu.append(solution.off_cpu_time)
        self.stolen.append(stolen)
        self.statuses.append(solution.status.value)
        c = solution.certificate
        self.certificates.append((np.nan,) * 3 if c is None else (c.primal_residual, c.dual_residual, c.duality_gap))
        v = solution.violation
        self.violations.append(
            (np.nan,) * len(VIOLATION_NAMES) if v is None or fallback else tuple(v[name] for name in VIOLATION_NAMES)
        )

    def into(self, result: HuntResult, deadline: float | None) -> HuntResult:
        return replace(
            result,
            setup_times=np.array(self.setups),
            overhead_times=np.array(self.overheads),
            off_cpu_times=np.array(self.off_cpu),
            stolen_times=np.array(self.stolen),
            solve_statuses=tuple(self.statuses),
            certificates=np.array(self.certificates, dtype=float).reshape(-1, 3),
            applied_violations=np.array(self.violations, dtype=float).reshape(-1, len(VIOLATION_NAMES)),
            deadline=deadline,
            violating_plans=self.violating,
            solve_times=np.array(self.times),
            solve_iterations=np.array(self.iterations, dtype=int),
            failed_solves=self.failed,
            fallbacks=self.fallbacks,
            longest_failure_streak=self.longest_streak,
        )

"""The hunting strategy: the defenders' controller (it never sees how the world is simulated).

Each defender is in the approaching stage (|r_ai| ≥ R_agg: Eq. 6 towards the
predicted intercept) or the capture stage (|r_ai| < R_agg: its next positions
come from the capture-stage problem, Eqs. 12–15, solved over a receding
horizon). When that solve fails, the fallback (counted) is, in order: the
solver's last iterate if the shared evaluator finds it feasible (violations ≤
``FEASIBLE_TOLERANCE``; this is the common case of IPOPT stalling on the
field's kink at |r_ai| = R_agg, where H is continuous but not differentiable);
else the previous plan shifted one step if its structure still fits; else
holding position, which the problem's constraints always allow.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from formulations import shift_plan
from mpc_hunt import attacker
from mpc_hunt.approach import approach_target, approach_velocity
from mpc_hunt.capture_problem import CaptureProblem
from mpc_hunt.scenario import Scenario
from mpc_hunt.solution import Solution
from mpc_hunt.solver import CaptureSolver

FEASIBLE_TOLERANCE = 1e-6


@dataclass(frozen=True)
class Observation:
    """What the defenders know at time t (the UAV's broadcast in the paper's Fig. 2)."""

    time: float
    attacker: np.ndarray
    previous_attacker: np.ndarray | None
    defenders: np.ndarray


@dataclass
class Command:
    """The defenders' velocities for the next step, and why."""

    velocities: np.ndarray             # (n, 2)
    capture_stage: np.ndarray          # (n,) bool
    intercepts: np.ndarray             # (n, 2): approach targets p'_di (NaN in the capture stage)
    solution: Solution | None = None
    fallback: bool = False


class HuntingStrategy:
    """The paper's strategy; the capture stage solved by any formulation and backend."""

    def __init__(self, scenario: Scenario, *, prediction: bool = True, formulation: str = "nlp",
                 backend: str | None = None, horizon: int = 1, time_limit: float | None = None):
        self.scenario = scenario
        self.prediction = prediction
        self.horizon = horizon
        self.solver = CaptureSolver(formulation, backend, time_limit=time_limit)
        self._last_plan: tuple | None = None   # (structure, plan) of the last usable capture solve

    def attacker_velocity_estimate(self, obs: Observation) -> np.ndarray:
        """Eq. 7's line of motion: the finite difference of the last two observed positions."""
        if obs.previous_attacker is None:
            return np.zeros(2)
        return (obs.attacker - obs.previous_attacker) / self.scenario.hunt.time_step

    def command(self, obs: Observation) -> Command:
        s = self.scenario
        T = s.hunt.time_step
        speeds = s.defender_max_speeds
        capture = attacker.perceives(s, obs.attacker, obs.defenders)
        velocities = np.zeros_like(obs.defenders)
        intercepts = np.full_like(obs.defenders, np.nan)
        v_a = self.attacker_velocity_estimate(obs)
        for i in np.flatnonzero(~capture):
            target = approach_target(obs.attacker, v_a, obs.defenders[i], speeds[i], self.prediction)
            intercepts[i] = target
            others = np.delete(obs.defenders, i, axis=0)
            velocities[i] = approach_velocity(s, obs.defenders[i], target, speeds[i], others)
        if not capture.any():
            self._last_plan = None
            return Command(velocities, capture, intercepts)
        problem = CaptureProblem.at_state(s, obs.attacker, obs.defenders, self.horizon)
        solution = self.solver.solve(problem)
        fallback = not solution.success
        if not fallback or (solution.plan is not None and solution.max_violation <= FEASIBLE_TOLERANCE):
            plan = solution.plan
            self._last_plan = (problem.structure, plan)
        elif self._last_plan is not None and self._last_plan[0] == problem.structure and self.horizon > 1:
            plan = shift_plan(self._last_plan[1])
            self._last_plan = (problem.structure, plan)
        else:
            plan = problem.held_plan()
            self._last_plan = None
        velocities[capture] = (plan[0][capture] - obs.defenders[capture]) / T
        return Command(velocities, capture, intercepts, solution, fallback)

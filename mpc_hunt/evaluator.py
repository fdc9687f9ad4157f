"""The referee: scores any plan on the true nonlinear capture problem.

Every formulation and backend is scored here, in plain NumPy, independently of
the CasADi expressions the formulations are built from. The objective is
Σ_k [ w_f |u'_a − u_a,k|²/v_a² + w_r Σ_i (|r_ai,k| − R_hunt/2)²/R_hunt²
      + w_m Σ_i |p_di,k − p_di,k−1|²/r_d,i² ] over controlled defenders i,
and each constraint's violation is its largest excess, in metres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mpc_hunt.capture_problem import CaptureProblem
from mpc_hunt.geometry import norm

VIOLATION_NAMES = ("motion_limit", "equal_distance", "obstacle_safety", "separation", "attacker_distance")


@dataclass(frozen=True)
class Evaluation:
    """The true objective of a plan, the attacker's predicted path and each constraint's violation."""

    objective: float
    violation: dict[str, float]
    attacker_path: np.ndarray  # (N, 2): the attacker at steps 1..N

    @property
    def max_violation(self) -> float:
        return max(self.violation.values())


def evaluate(problem: CaptureProblem, plan: np.ndarray) -> Evaluation:
    """Score ``plan`` (shape (N, n, 2): every defender at steps 1..N) on ``problem``."""
    plan = np.asarray(plan, dtype=float)
    N, n = problem.horizon, len(problem.controlled)
    if plan.shape != (N, n, 2):
        raise ValueError(f"plan: expected shape {(N, n, 2)}, got {plan.shape}")
    w, hunt, a = problem.weights, problem.scenario.hunt, problem.scenario.attacker
    c = problem.controlled
    r_d = np.where(c, problem.step_limits, 0.0)
    centres, radii = problem.scenario.obstacle_centres, problem.scenario.obstacle_radii

    objective = 0.0
    worst = dict.fromkeys(VIOLATION_NAMES, 0.0)
    p_a = problem.attacker_step(problem.attacker_position, problem.defender_positions)
    previous = problem.defender_positions
    path = []
    for k in range(N):
        p_d = plan[k]
        path.append(p_a)
        force_error = problem.desired_velocity - problem.resultant(p_a, p_d)
        dist = norm(p_a - p_d)
        step = p_d - previous
        objective += w.force * float(force_error @ force_error) / a.max_speed**2
        objective += w.ring * float(np.sum(((dist[c] - problem.ring_radius) / hunt.hunt_radius) ** 2))
        objective += w.move * float(np.sum(np.sum(step[c] ** 2, axis=1) / r_d[c] ** 2))

        worst["motion_limit"] = max(worst["motion_limit"], float(np.max(norm(step) - r_d)))
        worst["equal_distance"] = max(worst["equal_distance"], float(dist[c].max() - dist[c].min()))
        worst["attacker_distance"] = max(worst["attacker_distance"],
                                         float(np.max(hunt.min_attacker_distance - dist[c])))
        if len(radii):
            gap = norm(p_d[c][:, None, :] - centres[None]) - radii[None] - hunt.safety_distance
            worst["obstacle_safety"] = max(worst["obstacle_safety"], float(np.max(-gap)))
        for i in np.flatnonzero(c):
            others = np.arange(n) != i
            if others.any():
                sep = hunt.min_separation - norm(p_d[others] - p_d[i])
                worst["separation"] = max(worst["separation"], float(sep.max()))
        p_a = problem.attacker_step(p_a, p_d)
        previous = p_d
    violation = {k: max(v, 0.0) for k, v in worst.items()}
    return Evaluation(objective, violation, np.array(path))

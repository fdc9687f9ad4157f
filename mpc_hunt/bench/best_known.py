"""The reference of the optimality gap: a tightly converged multi-start NLP at each problem.

IPOPT (accuracy ``high``) from the plan that holds every defender and from
``starts − 1`` random plans, each a random walk within the motion limit drawn
with the generator handed in. The best start whose plan passes the success
rule is the reference; a compare run then takes the lower of it and every
pair's successful objective as the best known (:mod:`mpc_hunt.bench.compare`).
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.bench.metrics import is_success
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.solving.solver import CaptureSolver


def random_plan(problem: CaptureProblem, rng: np.random.Generator) -> np.ndarray:
    """Each controlled defender's random walk, every step uniform in the disc of radius r_d (Eq. 13 kept)."""
    plan = problem.held_plan().copy()
    c = np.flatnonzero(problem.controlled)
    position = problem.defender_positions[c].copy()
    for k in range(problem.horizon):
        angle = rng.uniform(0, 2 * np.pi, len(c))
        length = problem.step_limits[c] * np.sqrt(rng.uniform(0, 1, len(c)))
        position = position + length[:, None] * np.column_stack([np.cos(angle), np.sin(angle)])
        plan[k, c] = position
    return plan


class MultiStartNLP:
    """The reference solver; one persistent IPOPT, each start a one-shot solve (no duals)."""

    def __init__(self, starts: int, tolerance: float):
        self.starts = starts
        self.tolerance = tolerance
        self.solver = CaptureSolver("nlp", "ipopt", accuracy="high")

    def best(self, problem: CaptureProblem, rng: np.random.Generator, progress=None) -> float | None:
        """The lowest objective of a start that passes the success rule, or None if none does."""
        best = None
        plans = [problem.held_plan()] + [random_plan(problem, rng) for _ in range(self.starts - 1)]
        for plan in plans:
            solution = self.solver.solve(problem, plan)
            if is_success(solution.success, solution.violation, self.tolerance) and solution.objective is not None:
                best = solution.objective if best is None else min(best, solution.objective)
            if progress is not None:
                progress()
        return best

"""Which constraint families are active at a capture problem's optimum: the tags ``active:<family>``.

The optimum is the one-step NLP's (IPOPT, accuracy ``high``). An inequality
family (Eqs. 13, 15, separation, attacker distance) is active when one of its
rows is at its bound there, within ``ACTIVE_TOLERANCE`` metres either side (a
row the state already violates, relaxed by "never worse than now", does not
count). Eq. 14, an equality, holds at its bound whenever it holds; it is active
when it binds: when dropping it (its weight set to 0) yields a plan that keeps
every other constraint, scores lower on the rest of the objective, and leaves
the defenders' distances unequal. That plan is a certificate, so an unconverged
solve without Eq. 14 still counts.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mpc_hunt.capture.evaluator import VIOLATION_NAMES, Evaluation, evaluate
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.solving.solver import CaptureSolver

ACTIVE_TOLERANCE = 1e-6  # m
INEQUALITIES = tuple(name for name in VIOLATION_NAMES if name != "equal_distance")


def active_inequalities(evaluation: Evaluation) -> tuple[str, ...]:
    """The inequality families with a row at its bound at the plan ``evaluation`` scored."""
    return tuple(name for name in INEQUALITIES if abs(evaluation.margin[name]) <= ACTIVE_TOLERANCE)


def _rest(evaluation: Evaluation) -> float:
    return sum(value for term, value in evaluation.terms.items() if term != "equal_distance")


def binds(problem: CaptureProblem, optimum: Evaluation, free: Evaluation) -> bool:
    """Whether ``free``, a plan solved without Eq. 14, certifies that Eq. 14 binds at ``optimum``."""
    keeps_the_rest = all(free.violation[name] <= ACTIVE_TOLERANCE for name in INEQUALITIES)
    return bool(keeps_the_rest and free.margin["equal_distance"] < -ACTIVE_TOLERANCE and _rest(free) < _rest(optimum))


class ActivityProbe:
    """Solves one-step problems tightly (NLP on IPOPT, accuracy ``high``) to tell which families are active."""

    def __init__(self):
        self.solver = CaptureSolver("nlp", "ipopt", accuracy="high")

    def optimum(self, problem: CaptureProblem) -> np.ndarray | None:
        """The optimal plan, or None if the solve fails."""
        solution = self.solver.solve(problem)
        return solution.plan if solution.success else None

    def tags(self, problem: CaptureProblem) -> tuple[str, ...]:
        """``active:<family>`` for each family active at the optimum (see the module); none if the solve fails."""
        return self.examine(problem)[1]

    def examine(self, problem: CaptureProblem) -> tuple[float | None, tuple[str, ...]]:
        """The optimum's largest violation (None if the solve fails) and its ``active:<family>`` tags."""
        plan = self.optimum(problem)
        if plan is None:
            return None, ()
        optimum = evaluate(problem, plan)
        active = set(active_inequalities(optimum))
        if problem.controlled.sum() > 1:
            free = self.solver.solve(replace(problem, weights=replace(problem.weights, equal_distance=0.0)))
            if free.plan is not None and binds(problem, optimum, evaluate(problem, free.plan)):
                active.add("equal_distance")
        return optimum.max_violation, tuple(f"active:{name}" for name in VIOLATION_NAMES if name in active)

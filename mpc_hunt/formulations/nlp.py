"""``nlp``: the capture problem as it is (Eqs. 12–15), CasADi + IPOPT.

min  Σ_k |ε_k(X)|² + w_eq Σ_{k,i} s_ki / R_hunt²
s.t. |p_di,k − p_di,k−1|² ≤ r_d²                      (Eq. 13)
     −s_ki ≤ |r_ai,k|² − q_k ≤ s_ki,  s ≥ 0            (Eq. 14, exact L1 penalty)
     |p_di,k − c_o|² ≥ (r_o + R_safe)²                 (Eq. 15)
     |p_di,k − p_dj,k|² ≥ d_sep²,  |r_ai,k|² ≥ d_min²
with the attacker propagated through its APF dynamics inside ε and r_ai.
"""

from __future__ import annotations

from dataclasses import replace

import casadi as ca
import numpy as np

from mpc_hunt.capture.data import NLPData
from mpc_hunt.capture.evaluator import VIOLATION_NAMES
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.solution import Solution, WarmStart
from mpc_hunt.capture.structure import Structure
from mpc_hunt.formulations.base import Formulation, separation_pairs
from mpc_hunt.formulations.capture_model import capture_model, decision_point, parameter_vector


def nonlinear_constraints(model) -> tuple[ca.SX, list[float], list[float], list[str]]:
    """Eqs. 13, 15 and the separations as g with bounds; returns (g, lbg, ubg, family of each row)."""
    p, nc, nf, m, N = model.p, model.nc, model.nf, model.m, model.N
    g, lo, hi, family = [], [], [], []

    def add(expr, lower, upper, name):
        g.append(expr)
        lo.append(lower)
        hi.append(upper)
        family.append(name)

    for k in range(N):
        a = model.attacker[2 * k : 2 * k + 2]
        for i in range(nc):
            x = model.defender(k, i)
            step = x - model.previous(k, i)
            add(ca.dot(step, step) - p["step_limits"][i] ** 2, -ca.inf, 0.0, "motion_limit")
            for o in range(m):
                v = x - p["centres"][2 * o : 2 * o + 2]
                add(ca.dot(v, v) - (p["radii"][o] + p["safety_distance"]) ** 2, 0.0, ca.inf, "obstacle_safety")
            r = x - a
            add(ca.dot(r, r) - p["min_attacker_distance"] ** 2, 0.0, ca.inf, "attacker_distance")
        for i, j in separation_pairs(nc, nf):
            v = model.defender(k, i) - (model.defender(k, j) if j < nc else model.held(j - nc))
            add(ca.dot(v, v) - p["min_separation"] ** 2, 0.0, ca.inf, "separation")
    return ca.vertcat(*g), lo, hi, family


RELAXABLE = ("obstacle_safety", "attacker_distance", "separation")


def arena_bounds(problem: CaptureProblem) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) of a defender's (x, y): with the enclose objective, the scenario's arena; else none (±inf).

    A defender already outside is bounded by where it stands (never worse than now). The paper's
    objective keeps its problem as it was (and the committed results their numbers).
    """
    arena = problem.scenario.arena
    if arena is None or problem.objective != "enclose":
        return np.full(2, -np.inf), np.full(2, np.inf)
    here = problem.defender_positions[problem.controlled]
    return np.minimum(arena[:2], here.min(axis=0)), np.maximum(arena[2:], here.max(axis=0))


class ConstraintSet:
    """The constraints of one structure: g(X, θ), its bounds and the rows relaxed to the held plan."""

    def __init__(self, structure: Structure):
        model = capture_model(structure)
        self.g, lo, hi, family = nonlinear_constraints(model)
        self.lower, self.upper = np.array(lo, dtype=float), np.array(hi, dtype=float)
        self.relax = np.array([f in RELAXABLE for f in family], dtype=bool)
        self.function = ca.Function("constraints", [model.X, model.theta], [self.g])


def relaxed_lower_bounds(lower: np.ndarray, relax: np.ndarray, held_values: np.ndarray) -> np.ndarray:
    """Never worse than now: a ≥-constraint the current state violates is relaxed to its current value.

    Holding position then always satisfies the problem, so it stays feasible
    after a disturbance; the evaluator still reports the violation against the
    true bound.
    """
    out = lower.copy()
    out[relax] = np.minimum(lower[relax], held_values[relax])
    return out


class NLPFormulation(Formulation[ConstraintSet]):
    """The true problem, expanded to SX, parametric in the state; warm-started by a shifted plan."""

    name = "nlp"
    kind = "nlp"
    default_backend = "ipopt"
    exact = frozenset(VIOLATION_NAMES)
    construction = ConstraintSet

    def _nlp(self, structure: Structure) -> dict:
        model = capture_model(structure)
        nc, N = model.nc, model.N
        q = ca.SX.sym("q", N)
        s = ca.SX.sym("s", N * nc)
        g = self.built(structure).g
        equal = []
        for k in range(N):
            for i in range(nc):
                gap = model.squared_distance[k * nc + i] - q[k]
                equal += [gap - s[k * nc + i], gap + s[k * nc + i]]
        f = ca.sumsqr(model.residual) + model.p["w_equal"] * ca.sum1(s) / model.p["hunt_radius"] ** 2
        return {"x": ca.vertcat(model.X, q, s), "p": model.theta, "f": f, "g": ca.vertcat(g, *equal)}

    def data(self, problem: CaptureProblem) -> NLPData:
        structure = problem.structure
        model = capture_model(structure)
        nc, N = model.nc, model.N
        constraints = self.built(structure)
        theta = parameter_vector(problem)
        held = np.array(constraints.function(problem.x_from_plan(problem.held_plan()), theta)).ravel()
        lo = relaxed_lower_bounds(constraints.lower, constraints.relax, held)
        lbg = np.concatenate([lo, np.tile([-np.inf, 0.0], N * nc)])
        ubg = np.concatenate([constraints.upper, np.tile([0.0, np.inf], N * nc)])
        low, high = arena_bounds(problem)
        lbx = np.concatenate([np.tile(low, N * nc), np.zeros(N + N * nc)])
        ubx = np.concatenate([np.tile(high, N * nc), np.full(N + N * nc, np.inf)])
        return NLPData(("nlp", structure), lambda: self._nlp(structure), theta, lbx, ubx, lbg, ubg)

    def solve(self, problem, backend, warm_plan, duals) -> Solution:
        data = self.data(problem)
        plan0 = problem.held_plan() if warm_plan is None else warm_plan
        warm = WarmStart(
            decision_point(problem, problem.x_from_plan(plan0), data.p),
            None if duals is None else duals.y,
            None if duals is None else duals.z,
        )
        result = backend.solve(data, warm)
        return replace(result, plan=None if result.x is None else problem.plan_from_x(result.x))

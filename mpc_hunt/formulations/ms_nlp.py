"""``ms-nlp``: the capture problem (Eqs. 12–15) in multiple-shooting form, on the smoothed field.

The same problem as ``nlp`` (Eq. 14 as the same exact L1 penalty), posed with
the attacker's and the defenders' positions at every step as variables, tied
by the dynamics as equality constraints (:mod:`mpc_hunt.formulations.stage_model`), and
declared stage by stage, so that the Jacobian and the Hessian are block-banded:

    w = (u_0, x_1, u_1, …, x_N, u_N),  u_0 = Δp_d,0,
    u_k = (Δp_d,k, q_k, s_k) (0 < k < N),  u_N = (q_N, s_N),
    g = (x_1 − f(x_0, u_0), c_0(u_0), x_2 − f(x_1, u_1), c_1(x_1, u_1), …, c_N(x_N, u_N)),

with the current state x_0 a parameter (fixing it by bounds lbx = ubx would give
an interior-point method a zero-width inequality). This is the order a
structure-exploiting solver reads (kind ``ocp-nlp``; docs/architecture.md);
IPOPT takes it as any NLP, and its sparse factorisation then works on a banded
system. The optimiser's field is rounded on a band of half-width
``smoothing`` around its kinks (docs/model.md, E11); ``smoothing = 0`` poses
``nlp``'s problem exactly.
"""

from __future__ import annotations

from dataclasses import replace

import casadi as ca
import numpy as np

from mpc_hunt.capture.data import NLPData
from mpc_hunt.capture.solution import Solution, WarmStart
from mpc_hunt.capture.structure import Structure
from mpc_hunt.formulations.base import Formulation
from mpc_hunt.formulations.capture_model import parameter_size, parameter_vector, stage_parameters, unpack
from mpc_hunt.formulations.nlp import RELAXABLE, arena_bounds
from mpc_hunt.formulations.stage_model import SMOOTHING, stage_model


class StagedNLP:
    """The multiple-shooting NLP of one structure, its starting point and its read-back (built once)."""

    def __init__(self, structure: Structure):
        nc, N = structure.planned, structure.horizon
        sm = stage_model(structure)
        theta = ca.SX.sym("theta", parameter_size(structure) + 1)

        def stage(k):  # θ of stage k ≥ 1 (its own step of the reference)
            return stage_parameters(theta, structure, max(k, 1))

        p = unpack(theta, structure)
        D = ca.SX.sym("D", N * 2 * nc)  # the controlled defenders' plan, steps 1..N
        x = x_guess = ca.vertcat(p["attacker"], p["controlled"])  # x_0: the state, a parameter
        # The first move of the attacker follows from the state alone: the paper's field, unsmoothed.
        exact = ca.vertcat(stage(1)[:-1], 0)
        # Rows in units of one step (Eq. 13 per r_d², distances per r̄_d): IPOPT's tolerances and bound
        # relaxation (1e-8 in a row's units) then move a robot by ~1e-10 m, not ~1e-7 m, so a plan the
        # world caps at the robot's speed lands where it was planned (docs/robustness.md).
        length = ca.sum1(p["step_limits"]) / nc
        w_parts: list[ca.SX] = []
        guess_parts: list[ca.SX] = []
        g_parts: list[ca.SX] = []
        f: ca.SX | float = 0
        lbg, ubg, relax = [], [], []
        kind_parts: list[np.ndarray] = []

        def rows(expr, lower, upper, relaxable):
            g_parts.append(expr)
            lbg.extend(np.broadcast_to(lower, expr.shape[0]))
            ubg.extend(np.broadcast_to(upper, expr.shape[0]))
            relax.extend(np.broadcast_to(relaxable, expr.shape[0]))

        for k in range(N + 1):
            u, u_guess, u_kinds = [], [], []
            if k < N:
                du = ca.SX.sym(f"du{k}", sm.nu)
                u.append(du)
                u_guess.append(D[sm.nu * k : sm.nu * (k + 1)] - x_guess[2:])
                u_kinds += ["move"] * sm.nu
            if k > 0:
                q, s = ca.SX.sym(f"q{k}"), ca.SX.sym(f"s{k}", nc)
                sq_guess = sm.squared_distance(x_guess)
                q_guess = ca.sum1(sq_guess) / nc
                u += [q, s]
                u_guess += [q_guess, ca.fabs(sq_guess - q_guess)]
                u_kinds += ["q"] + ["s"] * nc
            w_parts.append(ca.vertcat(*u))
            guess_parts.append(ca.vertcat(*u_guess))
            kind_parts.append(np.array(u_kinds, dtype=object))
            if k < N:
                x_next = ca.SX.sym(f"x{k + 1}", sm.nx)
                rows(x_next - sm.dynamics(x, du, exact if k == 0 else stage(k)), 0.0, 0.0, False)
                steps, limits = sm.motion(du, stage(k))
                rows(steps / limits - 1, -np.inf, 0.0, False)  # Eq. 13, per r_d²
                f += ca.sumsqr(sm.move(du, stage(k)))
            if k > 0:
                values, lower = sm.path(x, stage(k))
                rows((values - lower) / length, 0.0, np.inf, np.array([fam in RELAXABLE for fam in sm.families]))
                gap = sm.squared_distance(x) - q  # Eq. 14, exact L1
                rows(gap - s, -np.inf, 0.0, False)
                rows(gap + s, 0.0, np.inf, False)
                f += ca.sumsqr(sm.residual(x, stage(k))) + p["w_equal"] * ca.sum1(s) / p["hunt_radius"] ** 2
            if k < N:
                x_guess = sm.dynamics(x_guess, u_guess[0], exact if k == 0 else stage(k))
                x = x_next
                w_parts.append(x)
                guess_parts.append(x_guess)
                kind_parts.append(np.full(sm.nx, "state", dtype=object))
        w, g = ca.vertcat(*w_parts), ca.vertcat(*g_parts)
        self.problem = {"x": w, "p": theta, "f": f, "g": g}
        self.nc = nc
        self.lbg, self.ubg, self.relax = np.array(lbg), np.array(ubg), np.array(relax, dtype=bool)
        kinds = np.concatenate(kind_parts)
        self.slack = kinds == "s"
        state = np.flatnonzero(kinds == "state")
        self.plan_index = state.reshape(N, sm.nx)[:, 2:].ravel()  # p_d,k for k = 1..N
        guess = ca.vertcat(*guess_parts)
        held = ca.repmat(p["controlled"], N, 1)
        at_held = ca.substitute(g, w, ca.substitute(guess, D, held))
        self.start = ca.Function("start", [theta, D], [guess, at_held])

    def bounds(self, theta: np.ndarray, D: np.ndarray) -> tuple[np.ndarray, ...]:
        """(w0 from the plan D, lbx, ubx, lbg relaxed to the held plan: never worse than now)."""
        w0, at_held = self.start(theta, D)
        w0 = np.array(w0).ravel()
        lbx, ubx = np.full(w0.shape, -np.inf), np.full(w0.shape, np.inf)
        lbx[self.slack] = 0.0
        lbg = self.lbg.copy()
        lbg[self.relax] = np.minimum(lbg[self.relax], np.array(at_held).ravel()[self.relax])
        return w0, lbx, ubx, lbg


class MSNLPFormulation(Formulation[StagedNLP]):
    """The true problem in stage form (multiple shooting), warm-started by the shifted plan."""

    name = "ms-nlp"
    kind = "ocp-nlp"
    default_backend = "ipopt"
    smoothing = SMOOTHING
    construction = StagedNLP

    def solve(self, problem, backend, warm_plan, duals) -> Solution:
        nlp = self.built(problem.structure)
        theta = np.append(parameter_vector(problem), self.smoothing)
        plan0 = problem.held_plan() if warm_plan is None else warm_plan
        w0, lbx, ubx, lbg = nlp.bounds(theta, problem.x_from_plan(plan0))
        low, high = arena_bounds(problem)
        lbx[nlp.plan_index] = np.tile(low, problem.horizon * nlp.nc)
        ubx[nlp.plan_index] = np.tile(high, problem.horizon * nlp.nc)
        data = NLPData(("ms-nlp", problem.structure), lambda: nlp.problem, theta, lbx, ubx, lbg, nlp.ubg, self.kind)
        result = backend.solve(
            data, WarmStart(w0, None if duals is None else duals.y, None if duals is None else duals.z)
        )
        if result.x is None:
            return result
        plan = problem.held_plan().copy()
        plan[:, problem.controlled] = result.x[nlp.plan_index].reshape(problem.horizon, -1, 2)
        return replace(result, plan=plan)

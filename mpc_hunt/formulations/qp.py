"""``qp``: the capture problem linearised around a reference plan, a convex QP.

Around the reference X̄ (the previous plan shifted one step, or every defender
held), in the step δ = X − X̄ (so that the data stay of the order of the
objective, which absolute positions would swamp): the objective's residuals ε(X) ≈ ε(X̄) + J (X − X̄) (Gauss–Newton, so
P = 2JᵀJ is positive semidefinite), the attacker's path through the Jacobian
of its APF dynamics, Eq. 14 through the linearised squared distances, Eq. 15
and the separations as tangent half-planes (inner approximations: a feasible
QP point keeps the true distances), Eq. 13 as an inscribed regular polygon,
and a trust region |X − X̄|∞ ≤ 2 r_d. The matrices' sparsity is fixed per
structure; each step only changes their values.
"""

from __future__ import annotations

import threading
from dataclasses import replace

import casadi as ca
import numpy as np
import scipy.sparse as sp

from mpc_hunt.capture.data import QPData
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.solution import Solution, WarmStart
from mpc_hunt.capture.structure import Structure
from mpc_hunt.formulations.base import Formulation, separation_pairs
from mpc_hunt.formulations.capture_model import capture_model, decision_point, parameter_vector
from mpc_hunt.formulations.field import unit

POLYGON_SIDES = 8
TRUST_REGION = 2.0  # in units of r_d


class LinearisedCapture:
    """The QP's data as one CasADi function of (θ, X̄), with fixed output sparsity."""

    def __init__(self, structure: Structure, exact_motion_cone: bool = False):
        model = capture_model(structure)
        p, nc, nf, m, N = model.p, model.nc, model.nf, model.m, model.N
        X, theta = model.X, model.theta
        nX = N * nc * 2
        Xref = ca.SX.sym("Xref", nX)
        delta = ca.SX.sym("delta", nX)  # the decision is the step from the reference: X = X̄ + δ
        q, s = ca.SX.sym("q", N), ca.SX.sym("s", N * nc)
        x = ca.vertcat(delta, q, s)

        def at_ref(expr):
            return ca.substitute(expr, X, Xref)

        J = at_ref(ca.jacobian(model.residual, X))
        eps_ref = at_ref(model.residual)
        a_ref = at_ref(model.attacker)
        a_lin = a_ref + ca.mtimes(at_ref(ca.jacobian(model.attacker, X)), X - Xref)

        Jx = ca.horzcat(J, ca.SX(J.shape[0], N + N * nc))
        c = eps_ref
        lin = ca.vertcat(ca.SX(nX + N, 1), ca.SX.ones(N * nc) * p["w_equal"] / p["hunt_radius"] ** 2)
        P = 2 * ca.mtimes(Jx.T, Jx)
        qvec = 2 * ca.mtimes(Jx.T, c) + lin

        rows, lo, hi, relax, family, self.cones = [], [], [], [], [], []

        def add(expr, lower, upper, name, relaxable=False):
            rows.append(expr)
            lo.append(lower)
            hi.append(upper)
            relax.extend([relaxable] * expr.shape[0])
            family.extend([name] * expr.shape[0])

        step_limits = ca.vertcat(*[ca.repmat(p["step_limits"][i], 2, 1) for i in range(nc)])
        region = TRUST_REGION * ca.repmat(step_limits, N, 1)
        low, high = -region, region
        if model.objective == "enclose":  # the arena bounds every plan (never worse than the reference)
            low = ca.fmax(low, ca.fmin(ca.repmat(p["arena"][:2], N * nc, 1) - Xref, 0))
            high = ca.fmin(high, ca.fmax(ca.repmat(p["arena"][2:], N * nc, 1) - Xref, 0))
        add(X - Xref, low, high, "trust_region")
        # s ≥ 0 is implied by Eq. 14's two elastic rows below (s ≥ |d² − q|), so it is marked: a solver may drop
        # it. ADMM (OSQP) converges faster with it; an active-set method (DAQP) cycles on it, 30 linearly
        # dependent active rows at N = 10 (105 active, rank 75) (docs/benchmarks.md, "The QP in its own loop").
        add(s, ca.SX.zeros(N * nc), ca.inf * ca.SX.ones(N * nc), "equal_distance")
        n_rows = nX + N * nc
        for k in range(N):
            a_k, a_ref_k = a_lin[2 * k : 2 * k + 2], a_ref[2 * k : 2 * k + 2]
            for i in range(nc):
                xi, xi_ref = model.defender(k, i), Xref[(k * nc + i) * 2 : (k * nc + i) * 2 + 2]
                step = xi - model.previous(k, i)
                if exact_motion_cone:  # b − A x = (r_d, step) ∈ SOC
                    self.cones.append((n_rows, 3))
                    add(
                        ca.vertcat(0, -step),
                        -ca.inf * ca.SX.ones(3),
                        ca.vertcat(p["step_limits"][i], 0, 0),
                        "motion_limit",
                    )
                    n_rows += 3
                else:
                    for j in range(POLYGON_SIDES):
                        angle = 2 * np.pi * j / POLYGON_SIDES
                        normal = ca.DM([np.cos(angle), np.sin(angle)])
                        add(
                            ca.dot(normal, step),
                            -ca.inf,
                            p["step_limits"][i] * np.cos(np.pi / POLYGON_SIDES),
                            "motion_limit",
                        )
                        n_rows += 1
                for o in range(m):
                    centre = p["centres"][2 * o : 2 * o + 2]
                    add(
                        ca.dot(unit(xi_ref - centre), xi - centre) - p["radii"][o] - p["safety_distance"],
                        0.0,
                        ca.inf,
                        "obstacle_safety",
                        True,
                    )
                    n_rows += 1
                add(
                    ca.dot(unit(xi_ref - a_ref_k), xi - a_k) - p["min_attacker_distance"],
                    0.0,
                    ca.inf,
                    "attacker_distance",
                    True,
                )
                r_ref = xi_ref - a_ref_k
                d2 = ca.dot(r_ref, r_ref) + 2 * ca.dot(r_ref, (xi - xi_ref) - (a_k - a_ref_k))
                add(d2 - q[k] - s[k * nc + i], -ca.inf, 0.0, "equal_distance")
                add(d2 - q[k] + s[k * nc + i], 0.0, ca.inf, "equal_distance")
                n_rows += 3
            for i, j in separation_pairs(nc, nf):
                xi = model.defender(k, i)
                xj = model.defender(k, j) if j < nc else model.held(j - nc)
                xi_ref = Xref[(k * nc + i) * 2 : (k * nc + i) * 2 + 2]
                xj_ref = Xref[(k * nc + j) * 2 : (k * nc + j) * 2 + 2] if j < nc else model.held(j - nc)
                add(ca.dot(unit(xi_ref - xj_ref), xi - xj) - p["min_separation"], 0.0, ca.inf, "separation", True)
                n_rows += 1
        g = ca.substitute(ca.vertcat(*rows), X, Xref + delta)
        self.relax = np.array(relax, dtype=bool)
        self.family = np.array(family)  # each row's constraint family (evaluator names, or "trust_region")
        self.implied = np.zeros(len(self.family), dtype=bool)  # rows the others imply: the s ≥ 0 rows
        self.implied[nX : nX + N * nc] = True
        A = ca.jacobian(g, x)
        b0 = ca.substitute(g, x, ca.DM.zeros(x.shape))
        # Never worse than now (as nlp): a row that the held plan breaks is relaxed to the held plan's
        # value of the distance it bounds (a tangent row at the held plan is that distance), wherever the
        # reference lies; its inner approximation then keeps the true distance at least as large.
        at_held = ca.substitute(b0, Xref, ca.repmat(p["controlled"], N, 1))
        lower = ca.vertcat(*lo)
        lower = ca.if_else(ca.DM(self.relax), ca.fmin(lower, at_held), lower) - b0
        self.function = ca.Function(
            "capture_qp", [theta, Xref], [ca.triu(P), qvec, A, lower, ca.vertcat(*hi) - b0, Jx, c, lin]
        )
        # The function evaluated through CasADi's buffers: its outputs written straight into fresh NumPy arrays
        # (the nonzeros, placed), no conversion of CasADi matrices per step; one buffer per thread.
        self._local = threading.local()
        self._outputs = [self.function.sparsity_out(i) for i in range(self.function.n_out())]
        self._csc_index = {i: tuple(np.array(v) for v in self._outputs[i].get_ccs()) for i in (0, 2)}
        self._places = {i: np.array(pattern.find()) for i, pattern in enumerate(self._outputs) if i not in (0, 2)}
        j_rows = self._outputs[5].size1()
        self.J_pattern = (self._places[5] % j_rows, self._places[5] // j_rows)  # J's structural nonzeros

    def data(self, key: tuple, theta: np.ndarray, Xref: np.ndarray) -> QPData:
        """The QP at reference X̄ in x = (δ, q, s)."""
        theta, Xref = np.ascontiguousarray(theta, dtype=float), np.ascontiguousarray(Xref, dtype=float)
        out = [np.empty(pattern.nnz()) for pattern in self._outputs]
        local = self._local
        if not hasattr(local, "buffer"):
            local.buffer, local.evaluate = self.function.buffer()
        local.buffer.set_arg(0, theta.data)
        local.buffer.set_arg(1, Xref.data)
        for i, values in enumerate(out):
            local.buffer.set_res(i, values.data)
        local.evaluate()
        local.bound = theta, Xref, out  # the buffer keeps their addresses: kept alive until the next evaluation
        q, l, u, J, c, lin = (self._dense(i, out[i]) for i in (1, 3, 4, 5, 6, 7))
        return QPData(
            key,
            self._csc(0, out[0]),
            q.ravel(),
            self._csc(2, out[2]),
            l.ravel(),
            u.ravel(),
            J,
            c.ravel(),
            lin.ravel(),
            tuple(self.cones),
            self.implied,
            self.J_pattern,
        )

    def _csc(self, i: int, values: np.ndarray) -> sp.csc_matrix:
        colind, row = self._csc_index[i]
        return sp.csc_matrix((values, row, colind), shape=self._outputs[i].shape)

    def _dense(self, i: int, values: np.ndarray) -> np.ndarray:
        rows, cols = self._outputs[i].shape
        dense = np.zeros(rows * cols)
        dense[self._places[i]] = values  # column-major places of the nonzeros
        return dense.reshape(cols, rows).T


class QPFormulation(Formulation[LinearisedCapture]):
    """One linearisation, one convex QP, solved by a persistent QP backend."""

    name = "qp"
    kind = "qp"
    default_backend = "osqp"
    construction = LinearisedCapture
    construction_options = (False,)  # Eq. 13 as an inscribed polygon, not its exact cone

    def solve_at(
        self, problem: CaptureProblem, backend, reference: np.ndarray, theta: np.ndarray, duals: WarmStart | None
    ) -> Solution:
        """Solve the QP linearised at the plan ``reference``; ``x`` and ``plan`` in absolute positions."""
        lin = self.built(problem.structure)
        Xref = problem.x_from_plan(reference)
        guess = decision_point(problem, Xref, theta)
        guess[: len(Xref)] = 0.0
        data = lin.data((self.name, problem.structure), theta, Xref)
        result = backend.solve(data, WarmStart(guess, None if duals is None else duals.y))
        if result.x is None:
            return result
        # Row sums, not BLAS: the reported objective's bits do not depend on the CPU (docs/robustness.md).
        residual = np.sum(data.J * result.x, axis=1) + data.c
        x = np.concatenate([Xref + result.x[: len(Xref)], result.x[len(Xref) :]])
        return replace(
            result,
            x=x,
            plan=problem.plan_from_x(x),
            formulation_objective=float(np.sum(residual**2) + np.sum(data.lin * result.x)),
        )

    def solve(self, problem, backend, warm_plan, duals) -> Solution:
        reference = problem.held_plan() if warm_plan is None else warm_plan
        return self.solve_at(problem, backend, reference, parameter_vector(problem), duals)

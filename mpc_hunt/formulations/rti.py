"""``rti``: a real-time iteration, one Gauss–Newton QP per control step, in stage form.

Around the reference (the previous plan shifted one step, or every defender
held), rolled out through the attacker's dynamics from the current state, the
multiple-shooting model is linearised stage by stage
(:mod:`mpc_hunt.formulations.stage_linearisation`) as ``qp`` linearises the condensed
one: Gauss–Newton objective, tangent half-planes for Eq. 15, the separations
and the attacker distance, Eq. 14's exact L1 penalty through the squared
distances, Eq. 13 as the inscribed octagon, the trust region |δp_d| ≤ 2 r_d,
"never worse than now". In stage order it is an optimal-control QP (kind
``ocp-qp``):

    z = (ξ_0, ν_0, ξ_1, ν_1, …, ξ_N),  ξ_0 = 0,
    rows = (gap_0, c_0, gap_1, c_1, …, c_N),  gap_k: ξ_k+1 + G_x ξ_k + G_u ν_k = 0.

Eq. 14's rows for step k+1 sit on stage k (through the dynamics), because the
last stage has no controls to hold their slacks. The QP's data, the QP and the
plan form one CasADi graph, which the backend closes with its solver into one
Function: a control step is one call, with no Python loop and no matrix built
in Python. Where no distance lies in the smoothing band, its QP is ``qp``'s.
"""

from __future__ import annotations

from dataclasses import replace

import casadi as ca
import numpy as np

from mpc_hunt.capture.data import StageQPData
from mpc_hunt.capture.iteration import ONE_QP
from mpc_hunt.capture.solution import Solution
from mpc_hunt.capture.structure import Structure
from mpc_hunt.formulations.base import Formulation
from mpc_hunt.formulations.capture_model import parameter_size, parameter_writer, stage_parameters, unpack
from mpc_hunt.formulations.nlp import RELAXABLE
from mpc_hunt.formulations.qp import TRUST_REGION
from mpc_hunt.formulations.stage_linearisation import stage_linearisation
from mpc_hunt.formulations.stage_model import SMOOTHING, stage_model


def _place(block, left: int, total: int):
    """``block`` between ``left`` zero columns and enough zero columns to make ``total``."""
    return ca.horzcat(ca.SX(block.shape[0], left), block, ca.SX(block.shape[0], total - left - block.shape[1]))


class LinearisedStages:
    """The stage-structured QP of one structure, as CasADi expressions of (θ, reference plan)."""

    def __init__(self, structure: Structure):
        nc, N, objective = structure.planned, structure.horizon, structure.objective
        sm = stage_model(structure)
        st = stage_linearisation(structure)
        nx, nd, nu = st.nx, st.nd, st.nu
        theta = ca.SX.sym("theta", parameter_size(structure) + 1)
        D = ca.SX.sym("D", N * nd)  # the reference plan, steps 1..N

        def stage(k):  # θ of stage k (its own reference)
            return stage_parameters(theta, structure, k)

        p = unpack(theta, structure)
        S_x = st.S_x(stage(1))
        exact = ca.vertcat(stage(0)[:-1], 0)
        relaxable = ca.DM([f in RELAXABLE for f in st.families])
        # A robot planning apart (``distributed``) relaxes its separation rows to its reference's values, not the
        # held plan's: its team-mates keep theirs to the same midpoints from their references, so where it stands
        # may be where one of them plans to go; a round's references are d_min apart whenever the last plans were,
        # and the rows then hold unrelaxed.
        from_reference = ca.DM([f == "separation" for f in st.families])
        nz = (N + 1) * nx + N * nu
        x_ref, hessian, gradient, rows, lower, lbz, ubz, ng = [], [], [], [], [], [], [], []
        upper: list[ca.SX | ca.DM] = []  # a DM (+inf) for the path rows, which have no upper bound
        constant = 0  # |ε|² at the reference
        x_ref.append(ca.vertcat(p["attacker"], p["controlled"]))
        held = [x_ref[0]]  # the held plan: "never worse than now"
        for k in range(N + 1):
            col = k * (nx + nu)  # where ξ_k starts in z
            c_rows, c_lower, c_upper = [], [], []  # c_k: the stage's rows
            if k == 0:
                hessian.append(ca.SX(nx, nx))
                gradient.append(ca.SX(nx, 1))
                lbz.append(ca.DM.zeros(nx))
                ubz.append(ca.DM.zeros(nx))
            else:
                r, J, c, C = st.state(x_ref[k], stage(k))
                constant += ca.sumsqr(r)
                hessian.append(2 * ca.mtimes(J.T, J))
                gradient.append(2 * ca.mtimes(J.T, r))
                low = high = TRUST_REGION * ca.DM.ones(nd)
                low = -low
                if objective == "enclose":  # the arena bounds every plan (never worse than the reference)
                    scale, here = S_x[2:], x_ref[k][2:]
                    low = ca.fmax(low, ca.fmin((ca.repmat(p["arena"][:2], nc, 1) - here) / scale, 0))
                    high = ca.fmin(high, ca.fmax((ca.repmat(p["arena"][2:], nc, 1) - here) / scale, 0))
                lbz.append(ca.vertcat(-ca.inf, -ca.inf, low))
                ubz.append(ca.vertcat(ca.inf, ca.inf, high))
                # Path rows c + C ξ ≥ 0, those the held plan breaks relaxed to its values (as nlp): their inner
                # approximation then keeps each true distance at least as large as holding would.
                at_held = st.state(held[k], stage(k))[2]
                if structure.robot:
                    at_held = ca.if_else(from_reference, c, at_held)
                c_rows.append(_place(C, col, nz))
                c_lower.append(ca.if_else(relaxable, ca.fmin(at_held, 0), 0) - c)
                c_upper.append(ca.DM.inf(c.shape[0]))
            if k < N:
                u_ref = D[nd * k : nd * (k + 1)] - x_ref[k][2:]
                # The attacker's first move follows from the state alone: the paper's field, unsmoothed.
                move, M, nxt, G_x, G_u, c, C_x, C_u, penalty = st.control(
                    x_ref[k], u_ref, exact if k == 0 else stage(k)
                )
                constant += ca.sumsqr(move)
                x_ref.append(nxt)
                held.append(sm.dynamics(held[k], ca.DM.zeros(nd), exact if k == 0 else stage(k)))
                hessian.append(2 * ca.mtimes(M.T, M))
                gradient.append(2 * ca.mtimes(M.T, move) + penalty)
                lo, hi, lo_rows, hi_rows = st.control_bounds(u_ref, stage(k))
                lbz.append(lo)
                ubz.append(hi)
                # gap_k: ξ_k+1 + G_x ξ_k + G_u ν_k = 0 (the reference has no gaps)
                rows.append(_place(ca.horzcat(G_x, G_u, ca.SX.eye(nx)), col, nz))
                lower.append(ca.SX.zeros(nx))
                upper.append(ca.SX.zeros(nx))
                c_rows.append(_place(ca.horzcat(C_x, C_u), col, nz))
                c_lower.append(lo_rows - c)
                c_upper.append(hi_rows - c)
            rows += c_rows
            lower += c_lower
            upper += c_upper
            ng.append(sum(row.shape[0] for row in c_rows))
        self.inputs = [theta, D]
        self.z = ca.SX.sym("z", nz)
        self.qp = {
            "h": ca.diagcat(*hessian),
            "g": ca.vertcat(*gradient),
            "a": ca.vertcat(*rows),
            "lba": ca.vertcat(*lower),
            "uba": ca.vertcat(*upper),
            "lbx": ca.vertcat(*lbz),
            "ubx": ca.vertcat(*ubz),
        }
        xi = [self.z[k * (nx + nu) : k * (nx + nu) + nx] for k in range(N + 1)]
        self.plan = ca.vertcat(*[x_ref[k][2:] + S_x[2:] * xi[k][2:] for k in range(1, N + 1)])
        h, g = self.qp["h"], self.qp["g"]
        self.cost = constant + 0.5 * ca.bilin(h, self.z, self.z) + ca.dot(g, self.z)  # the model's objective
        self.stages = (N, [nx] * (N + 1), [nu] * N + [0], ng)


class RTIFormulation(Formulation[LinearisedStages]):
    """One Gauss–Newton QP per step in stage form; linearisation, QP and plan in one call."""

    name = "rti"
    kind = "ocp-qp"
    default_backend = "hpipm"
    smoothing = SMOOTHING
    construction = LinearisedStages
    # QPs a control step makes and the move that ends them, read by the control loop and the C export:
    # one QP, linearised once (stage-sqp repeats it).
    iteration = ONE_QP

    def stage_data(self, structure: Structure, args: tuple = ()) -> StageQPData:
        """The stage QP of ``structure`` for a backend to close, with the inputs ``args`` of one solve."""
        return StageQPData((self.name, structure), lambda: self.built(structure), args)

    def step_inputs(self, problem, warm_plan=None) -> tuple[np.ndarray, np.ndarray]:
        """The step's inputs at ``problem``: θ (the parameter vector, then the smoothing) and the reference
        (``warm_plan``'s controlled positions, else every defender held), both flat."""
        theta, reference = np.empty(parameter_size(problem.structure) + 1), np.empty(problem.structure.plan_size)
        self.write_inputs(problem, warm_plan, theta, reference)
        return theta, reference

    def write_inputs(self, problem, warm_plan, theta: np.ndarray, reference: np.ndarray) -> None:
        """:meth:`step_inputs` written into the flat arrays ``theta`` and ``reference`` (a control loop's)."""
        parameter_writer(problem.structure).write(problem, theta)
        theta[-1] = self.smoothing
        if not reference.flags.c_contiguous:
            raise ValueError("the reference is written into a contiguous array")
        positions = problem.defender_positions[None] if warm_plan is None else np.asarray(warm_plan, dtype=float)
        structure = problem.structure
        reference.reshape(structure.horizon, structure.planned, 2)[...] = (
            positions[:, problem.controlled] if structure.fixed else positions
        )

    def parameter_parts(self, theta: np.ndarray, structure: Structure) -> dict[str, np.ndarray]:
        """θ's named parts (the parameter vector's layout, then ``smoothing``) as views of the array ``theta``."""
        return {**unpack(theta, structure), "smoothing": theta[-1:]}

    def solve(self, problem, backend, warm_plan, duals) -> Solution:
        data = self.stage_data(problem.structure, self.step_inputs(problem, warm_plan))
        result = backend.solve(data, duals)
        return result if result.x is None else replace(result, plan=problem.plan_from_x(result.x))

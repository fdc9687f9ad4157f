"""The capture problem stage by stage (multiple shooting), on the optimiser's smoothed field.

Stage k = 0..N has the state x_k = (p_a,k, p_di,k for i ∈ C) and, for k < N,
the control u_k = p_d,k+1 − p_d,k (Eq. 1). The attacker's dynamics (Eqs. 2, 9)

    x_{k+1} = f(x_k, u_k) = (p_a,k + T sat_{v_a}(u_a(p_a,k, p_d,k)), p_d,k + u_k)

tie consecutive stages, so every other term touches one stage only: the
residuals of step k (Eq. 12's force error, the ring) depend on x_k, the
smoothness term and Eq. 13 on u_{k−1}, Eq. 15, the separations and the
attacker distance on x_k. Written once per structure (controlled, held,
obstacles) as functions of one stage; a formulation lays them out over the
horizon. θ is :func:`mpc_hunt.formulations.capture_model.parameter_vector` followed by
the smoothing half-width w of :mod:`mpc_hunt.formulations.field` (w = 0: the
paper's field).

A robot planning apart (``Structure.robot``, the ``distributed`` formulation)
has the state (p_a, p_d) of itself alone. The rest of the team pushes the
attacker by F_k + J_k (p_a − ā_k), its push at the attacker's position ā_k
predicted under the team's plans, to first order (exact at ā_k, where the
robot's QP is linearised); its separation rows are to the midpoints m_j between
its planned and each neighbour's planned position, |p_d − m_j| ≥ d_min / 2,
so that two robots that each keep theirs are d_min apart whatever both do.
"""

from __future__ import annotations

from functools import lru_cache

import casadi as ca

from mpc_hunt.capture.structure import Structure
from mpc_hunt.formulations.base import separation_pairs
from mpc_hunt.formulations.capture_model import enclose_residuals, parameter_size, step_reference, team_step, unpack
from mpc_hunt.formulations.field import norm, obstacle_repulsion, repulsion, saturate

SMOOTHING = 0.001  # m: half-width of the band around R_agg (and the obstacles' range) where H is rounded (E11)


class StageModel:
    """CasADi functions of one stage for one structure (its planned and held defenders, obstacles, objective).

    With the ``enclose`` objective a stage's θ holds its own step of the reference
    (:func:`mpc_hunt.formulations.capture_model.stage_parameters`).
    """

    def __init__(self, structure: Structure):
        structure = structure.stage  # a stage's θ: its own step of the reference
        nc, nf, m, objective = structure.planned, structure.fixed, structure.obstacles, structure.objective
        self.nc, self.nf, self.m, self.objective = nc, nf, m, objective
        self.nx, self.nu = 2 + 2 * nc, 2 * nc
        theta = ca.SX.sym("theta", parameter_size(structure) + 1)
        p = unpack(theta, structure)
        w = theta[-1]
        x, u = ca.SX.sym("x", self.nx), ca.SX.sym("u", self.nu)
        a = x[:2]
        defenders = [x[2 + 2 * i : 4 + 2 * i] for i in range(nc)]
        held = [p["held"][2 * j : 2 * j + 2] for j in range(0 if structure.robot else nf)]

        force = p["nominal"]
        pushers, separation = defenders + held, p["min_separation"]
        if structure.robot:
            team = team_step(p, structure)
            held = [team["slots"][2 * j : 2 * j + 2] for j in range(nf)]
            pushers, separation = defenders, separation / 2
            force = force + team["pushed"] + ca.mtimes(team["push_jacobian"], a - team["push_attacker"])
        for d in pushers:
            force = force + p["k_d"] * repulsion(a - d, p["perception_radius"], p["eta"], w)
        for o in range(m):
            force = force + p["k_o"] * obstacle_repulsion(
                a, p["centres"][2 * o : 2 * o + 2], p["radii"][o], p["protective_distance"], p["eta"], w
            )
        step = p["time_step"] * saturate(force, p["attacker_max_speed"])
        self.dynamics = ca.Function("f", [x, u, theta], [ca.vertcat(a + step, x[2:] + u)])

        distance = [norm(d - a) for d in defenders]
        if objective == "enclose":
            residual = enclose_residuals(p, a, defenders, *step_reference(p, 0, structure))
        else:
            residual = [ca.sqrt(p["w_force"]) * (p["desired"] - force) / p["attacker_max_speed"]]
            residual += [ca.sqrt(p["w_ring"]) * (r - p["ring_radius"]) / p["hunt_radius"] for r in distance]
        self.residual = ca.Function("residual", [x, theta], [ca.vertcat(*residual)])
        reach = ca.vertcat(*[p["step_limits"][i] for i in range(nc) for _ in range(2)])
        self.move = ca.Function("move", [u, theta], [ca.sqrt(p["w_move"]) * u / reach])
        # Eq. 14's squared distances; with ``enclose`` none (ms-nlp's rows then pin their slacks at zero; the
        # stage QP of rti leaves rows and slacks out).
        squared = [ca.dot(d - a, d - a) if objective == "paper" else ca.SX.zeros(1, 1) for d in defenders]
        self.squared_distance = ca.Function("squared_distance", [x], [ca.vertcat(*squared)])

        # Distances, not their squares: linearised, a distance gives the tangent half-plane
        # n̄·(p − c) ≥ R, the tightest inner approximation (the one mpc_hunt/formulations/qp.py uses).
        rows, lower, self.families = [], [], []
        for d in defenders:
            for o in range(m):
                rows.append(norm(d - p["centres"][2 * o : 2 * o + 2]))
                lower.append(p["radii"][o] + p["safety_distance"])
                self.families.append("obstacle_safety")
            rows.append(norm(d - a))
            lower.append(p["min_attacker_distance"])
            self.families.append("attacker_distance")
        for i, j in separation_pairs(nc, nf):
            rows.append(norm(defenders[i] - (defenders[j] if j < nc else held[j - nc])))
            lower.append(separation)
            self.families.append("separation")
        self.path = ca.Function("path", [x, theta], [ca.vertcat(*rows), ca.vertcat(*lower)])
        steps = [ca.dot(u[2 * i : 2 * i + 2], u[2 * i : 2 * i + 2]) for i in range(nc)]
        self.motion = ca.Function("motion", [u, theta], [ca.vertcat(*steps), p["step_limits"] ** 2])


def stage_model(structure: Structure) -> StageModel:
    """The stage functions for ``structure`` (whatever its horizon), built once per process."""
    return _stage_model(structure.stage)


@lru_cache(maxsize=32)
def _stage_model(structure: Structure) -> StageModel:
    return StageModel(structure)

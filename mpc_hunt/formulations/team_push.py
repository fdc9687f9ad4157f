"""The team's broadcast to robots that plan apart: the attacker's predicted path and each defender's push on it.

For a team's plans D (every planned defender's positions at steps 1..N; the
held ones where they stand) the attacker's path under the stage model's
dynamics (Eqs. 2, 9; the field rounded from step 1 on, the paper's at step 0,
as ``rti`` has it):

    ā_0 = p_a,   ā_k+1 = ā_k + T sat(u_a + Σ_j k_d H(ā_k − p_j,k) + Σ_o k_o H_o(ā_k), v_a),

and, at every step k < N, each defender's push k_d H(ā_k − p_j,k) and its
Jacobian in ā_k. A robot's parameters (:mod:`mpc_hunt.formulations.distributed`) take the
sum over the others: its own push it models itself. One CasADi Function per
team structure, O(n N) to evaluate: what the UAV of the paper's Fig. 2 (or
every robot) computes once a round.
"""

from __future__ import annotations

from functools import lru_cache

import casadi as ca

from mpc_hunt.capture.structure import Structure
from mpc_hunt.formulations.capture_model import parameter_size, unpack
from mpc_hunt.formulations.field import obstacle_repulsion, repulsion, saturate


@lru_cache(maxsize=32)
def team_push(structure: Structure) -> ca.Function:
    """(θ, D) ↦ (ā (2 × N), pushes (2 × n·N), their Jacobians (4 × n·N, column by column)) for the team's
    ``structure``; θ is the team's parameter vector then the smoothing, D its plans (steps 1..N), the
    defenders of a step in the order planned, then held."""
    nc, nf, m, N = structure.planned, structure.fixed, structure.obstacles, structure.horizon
    theta = ca.SX.sym("theta", parameter_size(structure) + 1)
    plans = ca.SX.sym("D", N * nc * 2)
    p = unpack(theta, structure)
    held = [p["held"][2 * j : 2 * j + 2] for j in range(nf)]
    a = p["attacker"]
    path: list[ca.SX] = []
    pushes: list[ca.SX] = []
    jacobians: list[ca.SX] = []
    for k in range(N):
        positions = p["controlled"] if k == 0 else plans[(k - 1) * nc * 2 : k * nc * 2]
        team = [positions[2 * i : 2 * i + 2] for i in range(nc)] + held
        w = 0 if k == 0 else theta[-1]
        here = ca.SX.sym("a", 2)  # the pushes' Jacobians are taken at ā_k
        step_pushes = [p["k_d"] * repulsion(here - d, p["perception_radius"], p["eta"], w) for d in team]
        force = p["nominal"] + sum(step_pushes, ca.SX.zeros(2))
        for o in range(m):
            force = force + p["k_o"] * obstacle_repulsion(
                here, p["centres"][2 * o : 2 * o + 2], p["radii"][o], p["protective_distance"], p["eta"], w
            )
        at = ca.Function(
            "at",
            [here, theta, plans],
            [force] + step_pushes + [ca.reshape(ca.jacobian(f, here), 4, 1) for f in step_pushes],
        )
        values = at(a, theta, plans)
        path.append(a)
        pushes += values[1 : 1 + len(team)]
        jacobians += values[1 + len(team) :]
        a = a + p["time_step"] * saturate(values[0], p["attacker_max_speed"])
    return ca.Function("team_push", [theta, plans], [ca.horzcat(*path), ca.horzcat(*pushes), ca.horzcat(*jacobians)])

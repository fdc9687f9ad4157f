"""One stage of the capture problem linearised and scaled, for the real-time iteration (``rti``).

At a reference stage (x̄, ū) of :mod:`mpc_hunt.formulations.stage_model`, in the scaled
deviations ξ = S_x⁻¹ (x − x̄) and ν = ((u − ū) / r_d, q̃, s̃): the residuals
and their Jacobians (Gauss–Newton), the linearised dynamics, and the rows with
their Jacobians and bounds. S_x holds each state's reach in one step (v_a T
for the attacker, r_d for a defender); rows in metres are divided by r̄_d,
Eq. 14's squared distances by R_hunt r̄_d, so that the Hessian and the rows
are of order one. Built once per structure; independent of the horizon.

The ``enclose`` objective has no Eq. 14 (:mod:`mpc_hunt.formulations.stage_model`):
its rows could never bind and its slacks would sit at zero, so the stage
leaves both out, ν = (u − ū) / r_d. The QP's optimum is the same; HPIPM's
factorisations shrink with the stage (4 of 10 controls and 6 rows fewer at
N_d = 3), about a quarter of the step's time.
"""

from __future__ import annotations

from functools import lru_cache

import casadi as ca
import numpy as np

from mpc_hunt.capture.structure import Structure
from mpc_hunt.formulations.capture_model import unpack
from mpc_hunt.formulations.stage_model import stage_model

_DIAGONALS = ca.DM([[1.0, 1.0], [-1.0, 1.0]]) / np.sqrt(2.0)  # the octagon's diagonal normals
_APOTHEM = np.cos(np.pi / 8)  # distance of its sides, per r_d


class StageLinearisation:
    """One stage's linearisation, as CasADi functions of (x̄, ū, θ), for one structure (any horizon).

    ``state(x̄, θ)``: the residuals of step k and their Jacobian in ξ, the path rows (Eq. 15,
    separations, attacker distance) over r̄_d and theirs. ``control(x̄, ū, θ)``: the smoothness
    residual and its Jacobian in ν, the gap x̄_k+1 − f and its Jacobians in (ξ, ν), the octagon's
    diagonal rows and Eq. 14's rows for step k+1 with theirs, and the gradient of Eq. 14's penalty.
    """

    def __init__(self, structure: Structure):
        nc = structure.planned
        sm = stage_model(structure)
        eq14 = structure.objective == "paper"  # Eq. 14's rows and slacks (module docstring)
        self.nx, self.nd, self.nu = sm.nx, sm.nu, sm.nu + (1 + nc if eq14 else 0)
        self.families = sm.families
        theta = ca.SX.sym("theta", sm.dynamics.size1_in(2))
        p = unpack(theta, structure.stage)
        reach = ca.vertcat(*[p["step_limits"][i] for i in range(nc) for _ in range(2)])
        attacker_reach = p["time_step"] * p["attacker_max_speed"]
        self.S_x = ca.Function("S_x", [theta], [ca.vertcat(attacker_reach, attacker_reach, reach)])
        length = ca.sum1(p["step_limits"]) / nc  # the rows' length scale, r̄_d
        sigma = p["hunt_radius"] * length  # Eq. 14's squared-distance scale
        S_x = self.S_x(theta)
        x_ref, u_ref = ca.SX.sym("x_ref", self.nx), ca.SX.sym("u_ref", self.nd)
        xi, nu = ca.SX.sym("xi", self.nx), ca.SX.sym("nu", self.nu)
        x, u = x_ref + S_x * xi, u_ref + reach * nu[: self.nd]

        def at_zero(name, inputs, outputs):
            """Outputs evaluated at ξ = ν = 0, as a function of ``inputs``."""
            f = ca.Function(name, inputs + [xi, nu], outputs)
            return ca.Function(name, inputs, f(*inputs, 0, 0))

        r = sm.residual(x, theta)
        values, bound = sm.path(x, theta)
        c = (values - bound) / length
        self.state = at_zero("state", [x_ref, theta], [r, ca.jacobian(r, xi), c, ca.jacobian(c, xi)])

        move = sm.move(u, theta)
        nxt = sm.dynamics(x, u, theta)
        gap = -nxt / S_x  # the row is ξ_k+1 + gap (+ x̄_k+1 / S_x): unit diagonal on ξ_k+1
        side = ca.vertcat(*[_APOTHEM * p["step_limits"][i] for i in range(nc) for _ in range(2)])
        diagonals = ca.vertcat(*[ca.mtimes(_DIAGONALS, u[2 * i : 2 * i + 2]) for i in range(nc)]) / length
        if eq14:
            squared = sm.squared_distance(nxt)  # Eq. 14 for step k+1
            q = ca.sum1(squared) / nc + sigma * nu[self.nd]
            s = sigma * nu[self.nd + 1 :]
            rows = ca.vertcat(diagonals, (squared - q - s) / sigma, (squared - q + s) / sigma)
            penalty = p["w_equal"] * ca.sum1(s) / p["hunt_radius"] ** 2
        else:
            rows, penalty = diagonals, ca.SX(0)
        self.control = at_zero(
            "control",
            [x_ref, u_ref, theta],
            [
                move,
                ca.jacobian(move, nu),
                nxt,
                ca.jacobian(gap, xi),
                ca.jacobian(gap, nu),
                rows,
                ca.jacobian(rows, xi),
                ca.jacobian(rows, nu),
                ca.gradient(penalty, nu),
            ],
        )
        inf = ca.DM.inf(nc)
        octagon = side / length
        low, high = -octagon * length / reach - u_ref / reach, octagon * length / reach - u_ref / reach
        if eq14:
            self.control_bounds = ca.Function(
                "control_bounds",
                [u_ref, theta],
                [
                    ca.vertcat(low, -ca.inf, ca.DM.zeros(nc)),
                    ca.vertcat(high, ca.inf, inf),  # Eq. 13, axis sides
                    ca.vertcat(-octagon, -inf, ca.DM.zeros(nc)),
                    ca.vertcat(octagon, ca.DM.zeros(nc), inf),
                ],
            )
        else:
            self.control_bounds = ca.Function("control_bounds", [u_ref, theta], [low, high, -octagon, octagon])


def stage_linearisation(structure: Structure) -> StageLinearisation:
    """The stage linearisation for ``structure`` (whatever its horizon), built once per process."""
    return _stage_linearisation(structure.stage)


@lru_cache(maxsize=32)
def _stage_linearisation(structure: Structure) -> StageLinearisation:
    return StageLinearisation(structure)

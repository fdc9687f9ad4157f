"""A peer for studies/step_latency.py: the capture-stage MPC written in do-mpc (``pip install -e .[peers]``).

The model is discrete-time: state x = (p_a, p_di for the controlled i), input
u = (Δp_d, q, s), x⁺ = (p_a + T sat(u_a(p_a, p_d), v_a,max), p_d + Δp_d), the
attacker's resultant built from :mod:`mpc_hunt.formulations.field`'s
``repulsion``, ``obstacle_repulsion`` and ``saturate`` (the paper's field,
unsmoothed, as ``nlp``). The scenario's numbers (θ of
:func:`~mpc_hunt.formulations.capture_model.parameter_vector`, of which the state's part
is unused) and the relaxed bounds are time-varying parameters, so one
``setup()`` serves every state of a structure.

do-mpc charges stage k's cost and nonlinear constraints at (x_k, u_k),
k = 0..N−1, and none at x_N; so stage k's terms are written on the step it
leads to, x_k+1 = f(x_k, u_k). With that the problem is ``nlp``'s exactly:

* cost (lterm; no mterm, no rterm): Eq. 12's force error, the ring, the
  smoothness and w_eq Σ s / R_hunt², with the same weights;
* Eq. 13 as a nonlinear constraint |Δp_di|² ≤ r_d² (a disc, not a box on u);
* Eq. 14 as ``nlp``'s exact L1 penalty: q_k and s_k are inputs (s ≥ 0 by a
  bound), ±(|r_ai|² − q) − s ≤ 0 hard nonlinear constraints. do-mpc's own soft
  constraints would give the same form, but their penalty is a number fixed at
  ``setup()``, not a parameter;
* Eq. 15, the attacker distance and the separations as bound² − |d|² ≤ floor,
  floor a parameter: the row's value with every defender held, clipped at 0 —
  ``nlp``'s "never worse than now" relaxation, exact.

What is do-mpc's own: the NLP it assembles (states and inputs of every stage
as variables, multiple shooting, one SX graph), and its warm start — the
previous solution as it was, not shifted one step, with IPOPT handed the
previous multipliers but not told to use them (no ``warm_start_init_point``);
the first solve starts from x_0 held and q, s at the current distances.
IPOPT is silent, with our backend's tolerance and iteration limit.
"""

from __future__ import annotations

import time
import warnings

import casadi as ca
import numpy as np

with warnings.catch_warnings():
    warnings.simplefilter("ignore")         # do-mpc warns about its optional features on import
    import do_mpc

from mpc_hunt.formulations.base import separation_pairs
from mpc_hunt.formulations.capture_model import parameter_size, parameter_vector, unpack
from mpc_hunt.formulations.field import norm, obstacle_repulsion, repulsion, saturate
from mpc_hunt.solving.backends.ipopt import IpoptBackend
from mpc_hunt.capture.problem import CaptureProblem


class DoMPCPeer:
    """The capture-stage MPC of one structure in do-mpc, set up once (``setup_time``); ``solve`` gives the plan.

    After a solve, ``solver_time`` is the ``make_step`` call's and ``mpc.solver_stats`` IPOPT's statistics.
    """

    def __init__(self, problem: CaptureProblem):
        t0 = time.perf_counter()
        structure = self.structure = problem.structure
        nc, nf, m, N = structure.planned, structure.fixed, structure.obstacles, structure.horizon
        x, theta = ca.SX.sym("x", 2 + 2 * nc), ca.SX.sym("theta", parameter_size(structure))
        u = ca.SX.sym("u", 3 * nc + 1)                          # (Δp_d, q, s)
        p = unpack(theta, structure)
        held = [p["held"][2 * j:2 * j + 2] for j in range(nf)]

        def resultant(a, team):
            force = p["nominal"]
            for d in team:
                force = force + p["k_d"] * repulsion(a - d, p["perception_radius"], p["eta"])
            for o in range(m):
                force = force + p["k_o"] * obstacle_repulsion(a, p["centres"][2 * o:2 * o + 2], p["radii"][o],
                                                              p["protective_distance"], p["eta"])
            return force

        def defenders(state):
            return [state[2 + 2 * i:4 + 2 * i] for i in range(nc)]

        move, q, s = u[:2 * nc], u[2 * nc], u[2 * nc + 1:]
        a1 = x[:2] + p["time_step"] * saturate(resultant(x[:2], defenders(x) + held), p["attacker_max_speed"])
        x1 = ca.vertcat(a1, x[2:] + move)
        d1 = defenders(x1)
        r = [d - a1 for d in d1]
        steps = [move[2 * i:2 * i + 2] for i in range(nc)]
        cost = (p["w_force"] * ca.sumsqr(p["desired"] - resultant(a1, d1 + held)) / p["attacker_max_speed"] ** 2
                + p["w_ring"] * sum((norm(v) - p["ring_radius"]) ** 2 for v in r) / p["hunt_radius"] ** 2
                + p["w_move"] * sum(ca.sumsqr(steps[i]) / p["step_limits"][i] ** 2 for i in range(nc))
                + p["w_equal"] * ca.sum1(s) / p["hunt_radius"] ** 2)
        motion = ca.vertcat(*[ca.sumsqr(steps[i]) - p["step_limits"][i] ** 2 for i in range(nc)])
        sq = ca.vertcat(*[ca.sumsqr(v) for v in r])
        apart = []                                              # bound² − |d|²: ≤ 0 when kept
        for i, d in enumerate(d1):
            apart += [(p["radii"][o] + p["safety_distance"]) ** 2 - ca.sumsqr(d - p["centres"][2 * o:2 * o + 2])
                      for o in range(m)]
            apart.append(p["min_attacker_distance"] ** 2 - ca.sumsqr(r[i]))
        apart += [p["min_separation"] ** 2 - ca.sumsqr(d1[i] - (d1[j] if j < nc else held[j - nc]))
                  for i, j in separation_pairs(nc, nf)]
        apart = ca.vertcat(*apart)
        stage = ca.Function("stage", [x, u, theta], [x1, cost, motion, ca.vertcat(sq - q - s, q - sq - s), apart])

        floors, xk = [], x                                      # each row along the held plan, clipped at 0
        for _ in range(N):
            x_next, *_, rows = stage(xk, ca.DM.zeros(u.numel()), theta)
            floors.append(ca.fmax(rows, 0))
            xk = x_next
        self._floors = ca.Function("floors", [x, theta], [ca.horzcat(*floors)])

        model = do_mpc.model.Model("discrete")
        xs = [model.set_variable("_x", "attacker", (2, 1)), model.set_variable("_x", "defenders", (2 * nc, 1))]
        us = [model.set_variable("_u", "move", (2 * nc, 1)), model.set_variable("_u", "q"),
              model.set_variable("_u", "s", (nc, 1))]
        tvp_theta = model.set_variable("_tvp", "theta", theta.shape)
        floor = model.set_variable("_tvp", "floor", apart.shape)
        x1 = stage(ca.vertcat(*xs), ca.vertcat(*us), tvp_theta)[0]
        model.set_rhs("attacker", x1[:2])
        model.set_rhs("defenders", x1[2:])
        model.setup()               # swaps the symbols above for the model's own: the rest is built after it
        _, cost, motion, equal, apart = stage(ca.vertcat(*xs), ca.vertcat(*us), tvp_theta)

        mpc = self.mpc = do_mpc.controller.MPC(model)
        mpc.settings.n_horizon = N
        mpc.settings.t_step = problem.time_step
        mpc.settings.supress_ipopt_output()
        mpc.settings.nlpsol_opts.update({"ipopt.max_iter": 500,
                                         **{f"ipopt.{k}": v for k, v in IpoptBackend.ACCURACY["default"].items()}})
        mpc.set_objective(mterm=ca.DM(0), lterm=cost)
        mpc.bounds["lower", "_u", "s"] = 0
        mpc.set_nl_cons("motion_limit", motion, ub=0.0)
        mpc.set_nl_cons("equal_distance", equal, ub=0.0)
        mpc.set_nl_cons("keep_apart", apart - floor, ub=0.0)
        self.tvp = mpc.get_tvp_template()
        mpc.set_tvp_fun(lambda t_now: self.tvp)
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", "rterm was not set")        # the smoothness term is in lterm
            warnings.filterwarnings("ignore", category=FutureWarning, module="casadi")   # do-mpc's numpy on SX
            mpc.setup()
        self._plan_index = np.concatenate([mpc.opt_x.f["_x", k, 0, -1, "defenders"] for k in range(1, N + 1)])
        self.setup_time = time.perf_counter() - t0

    def solve(self, problem: CaptureProblem) -> np.ndarray:
        """One ``make_step`` at ``problem``'s state; the plan (N, n, 2), held defenders where they are."""
        mpc, N = self.mpc, self.structure.horizon
        c = problem.controlled
        x0 = np.concatenate([problem.attacker_position, problem.defender_positions[c].ravel()])
        theta = parameter_vector(problem)
        floors = np.array(self._floors(x0, theta))
        for k in range(N + 1):
            self.tvp["_tvp", k, "theta"] = theta
            self.tvp["_tvp", k, "floor"] = floors[:, min(k, N - 1)]
        if not mpc.flags["set_initial_guess"]:
            sq = np.sum((problem.defender_positions[c] - problem.attacker_position) ** 2, axis=1)
            mpc.x0 = x0
            mpc.u0 = np.concatenate([np.zeros(2 * len(sq)), [np.median(sq)], np.abs(sq - np.median(sq))])
            mpc.set_initial_guess()
        t0 = time.perf_counter()
        mpc.make_step(x0)
        self.solver_time = time.perf_counter() - t0
        return problem.plan_from_x(np.array(mpc.opt_x_num_unscaled.cat).ravel()[self._plan_index])

"""IPOPT through CasADi's ``nlpsol``: created once per NLP structure, then reused.

Under a time limit IPOPT gets ``max_wall_time``, fixed when CasADi builds the solver and checked once an
iteration, so a step could end an iteration past its limit. An iteration callback therefore stops it when what is
left of the step's limit would not fit another iteration (:mod:`~mpc_hunt.solving.backends.iteration_deadline`):
IPOPT returns ``User_Requested_Stop``, a ``time_limit``.
The certificate is computed once the solve's time is taken (:meth:`IpoptBackend.certify`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mpc_hunt.capture.certificate import Certificate, bound_violation, complementarity
from mpc_hunt.capture.data import NLPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.errors import OptionError
from mpc_hunt.solving.backends.base import Backend
from mpc_hunt.solving.backends.iteration_deadline import IterationDeadline, watched

_STATUS = {
    "Solve_Succeeded": Status.OPTIMAL,
    "Solved_To_Acceptable_Level": Status.OPTIMAL_INACCURATE,
    "Infeasible_Problem_Detected": Status.INFEASIBLE,
    "Maximum_Iterations_Exceeded": Status.ITERATION_LIMIT,
    "Maximum_WallTime_Exceeded": Status.TIME_LIMIT,
    "Maximum_CpuTime_Exceeded": Status.TIME_LIMIT,
    "User_Requested_Stop": Status.TIME_LIMIT,  # the deadline's callback (the module's docstring)
}


class IpoptBackend(Backend):
    """Persistent IPOPT (interior point): ``nlpsol`` built per structure; warm-started primal and dual."""

    name = "ipopt"
    accepts = ("nlp", "ocp-nlp")
    package = "casadi"
    # IPOPT relaxes every bound by bound_relax_factor (1e-8 by default, in a row's units: 6e-7 m on nlp's
    # Eq. 13 in m², whose r_d² is 6.4e-5 m²; ms-nlp's rows are per step); "high" tightens it.
    ACCURACY = {
        "default": {"tol": 1e-8},
        "high": {"tol": 1e-10, "constr_viol_tol": 1e-10, "bound_relax_factor": 1e-12},
        "low": {"tol": 1e-5},
    }
    # A stage-structured NLP is re-solved each step from the shifted previous solution: the adaptive
    # barrier update then takes fewer iterations than the monotone one (studies/step_latency).
    # The paper's one-step NLP keeps IPOPT's defaults.
    KIND = {"ocp-nlp": {"mu_strategy": "adaptive"}}
    MAX_ITER = 500
    NATIVE = {"time_limit": "max_wall_time", "max_iter": "max_iter"}

    def _check_options(self, options: dict) -> None:
        """The budget's names (``max_cpu_time`` too), then every other option as IPOPT itself takes it: a one-variable
        NLP is set up with them, and IPOPT's refusal becomes one line naming the option."""
        if "max_cpu_time" in options:
            raise OptionError(
                "max_cpu_time: the budget is given as time_limit=..., the same name on every backend "
                "(not as a solver option)"
            )
        super()._check_options(options)
        if not options:
            return
        import casadi as ca

        x = ca.MX.sym("x")
        for key, value in options.items():
            try:
                ca.nlpsol("probe", "ipopt", {"x": x, "f": x**2}, self._settings({key: value}))
            except RuntimeError as exc:
                reason = str(exc).strip().splitlines()[-1].split(": ", 1)[-1] if str(exc).strip() else "refused"
                raise OptionError(f"{key}: IPOPT refuses it ({reason}); check its name and value") from None

    def _settings(self, options: dict) -> dict:
        settings = {
            "ipopt.print_level": 0,
            "print_time": False,
            "ipopt.sb": "yes",
            "ipopt.warm_start_init_point": "yes",
            "ipopt.warm_start_bound_push": 1e-9,
            "ipopt.warm_start_mult_bound_push": 1e-9,
        }
        return settings | {f"ipopt.{k}": v for k, v in options.items()}

    def setup(self, data: NLPData):
        import casadi as ca

        options = self._settings({**self.KIND.get(data.kind, {}), **self.options, "max_iter": self.iteration_cap()})
        deadline = None
        if self.time_limit is not None:
            options["ipopt.max_wall_time"] = self.time_limit
            deadline = _deadline(len(data.lbx), len(data.lbg), len(data.p))
            options["iteration_callback"] = deadline
        return _Ipopt(ca.nlpsol("capture", "ipopt", data.build(), options), deadline)

    def run(self, state: _Ipopt, data: NLPData, warm: WarmStart) -> Solution:
        solver, deadline = state.solver, state.deadline
        args = dict(p=data.p, lbx=data.lbx, ubx=data.ubx, lbg=data.lbg, ubg=data.ubg)
        if warm.x is not None:
            args["x0"] = warm.x
        if warm.y is not None and warm.z is not None:
            args["lam_g0"], args["lam_x0"] = warm.y, warm.z
        with watched(None if deadline is None else deadline.pace, self.time_left()):
            out = solver(**args)  # CasADi raises RuntimeError on evaluation errors (NaN, …)
        stats = solver.stats()
        raw = stats.get("return_status", "unknown")
        x = np.array(out["x"]).ravel()
        lam_g, lam_x = np.array(out["lam_g"]).ravel(), np.array(out["lam_x"]).ravel()
        state.g, state.stats = out["g"], stats
        return Solution(
            status=_STATUS.get(raw, Status.ERROR),
            message=raw,
            x=x,
            formulation_objective=float(out["f"]),
            iterations=int(stats.get("iter_count", 0)),
            duals=WarmStart(x, lam_g, lam_x),
        )

    def certify(self, state: _Ipopt, data: NLPData, result: Solution) -> Certificate:
        """IPOPT's measures of the answer :meth:`run` returned last (:func:`certificate`)."""
        duals = result.duals
        assert result.x is not None and duals.y is not None and duals.z is not None  # run() returns all three
        return certificate(data, result.x, np.array(state.g).ravel(), duals.y, duals.z, state.stats)


@dataclass
class _Ipopt:
    """A structure's IPOPT: the solver, its deadline callback (None without a time limit), and of its last solve
    the constraint values and statistics the certificate is computed from once the solve's time is taken."""

    solver: Any
    deadline: Any
    g: Any = None
    stats: dict = field(default_factory=dict)


def certificate(
    data: NLPData, x: np.ndarray, g: np.ndarray, lam_g: np.ndarray, lam_x: np.ndarray, stats: dict
) -> Certificate:
    """IPOPT's final measures (:mod:`mpc_hunt.capture.certificate`): the primal infeasibility of g's and x's bounds
    and the complementarity of the returned multipliers, computed here; the dual infeasibility, IPOPT's own of its
    last iterate (NaN when it recorded none)."""
    inf_du = stats.get("iterations", {}).get("inf_du") or [float("nan")]
    primal = max(bound_violation(g, data.lbg, data.ubg), bound_violation(x, data.lbx, data.ubx))
    gap = max(complementarity(g, data.lbg, data.ubg, lam_g), complementarity(x, data.lbx, data.ubx, lam_x))
    return Certificate(primal, float(inf_du[-1]), gap, kind="nlp")


def _deadline(nx: int, ng: int, np_: int):
    """IPOPT's iteration callback under a time limit (the module's docstring), for an NLP of ``nx`` variables,
    ``ng`` rows and ``np_`` parameters: stops it when the time left would not fit another iteration. A CasADi
    ``Callback``, its class made here so that listing the backends loads no solver."""
    import casadi as ca

    class Deadline(ca.Callback):
        def __init__(self) -> None:
            ca.Callback.__init__(self)
            self.sizes = {"x": nx, "f": 1, "g": ng, "lam_x": nx, "lam_g": ng, "lam_p": np_}
            self.pace = IterationDeadline()
            self.construct("deadline", {})

        def get_n_in(self):
            return ca.nlpsol_n_out()

        def get_n_out(self):
            return 1

        def get_name_in(self, i):
            return ca.nlpsol_out(i)

        def get_name_out(self, i):
            return "stop"

        def get_sparsity_in(self, i):
            return ca.Sparsity.dense(self.sizes[ca.nlpsol_out(i)])

        def has_eval_buffer(self):
            return True  # called on raw buffers: no CasADi matrix made of IPOPT's iterate

        def eval_buffer(self, arg, res):
            memoryview(res[0]).cast("d")[0] = 1.0 if self.pace.passed() else 0.0
            return 0

    return Deadline()

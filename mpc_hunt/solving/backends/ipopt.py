"""IPOPT through CasADi's ``nlpsol``: created once per NLP structure, then reused."""

from __future__ import annotations

import numpy as np

from mpc_hunt.capture.certificate import Certificate, bound_violation, complementarity
from mpc_hunt.capture.data import NLPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.errors import OptionError
from mpc_hunt.solving.backends.base import Backend

_STATUS = {
    "Solve_Succeeded": Status.OPTIMAL,
    "Solved_To_Acceptable_Level": Status.OPTIMAL_INACCURATE,
    "Infeasible_Problem_Detected": Status.INFEASIBLE,
    "Maximum_Iterations_Exceeded": Status.ITERATION_LIMIT,
    "Maximum_WallTime_Exceeded": Status.TIME_LIMIT,
    "Maximum_CpuTime_Exceeded": Status.TIME_LIMIT,
}


class IpoptBackend(Backend):
    """Persistent IPOPT (interior point): ``nlpsol`` built per structure; warm-started primal and dual."""

    name = "ipopt"
    accepts = ("nlp", "ocp-nlp")
    package = "casadi"
    install = "casadi"
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
        if self.time_limit is not None:
            options["ipopt.max_wall_time"] = self.time_limit
        return ca.nlpsol("capture", "ipopt", data.build(), options)

    def run(self, solver, data: NLPData, warm: WarmStart) -> Solution:
        args = dict(p=data.p, lbx=data.lbx, ubx=data.ubx, lbg=data.lbg, ubg=data.ubg)
        if warm.x is not None:
            args["x0"] = warm.x
        if warm.y is not None and warm.z is not None:
            args["lam_g0"], args["lam_x0"] = warm.y, warm.z
        out = solver(**args)  # CasADi raises RuntimeError on evaluation errors (NaN, …)
        stats = solver.stats()
        raw = stats.get("return_status", "unknown")
        x = np.array(out["x"]).ravel()
        lam_g, lam_x = np.array(out["lam_g"]).ravel(), np.array(out["lam_x"]).ravel()
        return Solution(
            status=_STATUS.get(raw, Status.ERROR),
            message=raw,
            x=x,
            formulation_objective=float(out["f"]),
            iterations=int(stats.get("iter_count", 0)),
            duals=WarmStart(x, lam_g, lam_x),
            certificate=certificate(data, x, np.array(out["g"]).ravel(), lam_g, lam_x, stats),
        )


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

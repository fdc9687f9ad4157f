"""What the backends of stage-structured QPs share: the formulation's graph closed by a CasADi ``conic``.

A formulation of kind ``ocp-qp`` hands over a CasADi graph (``StageQPData``):
the QP's data as expressions of its inputs, and the plan as an expression of
the inputs and the QP's solution. ``setup`` closes it, once per structure,
into one Function

    step(inputs…, λ_x0, λ_a0) → (plan, model objective, λ_x, λ_a, QP objective, certificate)

with the backend's ``conic`` plugin in the middle, so a control step is one
call from Python: linearisation, QP and read-back run inside CasADi, with no
Python loop and no matrix built in Python. A subclass names its ``plugin``
and its options (the stage sizes, for a structure-exploiting solver). The
duals of the previous step are the next step's starting guess, for solvers
that take one.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from mpc_hunt.capture.certificate import Certificate
from mpc_hunt.capture.data import StageQPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.solving.backends.base import Backend

QP_KEYS = ("h", "g", "a", "lba", "uba", "lbx", "ubx")


class ConicStepBackend(Backend):
    """Base class: closes an ``ocp-qp`` graph with ``ca.conic(plugin)`` into one step Function."""

    accepts = ("ocp-qp",)
    package = "casadi"
    CLOCK = False  # the step is one CasADi call; its conic plugins read no clock: a time limit is a cap
    LOOP_CERTIFICATE = True  # the step's output 5: its QP's certificate
    plugin: ClassVar[str]

    def conic_options(self, graph: Any, cap: int) -> dict:
        """The plugin's options for this graph, at most ``cap`` iterations (tolerances come from ``self.options``)."""
        return {}

    def linearised(self, graph: Any, cap: int | None = None) -> tuple[Any, Any]:
        """The two halves of a step apart: ``graph``'s QP as a Function of its inputs (outputs: :data:`QP_KEYS`),
        and this backend's conic solver for that QP's sparsity, capped at ``cap`` iterations (by default
        :meth:`~mpc_hunt.solving.backends.base.Backend.iteration_cap`'s) (a study times them one by one)."""
        import casadi as ca

        qp = [graph.qp[key] for key in QP_KEYS]
        solver = ca.conic(
            "capture",
            self.plugin,
            {"h": qp[0].sparsity(), "a": qp[2].sparsity()},
            {"error_on_fail": False, **self.conic_options(graph, self.iteration_cap() if cap is None else cap)},
        )
        return ca.Function("linearise", graph.inputs, qp), solver

    def setup(self, data: StageQPData):
        return self.closed(data.build())

    def closed(self, graph: Any, cap: int | None = None):
        """``graph`` closed by the conic solver (at most ``cap`` iterations) into the step Function."""
        import casadi as ca

        linearise, solver = self.linearised(graph, cap)
        read = ca.Function("read", graph.inputs + [graph.z], [graph.plan, graph.cost])
        inputs = [ca.MX.sym(f"input{i}", s.sparsity()) for i, s in enumerate(graph.inputs)]
        lam_x0, lam_a0 = ca.MX.sym("lam_x0", linearise.size1_out(0)), ca.MX.sym("lam_a0", linearise.size1_out(2))
        # Every output requested: some plugins write their duals unconditionally.
        solution = solver(**dict(zip(QP_KEYS, linearise(*inputs))), lam_x0=lam_x0, lam_a0=lam_a0)
        plan, cost = read(*inputs, solution["x"])
        h, g, a, lba, uba, lbx, ubx = linearise(*inputs)
        residuals = certificate(h, g, a, lba, uba, lbx, ubx, solution["x"], solution["lam_x"], solution["lam_a"])
        return ca.Function(
            "step",
            inputs + [lam_x0, lam_a0],
            [plan, cost, solution["lam_x"], solution["lam_a"], solution["cost"], residuals],
        )

    def run(self, step, data: StageQPData, warm: WarmStart) -> Solution:
        outputs = call(step, data, warm)
        stats = step.stats()
        status = Status.OPTIMAL if stats.get("success") else self.failure(stats)
        return as_solution(status, str(stats.get("return_status", "")), int(stats.get("iter_count", 0)), outputs)

    def failure(self, stats: dict) -> Status:
        """The status of a solve the plugin did not report as a success."""
        return Status.ERROR

    def generated_step(self, step):
        """The Function CasADi generates C from (the C export), of the state ``setup`` returned."""
        return step

    def loop_function(self, step):
        """The Function a control loop evaluates through its buffers (:mod:`mpc_hunt.solving.step`)."""
        return step

    def loop_prepare(self, step) -> float:
        """Ready ``step`` for its next evaluation; the seconds spent rebuilding it (a set-up; 0 here: a step's
        options are fixed when it is built)."""
        return 0.0

    def longest_qp(self, step) -> float | None:
        """The longest the next QP of ``step`` may take, in seconds, where its cap is fixed and it reads no clock
        (None: it keeps within the time left by itself, or there is no limit)."""
        return None

    def loop_status(self, step, buffer) -> tuple[Status, int]:
        """(status, iterations) of the last evaluation of ``step`` through ``buffer``."""
        stats = buffer.stats()
        return (Status.OPTIMAL if stats.get("success") else self.failure(stats)), int(stats.get("iter_count", 0))

    def loop_message(self, step, buffer) -> str:
        """What went wrong in the last evaluation of ``step`` through ``buffer``, beyond its status ("" if nothing)."""
        return ""


def certificate(h, g, a, lba, uba, lbx, ubx, z, lam_x, lam_a):
    """The QP's primal residual, dual residual and duality gap at (z, λ_x, λ_a), as CasADi expressions of its data
    (:mod:`mpc_hunt.capture.certificate`; CasADi's multipliers are positive at an upper bound): a 3-vector."""
    import casadi as ca

    az = ca.mtimes(a, z)
    primal = ca.mmax(ca.vertcat(ca.fmax(az - uba, lba - az), ca.fmax(z - ubx, lbx - z), 0))
    dual = ca.norm_inf(ca.mtimes(h, z) + g + ca.mtimes(a.T, lam_a) + lam_x)

    def bound_terms(lam, lower, upper):  # u λ⁺ − l λ⁻ over the finite bounds (as the NumPy certificate)
        return ca.sum1(
            ca.if_else(ca.logic_and(lam > 0, ca.fabs(upper) < ca.inf), upper * lam, 0)
            + ca.if_else(ca.logic_and(lam < 0, ca.fabs(lower) < ca.inf), lower * lam, 0)
        )

    gap = ca.fabs(
        ca.dot(z, ca.mtimes(h, z)) + ca.dot(g, z) + bound_terms(lam_a, lba, uba) + bound_terms(lam_x, lbx, ubx)
    )
    return ca.vertcat(primal, dual, gap)


def call(step, data: StageQPData, warm: WarmStart) -> tuple:
    """One step: (plan, model objective, λ_x, λ_a, certificate), from the previous duals where they fit."""
    nz, na = step.size1_in(len(data.args)), step.size1_in(len(data.args) + 1)
    lam_x0 = warm.z if warm.z is not None and len(warm.z) == nz else np.zeros(nz)
    lam_a0 = warm.y if warm.y is not None and len(warm.y) == na else np.zeros(na)
    outputs = step(*data.args, lam_x0, lam_a0)
    return (*outputs[:4], outputs[5])


def as_solution(status: Status, message: str, iterations: int, outputs: tuple) -> Solution:
    plan, cost, lam_x, lam_a, residuals = outputs
    primal, dual, gap = (float(v) for v in np.array(residuals).ravel())
    return Solution(
        status=status,
        message=message,
        x=np.array(plan).ravel(),
        formulation_objective=float(cost),
        iterations=iterations,
        duals=WarmStart(None, np.array(lam_a).ravel(), np.array(lam_x).ravel()),
        certificate=Certificate(primal, dual, gap),
    )

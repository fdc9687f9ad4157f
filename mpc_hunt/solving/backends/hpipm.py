"""HPIPM (interior point on the stage structure: a Riccati recursion) through CasADi's ``conic``.

HPIPM factorises the QP stage by stage, so a step costs O(N) in the horizon.
It reads the stages from the sizes the formulation declares (``stages``: N,
nx, nu, ng): variables x_0, u_0, …, x_N, rows gap_0, c_0, …, c_N, each gap
x_k+1 = A x_k + B u_k with a diagonal on x_k+1 (kind ``ocp-qp``). An interior
point method gains little from a starting point: the previous duals are handed
over as for any conic plugin, and HPIPM's iterations start from its own point.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

from mpc_hunt.capture.data import StageQPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.errors import OptionError, UnknownNameError
from mpc_hunt.solving.backends.conic_step import ConicStepBackend

# HPIPM's modes offered: ``robust`` (LQ factorisations, the default) and ``balance`` (Cholesky: faster with a
# BLASFEO built for the CPU; its plans differ from robust's within the tolerances).
MODES = ("robust", "balance")
REBUILT_SHARE = 0.75  # of the iterations that fit, the cap a step is rebuilt with (the rest: room for the cost to rise)
RAISED_CAP = 2.0  # a step is rebuilt with a higher cap once that many times its cap would fit


@dataclass
class CappedStep:
    """An interpreted HPIPM step, the iteration cap it was built with, and the graph to build it again from."""

    function: Any
    cap: int
    graph: Any


class HpipmBackend(ConicStepBackend):
    """HPIPM in its ``robust`` mode, tolerances per ``accuracy``."""

    name = "hpipm"
    plugin = "hpipm"
    exports = "hpipm"
    # Complementarity one decade looser: CasADi hands HPIPM infinite bounds as ±1e8, whose slacks keep
    # its complementarity residual above 1e-8 (measured: 100 iterations at 1e-8, 9–11 at 1e-7).
    ACCURACY = {
        "default": {"res_g_max": 1e-8, "res_b_max": 1e-8, "res_d_max": 1e-8, "res_m_max": 1e-7},
        "high": {"res_g_max": 1e-10, "res_b_max": 1e-10, "res_d_max": 1e-10, "res_m_max": 1e-9},
        "low": {"res_g_max": 1e-5, "res_b_max": 1e-5, "res_d_max": 1e-5, "res_m_max": 1e-5},
    }
    MAX_ITER = 100
    NATIVE = {"max_iter": "iter_max"}

    def __init__(self, time_limit: float | None = None, accuracy: str = "default", **options):
        if options.get("mode", "robust") not in MODES:
            raise UnknownNameError(f"mode: HPIPM's mode is one of {', '.join(MODES)}, not {options['mode']!r}")
        super().__init__(time_limit, accuracy, **options)

    def _check_options(self, options: dict) -> None:
        """The budget's names, then every other option as HPIPM takes it through CasADi: a one-variable QP is set
        up with each, and a refusal becomes one line naming it."""
        super()._check_options(options)
        import casadi as ca

        for key, value in options.items():
            if key == "mode":
                continue
            try:
                ca.conic(
                    "probe",
                    "hpipm",
                    {"h": ca.Sparsity.dense(1, 1), "a": ca.Sparsity(0, 1)},
                    {"N": 0, "nx": [1], "nu": [0], "ng": [0], "hpipm": {key: value}},
                )
            except RuntimeError:
                raise OptionError(
                    f"{key}: not an option of HPIPM, or not of its type (HPIPM's own names: "
                    "iter_max is max_iter here; tolerances res_g_max, res_b_max, res_d_max, "
                    "res_m_max, ...)"
                ) from None

    def conic_options(self, graph, cap: int) -> dict:
        N, nx, nu, ng = graph.stages
        hpipm = {"mode": "robust", "mu0": 1.0, **self.options, "iter_max": cap}
        return {"N": N, "nx": nx, "nu": nu, "ng": ng, "hpipm": hpipm}

    def setup(self, data: StageQPData):
        graph = data.build()
        cap = self.iteration_cap()
        return CappedStep(self.closed(graph, cap), cap, graph)

    def run(self, state, data: StageQPData, warm: WarmStart) -> Solution:
        return super().run(state.function, data, warm)

    def loop_prepare(self, step) -> float:
        """Under a time limit, rebuild ``step`` once the iterations that fit in the whole limit, from the measured
        cost, fall below the cap it was built with (CasADi fixes HPIPM's ``iter_max`` when the step is built, before
        any of its solves is measured), with :data:`REBUILT_SHARE` of them, so that the cost may rise by a third
        before it is rebuilt again; and once :data:`RAISED_CAP` times its cap fit again (one dear solve lowers the
        measured bound's cap for as long as it is among the last solves: lowered for good, a step of random hunt
        9 at N = 10 stopped at 9 iterations 100 times in a row, measured). The seconds spent (a set-up), else 0. A
        step of several QPs keeps within its limit by not starting one that would not fit (:meth:`longest_qp`)."""
        if self.time_limit is None:
            return 0.0
        fits = self.iteration_cap(self.time_limit)
        cap = max(1, math.floor(REBUILT_SHARE * fits))
        if step.cap <= fits < RAISED_CAP * step.cap or cap == step.cap:
            return 0.0
        t0 = time.perf_counter()
        step.function, step.cap = self.closed(step.graph, cap), cap
        return time.perf_counter() - t0

    def longest_qp(self, step) -> float | None:
        """Its fixed cost plus its cap times the cost per iteration, both measured (:meth:`cost`; per step, so that
        for a step of several QPs it is more than one's), under a time limit."""
        if self.time_limit is None or not isinstance(step, CappedStep):
            return None
        fixed, per_iteration = self.cost()
        return fixed + step.cap * per_iteration

    def generated_step(self, step):
        return step.function

    def loop_function(self, step):
        return step.function

    def failure(self, stats: dict) -> Status:
        return Status.ITERATION_LIMIT if stats.get("return_status") == 1 else Status.ERROR

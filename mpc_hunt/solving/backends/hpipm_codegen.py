"""HPIPM's step compiled: linearisation, HPIPM and read-back generated to C once per structure.

The ``hpipm`` backend's one Function (:mod:`mpc_hunt.solving.backends.conic_step`)
generated to C by CasADi, compiled and cached (:mod:`mpc_hunt.solving.compiled`),
and called as one CasADi Function from the library. Four things in CasADi's
generated HPIPM code (3.8) are rewritten before it is compiled:

- it sets HPIPM's options one by one and leaves five unset (``dual_gap_max``,
  ``lam0_min``, ``t0_min``, ``t0_init``, ``update_fact_exit``), which then
  hold whatever the stack held: HPIPM's defaults for the mode go in first, as
  the interpreted plugin has them;
- it allocates HPIPM's memory on every call: each block is allocated once;
- it raises on any status but success, losing the plan and the iterations: the
  call returns, and the status and iteration count are read from the library
  (their accessors: ``c_templates/hpipm/hpipm_status.c``, :mod:`mpc_hunt.solving.c_template`);
- its iteration cap is a number in the code: each call takes the library's
  (set before it from the time left, :meth:`HpipmCodegenBackend.loop_prepare`),
  at most the generated one, so that under a time limit the cap follows the
  step's measured cost at each call (the interpreted step is rebuilt when its
  cap no longer fits, :meth:`HpipmBackend.loop_prepare`).

No compiler, or a failed build: one warning, and the interpreted ``hpipm`` step.
"""

from __future__ import annotations

import ctypes
import re
from dataclasses import dataclass
from typing import Any

from mpc_hunt.capture.data import StageQPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.solving.backends.conic_step import as_solution, call
from mpc_hunt.solving.backends.hpipm import HpipmBackend
from mpc_hunt.solving.c_template import render
from mpc_hunt.solving.compiled import FLAGS, compiled

MEMORY = ("dim", "qp", "qp_sol", "ipm_arg", "ipm")  # HPIPM's blocks, as CasADi's generated code names them


def _replace(source: str, old: str, new: str, count: int = 1) -> str:
    """``old`` replaced ``count`` times; a generator that writes otherwise is refused, not patched blindly."""
    if source.count(old) != count:
        raise RuntimeError(
            f"CasADi's generated HPIPM code has {source.count(old)} of {old.strip()!r}, expected {count}"
        )
    return source.replace(old, new)


def patch(source: str) -> str:
    """The four rewrites of the module docstring."""
    mode = re.findall(r"p\.hpipm_options\.mode = (\d+);", source)
    if len(mode) != 1:
        raise RuntimeError("CasADi's generated HPIPM code does not set one mode")
    source = _replace(
        source,
        "  p.hpipm_options.mu0 =",
        f"  d_ocp_qp_ipm_arg_set_default((enum hpipm_mode) {mode[0]}, &p.hpipm_options);\n  p.hpipm_options.mu0 =",
    )
    for block in MEMORY:
        source = _replace(
            source,
            f"void *{block}_mem = malloc({block}_size);",
            f"static void *{block}_mem = 0; if (!{block}_mem) {block}_mem = malloc({block}_size);",
        )
        source = _replace(source, f"free({block}_mem);", "")
    source = _replace(
        source,
        "#include <hpipm_d_ocp_qp_utils.h>\n",
        "#include <hpipm_d_ocp_qp_utils.h>\n\n" + render("hpipm/hpipm_status.c"),
    )
    cap = re.findall(r"p\.hpipm_options\.iter_max = (\d+);", source)
    if len(cap) != 1:
        raise RuntimeError("CasADi's generated HPIPM code does not set one iteration cap")
    source = _replace(
        source,
        f"p.hpipm_options.iter_max = {cap[0]};",
        f"p.hpipm_options.iter_max = mpc_hunt_iter_cap > 0 && mpc_hunt_iter_cap < {cap[0]} ? mpc_hunt_iter_cap "
        f": {cap[0]};",
    )
    source = _replace(
        source,
        "  casadi_hpipm_solve(&d, arg, res, iw, w);\n  if (d.return_status!=0) {\n    return -1;\n  }\n",
        "  casadi_hpipm_solve(&d, arg, res, iw, w);\n"
        "  mpc_hunt_status = d.return_status; mpc_hunt_iterations = d.iter_count;\n",
    )
    return source


@dataclass
class CompiledStep:
    """The step loaded from its library, the library's status and iteration count of the last call, and the
    interpreted Function it was generated from."""

    function: Any
    status: Any
    iterations: Any
    cap: Any  # sets the next calls' iteration cap
    source: Any


class HpipmCodegenBackend(HpipmBackend):
    """``hpipm`` compiled (``flags``: the compiler's flags, by default :data:`mpc_hunt.solving.compiled.FLAGS`)."""

    name = "hpipm-codegen"

    def __init__(self, time_limit: float | None = None, accuracy: str = "default", flags: tuple = FLAGS, **options):
        super().__init__(time_limit, accuracy, **options)
        self.flags = tuple(flags)

    def setup(self, data: StageQPData):
        step = super().setup(data)
        built = compiled(step.function, patch, self.flags, ("hpipm", "blasfeo"))
        if built is None:
            return step
        function, path = built
        library = ctypes.CDLL(str(path))
        return CompiledStep(
            function,
            library.mpc_hunt_hpipm_status,
            library.mpc_hunt_hpipm_iterations,
            library.mpc_hunt_hpipm_set_iter_max,
            step.function,
        )

    def run(self, state, data: StageQPData, warm: WarmStart) -> Solution:
        if not isinstance(state, CompiledStep):
            return super().run(state, data, warm)
        self.loop_prepare(state)
        outputs = call(state.function, data, warm)
        code = int(state.status())
        status = Status.OPTIMAL if code == 0 else self.failure({"return_status": code})
        return as_solution(status, "" if code == 0 else f"HPIPM status {code}", int(state.iterations()), outputs)

    def loop_prepare(self, step) -> float:
        """The next call's iteration cap: what fits in the time left, from the measured cost
        (:meth:`~mpc_hunt.solving.backends.base.Backend.iteration_cap`); nothing to rebuild."""
        if not isinstance(step, CompiledStep):
            return super().loop_prepare(step)
        step.cap(self.iteration_cap())
        return 0.0

    def generated_step(self, step):
        return step.source if isinstance(step, CompiledStep) else super().generated_step(step)

    def loop_status(self, step, buffer) -> tuple[Status, int]:
        if not isinstance(step, CompiledStep):
            return super().loop_status(step, buffer)
        code = int(step.status())
        return (Status.OPTIMAL if code == 0 else self.failure({"return_status": code})), int(step.iterations())

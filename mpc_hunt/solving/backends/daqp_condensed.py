"""``daqp-condensed``: a stage-form step condensed to a dense QP in its controls, solved by DAQP from its last
active set.

A stage QP (kind ``ocp-qp``, :mod:`mpc_hunt.formulations.rti`) has ξ_0 = 0 and gaps
ξ_k+1 + G_x ξ_k + G_u ν_k = 0, so its states follow from its controls: z = Z ν.
Condensed once per structure, as CasADi expressions of the step's inputs (θ,
reference), it is the dense QP

    min ½ νᵀ(ZᵀHZ)ν + (Zᵀg)ᵀν   s.t.  lbx_ν ≤ ν ≤ ubx_ν,  lbx_ξ ≤ Z_ξ ν ≤ ubx_ξ,  lba ≤ A Z ν ≤ uba

in 2N variables for a robot planning alone (``distributed``), the state bounds
that are finite becoming rows; the plan is affine in ν (plan₀ + P ν) and the
model's objective c₀ + ½νᵀHν + fᵀν. DAQP (a dual active-set solver, plain C)
solves it starting from the last solve's working set; a warm start that fails
is retried cold. The condensed Hessian is positive definite only where every
control is weighted, as the ``enclose`` objective's smoothness term does: the
paper's Eq. 14 slacks enter linearly, so the backend takes ``enclose`` only.

The step is one C file: CasADi's generated condensing, then the step around DAQP
(``c_templates/condensed/condensed_step.c``: DAQP's workspace, the warm start, the read-back), built against
DAQP's own sources (vendored in ``mpc_hunt/solving/daqp_c``, MIT, from its PyPI
sdist) into a library compiled once and cached (:mod:`mpc_hunt.solving.compiled`),
called through ``ctypes``; the C export (:mod:`mpc_hunt.solving.export`) writes
the same C. Each control loop's buffer (each robot's) holds its own workspace, so
each warm-starts from its own last solve. No compiler: one warning, and the same
condensing interpreted by CasADi with DAQP's Python package.
"""

from __future__ import annotations

import ctypes
import hashlib
import warnings
import weakref
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from mpc_hunt.capture.data import StageQPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.errors import OptionError, UnknownNameError
from mpc_hunt.solving.backends.base import Backend
from mpc_hunt.solving.backends.daqp import _MESSAGE, _STATUS
from mpc_hunt.solving.c_template import render
from mpc_hunt.solving.compiled import CompilationWarning, build, compiler

DAQP_SOURCES = Path(__file__).resolve().parents[1] / "daqp_c"      # DAQP 0.11.0's C sources, as its sdist ships them
DAQP_VERSION = "0.11.0"
INFINITY = 1e30             # DAQP's infinite bound (DAQP_INF)
CONDENSE = "mpc_hunt_condense"
FLAGS = ("-O2", "-fPIC", "-shared")
NON_FINITE_INPUT = -100     # the step's own codes beyond DAQP's exit flags
NON_FINITE_PLAN = -101
CODES = {NON_FINITE_INPUT: "non-finite input", NON_FINITE_PLAN: "non-finite plan", -99: "out of memory"}

def condensed(graph) -> tuple[Any, dict]:
    """The condensing Function of a stage QP ``graph`` (:class:`mpc_hunt.formulations.rti.LinearisedStages`): (θ,
    reference) → (H, f, Aᵀ, bu, bl, plan₀, P, c₀), all dense (Aᵀ column by column is A row by row, as DAQP
    reads it), and its sizes."""
    import casadi as ca

    N, nxs, nus, ngs = graph.stages
    qp, z = graph.qp, graph.z
    nv = sum(nus)
    v = ca.SX.sym("v", nv)
    A = qp["a"]
    xi, parts, gaps, controls, states = ca.SX.zeros(nxs[0]), [], [], [], []
    row = col = used = 0
    for k in range(N + 1):
        parts.append(xi)
        states.append(range(col, col + nxs[k]))
        col += nxs[k]
        if k < N:
            nx, nu = nxs[k], nus[k]
            step = v[used:used + nu]
            parts.append(step)
            controls += range(col, col + nu)
            gx, gu = A[row:row + nxs[k + 1], col - nx:col], A[row:row + nxs[k + 1], col:col + nu]
            gaps += range(row, row + nxs[k + 1])
            xi = -(ca.mtimes(gx, xi) + ca.mtimes(gu, step))
            row += nxs[k + 1]
            col += nu
            used += nu
        row += ngs[k]
    Z = ca.jacobian(ca.vertcat(*parts), v)                 # z = Z ν: ξ_0 = 0 and the gaps hold exactly

    def infinite(e, sign) -> bool:
        return bool(e.is_constant()) and float(e) == sign * np.inf

    lbx, ubx = qp["lbx"], qp["ubx"]
    bounded = [i for block in states[1:] for i in block if not (infinite(lbx[i], -1) and infinite(ubx[i], 1))]
    rows = [r for r in range(A.shape[0]) if r not in set(gaps)]
    select = ca.SX(len(bounded), z.shape[0])
    for r, i in enumerate(bounded):
        select[r, i] = 1
    constraint = ca.vertcat(ca.mtimes(select, Z), ca.mtimes(A[rows, :], Z))
    H = ca.mtimes([Z.T, qp["h"], Z])
    H = 0.5 * (H + H.T)
    zero = ca.DM.zeros(z.shape[0])
    outputs = [H, ca.mtimes(Z.T, qp["g"]), constraint.T,
               ca.fmin(ca.vertcat(ubx[controls], ubx[bounded], qp["uba"][rows]), INFINITY),
               ca.fmax(ca.vertcat(lbx[controls], lbx[bounded], qp["lba"][rows]), -INFINITY),
               ca.substitute(graph.plan, z, zero), ca.mtimes(ca.jacobian(graph.plan, z), Z),
               ca.substitute(graph.cost, z, zero)]
    function = ca.Function(CONDENSE, graph.inputs, [ca.densify(o) for o in outputs])
    sizes = dict(nv=nv, m=nv + constraint.shape[0], ms=nv, n_theta=graph.inputs[0].numel(),
                 n_reference=graph.inputs[1].numel())
    return function, sizes


def step_source(function, sizes: dict) -> str:
    """The step around DAQP (``c_templates/condensed/condensed_step.c``) for the condensing ``function`` of
    ``sizes`` (declared before it: generated code or its header)."""
    return render("condensed/condensed_step.c", **sizes, sz_arg=function.sz_arg(), sz_res=function.sz_res(),
                  sz_iw=function.sz_iw(), sz_w=function.sz_w(), condense=CONDENSE,
                  non_finite_input=NON_FINITE_INPUT, non_finite_plan=NON_FINITE_PLAN)


@cache
def daqp_digest() -> str:
    """The vendored DAQP sources' SHA-256, so that a changed copy never loads a stale library."""
    digest = hashlib.sha256()
    for path in sorted(DAQP_SOURCES.rglob("*.[ch]")):
        digest.update(path.read_bytes())
    return digest.hexdigest()


def daqp_sources() -> list[Path]:
    return sorted((DAQP_SOURCES / "src").glob("*.c"))


class CondensedStep:
    """A structure's condensed step: the condensing Function, its sizes, and the compiled library (or None)."""

    def __init__(self, graph, flags: tuple = FLAGS):
        self.function, self.sizes = condensed(graph)
        self.library = self._library(flags)

    def _library(self, flags: tuple):
        import casadi as ca

        cc = compiler()
        if cc is None:
            warnings.warn("no C compiler found: the condensed step runs interpreted", CompilationWarning,
                          stacklevel=4)
            return None
        generator = ca.CodeGenerator(f"{CONDENSE}.c", {"with_header": False})
        generator.add(self.function)
        source = (f"/* DAQP {DAQP_VERSION}, sources {daqp_digest()} */\n" + generator.dump()
                  + step_source(self.function, self.sizes))
        extra = (f"-I{DAQP_SOURCES / 'include'}", *map(str, daqp_sources()))
        try:
            path = build(source, flags, (), cc, extra)
            library = ctypes.CDLL(str(path))
        except (OSError, RuntimeError) as exc:
            warnings.warn(f"the condensed step could not be built ({str(exc).splitlines()[0]}): it runs "
                          "interpreted", CompilationWarning, stacklevel=4)
            return None
        library.mpc_hunt_daqp_new.restype = ctypes.c_void_p
        library.mpc_hunt_daqp_free.argtypes = [ctypes.c_void_p]
        library.mpc_hunt_daqp_solve.argtypes = [ctypes.c_void_p] * 5
        library.mpc_hunt_daqp_iterations.argtypes = [ctypes.c_void_p]
        library.mpc_hunt_daqp_flag.argtypes = [ctypes.c_void_p]
        return library

    def buffer(self):
        """A buffer with its own DAQP workspace, and the call that steps it (as a CasADi Function's buffer)."""
        buffer = CompiledBuffer(self.library) if self.library is not None else InterpretedBuffer(self.function,
                                                                                                  self.sizes)
        return buffer, buffer.evaluate


class CompiledBuffer:
    """The step's arrays and one workspace of the compiled library."""

    def __init__(self, library):
        self.library = library
        self.workspace = library.mpc_hunt_daqp_new()
        if not self.workspace:
            raise MemoryError("the condensed step's workspace could not be allocated")
        weakref.finalize(self, library.mpc_hunt_daqp_free, self.workspace)
        self.arrays = [None] * 4       # θ, reference, plan, objective (kept alive: the library holds their addresses)
        self.pointers = [None] * 4
        self.code = 0

    def set_arg(self, i: int, view) -> None:
        self._set(i, view)

    def set_res(self, i: int, view) -> None:
        self._set(2 + i, view)

    def _set(self, i: int, view) -> None:
        array = np.frombuffer(view, dtype=float)
        self.arrays[i], self.pointers[i] = array, array.ctypes.data

    def evaluate(self) -> None:
        self.code = self.library.mpc_hunt_daqp_solve(self.workspace, *self.pointers)

    @property
    def flag(self) -> int:
        return int(self.library.mpc_hunt_daqp_flag(self.workspace))

    @property
    def iterations(self) -> int:
        return int(self.library.mpc_hunt_daqp_iterations(self.workspace))


class InterpretedBuffer:
    """The same step without a compiler: the condensing interpreted by CasADi, DAQP through its Python package."""

    def __init__(self, function, sizes: dict):
        self.function, self.sizes = function, sizes
        self.model = None
        self.arrays = [None] * 4
        self.code = self.flag = self.iterations = 0

    def set_arg(self, i: int, view) -> None:
        self.arrays[i] = np.frombuffer(view, dtype=float)

    def set_res(self, i: int, view) -> None:
        self.arrays[2 + i] = np.frombuffer(view, dtype=float)

    def evaluate(self) -> None:
        import daqp

        theta, reference, plan, objective = self.arrays
        plan[:] = reference
        self.iterations, self.code = 0, NON_FINITE_INPUT
        self.flag = self.code
        if not (np.all(np.isfinite(theta)) and np.all(np.isfinite(reference))):
            return
        H, f, At, bu, bl, plan0, P, c0 = (np.array(o) for o in self.function(theta, reference))
        f, bu, bl = f.ravel(), bu.ravel(), bl.ravel()
        A = np.ascontiguousarray(At.T)
        if not all(np.all(np.isfinite(a)) for a in (H, f, A, bu, bl)):
            return
        if self.model is None:
            self.model = daqp.Model()
            self.model.setup(H, f, A, bu, bl)
            attempts = [None]
        else:
            attempts = [dict(H=H, f=f, A=A, bupper=bu, blower=bl), dict(sense=np.zeros(len(bu), dtype=np.intc))]
        for update in attempts:
            if update is not None:
                self.model.update(**update)
            x, _, flag, info = self.model.solve()
            self.iterations += int(info["iterations"])
            self.flag = int(flag)
            if flag > 0:
                break
        if self.flag <= 0:
            self.code = self.flag
            return
        x = np.asarray(x)
        new = plan0.ravel() + P @ x
        if not np.all(np.isfinite(new)):
            self.code = self.flag = NON_FINITE_PLAN
            return
        plan[:] = new
        if objective is not None:
            objective[0] = c0.item() + 0.5 * x @ H @ x + f @ x
        self.code = 0


class DaqpCondensedBackend(Backend):
    """A stage-form step condensed and solved by DAQP from its last active set (module docstring)."""

    name = "daqp-condensed"
    accepts = ("ocp-qp",)
    objectives = ("enclose",)     # every control weighted: a positive definite condensed Hessian
    package = "daqp"
    install = "daqp"
    TIME_LIMIT = False            # DAQP's limit needs its profiling build; the board's build has no clock
    ACCURACY = {"default": {}, "high": {}, "low": {}}     # an active-set solution is exact on its active set

    def __init__(self, time_limit: float | None = None, accuracy: str = "default", flags: tuple = FLAGS,
                 **options):
        super().__init__(time_limit, accuracy, **options)
        if self.max_iter is not None:
            raise OptionError(f"max_iter: backend {self.name}'s compiled step (the board's) runs DAQP's own cap; "
                              "drop max_iter or use the hpipm backend")
        if self.options:
            raise UnknownNameError(f"backend {self.name} takes no options (got {', '.join(sorted(self.options))})")
        self.flags = tuple(flags)

    def setup(self, data: StageQPData) -> CondensedStep:
        return CondensedStep(data.build(), self.flags)

    def run(self, step: CondensedStep, data: StageQPData, warm: WarmStart) -> Solution:
        if not hasattr(step, "default_buffer"):
            step.default_buffer = step.buffer()[0]
        buffer = step.default_buffer
        theta, reference = (np.array(a, dtype=float).ravel() for a in data.args)
        plan, objective = np.empty_like(reference), np.zeros(1)
        for i, a in enumerate((theta, reference)):
            buffer.set_arg(i, memoryview(a))
        for i, a in enumerate((plan, objective)):
            buffer.set_res(i, memoryview(a))
        buffer.evaluate()
        status, iterations = self.loop_status(step, buffer)
        return Solution(status=status, message=message(buffer.code), x=plan if status.usable else None,
                        formulation_objective=float(objective[0]) if status.usable else None,
                        iterations=iterations)

    def generated_step(self, step: CondensedStep) -> CondensedStep:
        return step

    def loop_function(self, step: CondensedStep) -> CondensedStep:
        return step

    def loop_status(self, step: CondensedStep, buffer) -> tuple[Status, int]:
        if buffer.code == 0:
            return (Status.OPTIMAL_INACCURATE if buffer.flag == 4 else Status.OPTIMAL), buffer.iterations
        return _STATUS.get(buffer.code, Status.ERROR), buffer.iterations

    def loop_message(self, step: CondensedStep, buffer) -> str:
        return message(buffer.code)


def message(code: int) -> str:
    """What a step's code means: "" solved, else DAQP's exit flag's name or the step's own."""
    return "" if code == 0 else CODES.get(code) or f"DAQP: {_MESSAGE.get(code, code)}"

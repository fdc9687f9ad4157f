"""The condensed step compiled: CasADi's condensing and the step around DAQP as one C library, and its buffers.

The library's source is CasADi's generated condensing
(:mod:`mpc_hunt.solving.backends.condensing`) followed by the step around DAQP
(``c_templates/condensed/condensed_step.c``: DAQP's workspace, the warm start from
the last working set, a cold retry, the read-back), built against DAQP's vendored
sources (:mod:`mpc_hunt.solving.vendored_daqp`) once and cached
(:mod:`mpc_hunt.solving.compiled`), and called through ``ctypes``; the C export
(:mod:`mpc_hunt.solving.export`) writes the same C. Each buffer holds its own
workspace, so each control loop (each robot's) warm-starts from its own last solve.
No compiler, or a failed build: one warning, and None (the interpreted step,
:mod:`mpc_hunt.solving.backends.condensed_interpreted`, runs).
"""

from __future__ import annotations

import ctypes
import warnings
import weakref

import numpy as np

from mpc_hunt.solving.backends.condensing import CONDENSE
from mpc_hunt.solving.c_template import render
from mpc_hunt.solving.compiled import CompilationWarning, build, compiler
from mpc_hunt.solving.vendored_daqp import DAQP_SOURCES, DAQP_VERSION, daqp_digest, daqp_sources

FLAGS = ("-O2", "-fPIC", "-shared")
NON_FINITE_INPUT = -100  # the step's own codes beyond DAQP's exit flags
NON_FINITE_PLAN = -101
CODES = {NON_FINITE_INPUT: "non-finite input", NON_FINITE_PLAN: "non-finite plan", -99: "out of memory"}


def step_source(function, sizes: dict) -> str:
    """The step around DAQP (``condensed/condensed_step.c``) for the condensing ``function`` of ``sizes``
    (declared before it: generated code or its header)."""
    return render(
        "condensed/condensed_step.c",
        **sizes,
        sz_arg=function.sz_arg(),
        sz_res=function.sz_res(),
        sz_iw=function.sz_iw(),
        sz_w=function.sz_w(),
        condense=CONDENSE,
        non_finite_input=NON_FINITE_INPUT,
        non_finite_plan=NON_FINITE_PLAN,
    )


def compiled_library(function, sizes: dict, flags: tuple):
    """The library of the condensing ``function`` of ``sizes`` and the step around DAQP, compiled with ``flags``:
    loaded (built on a cache miss), or None with one warning."""
    import casadi as ca

    cc = compiler()
    if cc is None:
        warnings.warn("no C compiler found: the condensed step runs interpreted", CompilationWarning, stacklevel=4)
        return None
    generator = ca.CodeGenerator(f"{CONDENSE}.c", {"with_header": False})
    generator.add(function)
    source = f"/* DAQP {DAQP_VERSION}, sources {daqp_digest()} */\n" + generator.dump() + step_source(function, sizes)
    extra = (f"-I{DAQP_SOURCES / 'include'}", *map(str, daqp_sources()))
    try:
        path = build(source, flags, (), cc, extra)
        library = ctypes.CDLL(str(path))
    except (OSError, RuntimeError) as exc:
        warnings.warn(
            f"the condensed step could not be built ({str(exc).splitlines()[0]}): it runs interpreted",
            CompilationWarning,
            stacklevel=4,
        )
        return None
    library.mpc_hunt_daqp_new.restype = ctypes.c_void_p
    library.mpc_hunt_daqp_free.argtypes = [ctypes.c_void_p]
    library.mpc_hunt_daqp_solve.argtypes = [ctypes.c_void_p] * 5
    library.mpc_hunt_daqp_iterations.argtypes = [ctypes.c_void_p]
    library.mpc_hunt_daqp_flag.argtypes = [ctypes.c_void_p]
    return library


class CompiledBuffer:
    """The step's arrays and one workspace of the compiled library."""

    def __init__(self, library):
        self.library = library
        self.workspace = library.mpc_hunt_daqp_new()
        if not self.workspace:
            raise MemoryError("the condensed step's workspace could not be allocated")
        weakref.finalize(self, library.mpc_hunt_daqp_free, self.workspace)
        self.arrays = [None] * 4  # θ, reference, plan, objective (kept alive: the library holds their addresses)
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

"""``daqp-condensed``: a stage-form step condensed to a dense QP in its controls, solved by DAQP from its last
active set.

The stage QP is condensed once per structure (:mod:`mpc_hunt.solving.backends.condensing`:
2N variables for a robot planning alone, ``distributed``). DAQP (a dual active-set
solver, plain C) solves it starting from the last solve's working set; a warm start
that fails is retried cold. The condensed Hessian is positive definite only where
every control is weighted, as the ``enclose`` objective's smoothness term does: the
paper's Eq. 14 slacks enter linearly, so the backend takes ``enclose`` only.

The step is one C library, compiled once and cached (and, with its condensing, built once a process for every
backend of it: :func:`shared_condensing`), called through ``ctypes``
(:mod:`mpc_hunt.solving.backends.condensed_compiled`); the C export
(:mod:`mpc_hunt.solving.export`) writes the same C. Each control loop's buffer (each
robot's) holds its own workspace, so each warm-starts from its own last solve. No
compiler: one warning, and the same condensing interpreted by CasADi with DAQP's
Python package (:mod:`mpc_hunt.solving.backends.condensed_interpreted`).
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from mpc_hunt.capture.data import StageQPData
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.errors import OptionError, UnknownNameError
from mpc_hunt.solving.backends.base import Backend
from mpc_hunt.solving.backends.condensed_compiled import CODES, FLAGS, CompiledBuffer, compiled_library
from mpc_hunt.solving.backends.condensed_interpreted import InterpretedBuffer
from mpc_hunt.solving.backends.condensing import condensed
from mpc_hunt.solving.backends.daqp import EXIT_MESSAGE, EXIT_STATUS
from mpc_hunt.solving.compiled import compiler

SHARED_SIZE = 64  # structures whose condensing and library a process keeps for every backend of its own


_shared: OrderedDict[tuple, tuple] = OrderedDict()


def shared_condensing(data: StageQPData, flags: tuple) -> tuple:
    """(the condensing Function, its sizes, the compiled library or None) of ``data``'s structure, built once a
    process: generating and loading the C of a structure takes seconds, and every hunt's controller (a sweep's, a
    batch's) builds its own backend. What is shared holds no state of a solve: each buffer has its own workspace."""
    key = (data.key, flags, compiler())  # (no compiler, or another: built again, as the library's cache does)
    if key in _shared:
        _shared.move_to_end(key)
        return _shared[key]
    function, sizes = condensed(data.build())
    built = _shared[key] = (function, sizes, compiled_library(function, sizes, flags))
    if len(_shared) > SHARED_SIZE:
        _shared.popitem(last=False)
    return built


class CondensedStep:
    """A structure's condensed step: the condensing Function, its sizes, and the compiled library (or None), shared
    (:func:`shared_condensing`), and this backend's own buffer."""

    default_buffer: CompiledBuffer | InterpretedBuffer  # the backend's, made on its first run

    def __init__(self, function, sizes: dict, library):
        self.function, self.sizes, self.library = function, sizes, library

    def buffer(self):
        """A buffer with its own DAQP workspace, and the call that steps it (as a CasADi Function's buffer)."""
        buffer = CompiledBuffer(self.library) if self.library is not None else InterpretedBuffer(self.function)
        return buffer, buffer.evaluate


class DaqpCondensedBackend(Backend):
    """A stage-form step condensed and solved by DAQP from its last active set (module docstring)."""

    name = "daqp-condensed"
    accepts = ("ocp-qp",)
    exports = "condensed"
    objectives = ("enclose",)  # every control weighted: a positive definite condensed Hessian
    package = "daqp"
    TIME_LIMIT = False  # DAQP's limit needs its profiling build; the board's build has no clock
    ACCURACY = {"default": {}, "high": {}, "low": {}}  # an active-set solution is exact on its active set

    def __init__(self, time_limit: float | None = None, accuracy: str = "default", flags: tuple = FLAGS, **options):
        super().__init__(time_limit, accuracy, **options)
        if self.max_iter is not None:
            raise OptionError(
                f"max_iter: backend {self.name}'s compiled step (the board's) runs DAQP's own cap; "
                "drop max_iter or use the hpipm backend"
            )
        if self.options:
            raise UnknownNameError(f"backend {self.name} takes no options (got {', '.join(sorted(self.options))})")
        self.flags = tuple(flags)

    def setup(self, data: StageQPData) -> CondensedStep:
        return CondensedStep(*shared_condensing(data, self.flags))

    def run(self, step: CondensedStep, data: StageQPData, warm: WarmStart) -> Solution:
        if not hasattr(step, "default_buffer"):
            step.default_buffer = step.buffer()[0]
        buffer = step.default_buffer
        theta, reference = (np.array(a, dtype=float).ravel() for a in data.args)
        plan, objective = np.empty_like(reference), np.zeros(1)
        for i, a in enumerate((theta, reference)):
            buffer.set_arg(i, a.data)
        for i, a in enumerate((plan, objective)):
            buffer.set_res(i, a.data)
        buffer.evaluate()
        status, iterations = self.loop_status(step, buffer)
        return Solution(
            status=status,
            message=message(buffer.code),
            x=plan if status.usable else None,
            formulation_objective=float(objective[0]) if status.usable else None,
            iterations=iterations,
        )

    def generated_step(self, step: CondensedStep) -> CondensedStep:
        return step

    def loop_function(self, step: CondensedStep) -> CondensedStep:
        return step

    def loop_prepare(self, step: CondensedStep) -> float:
        """Nothing: its step runs DAQP's own cap (it takes no time limit)."""
        return 0.0

    def longest_qp(self, step: CondensedStep) -> float | None:
        """None: it takes no time limit."""
        return None

    def loop_status(self, step: CondensedStep, buffer) -> tuple[Status, int]:
        if buffer.code == 0:
            return (Status.OPTIMAL_INACCURATE if buffer.flag == 4 else Status.OPTIMAL), buffer.iterations
        return EXIT_STATUS.get(buffer.code, Status.ERROR), buffer.iterations

    def loop_message(self, step: CondensedStep, buffer) -> str:
        return message(buffer.code)


def message(code: int) -> str:
    """What a step's code means: "" solved, else DAQP's exit flag's name or the step's own."""
    return "" if code == 0 else CODES.get(code) or f"DAQP: {EXIT_MESSAGE.get(code, code)}"

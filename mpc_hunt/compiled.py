"""The decorator every compiled rule of the engine wears: Numba's ``njit``, cached on disk, or plain Python.

The world's rules, the attackers' behaviours and the geometric controllers are written once, as loops over one
hunt's arrays, and compiled by Numba (LLVM; no C compiler needed) the first time they run, the machine code
cached beside the module (``cache=True``), so a later process loads it in milliseconds. The same functions run
a single hunt (called from Python) and a batch of hunts (called from a compiled loop over the batch,
:mod:`mpc_hunt.sim.batch`): there is no second copy of any rule. Division follows NumPy (``error_model="numpy"``:
x / 0 is ±inf or NaN, not an exception), as the arrays the rules replaced did; nothing is reordered for speed
(no ``fastmath``), so a result is the same bits whatever the batch.

Without Numba (a platform it does not support), or with ``NUMBA_DISABLE_JIT=1``, the functions run as the plain
Python they are: the same results, slower (docs/engine.md).
"""

from __future__ import annotations

import importlib.util
from collections.abc import Callable
from typing import TypeVar, cast

F = TypeVar("F", bound=Callable)


def kernel(function: F) -> F:
    """``function`` compiled (the module's docstring), or itself where Numba is absent."""
    if importlib.util.find_spec("numba") is None:  # pragma: no cover - the fallback where Numba is not installed
        return function
    from numba import njit

    return cast(F, njit(cache=True, nogil=True, error_model="numpy")(function))

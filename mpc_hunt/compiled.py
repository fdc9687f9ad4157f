"""The decorator every compiled rule of the engine wears: Numba's ``njit``, cached on disk, or plain Python.

The world's rules, the attackers' behaviours and the geometric controllers are written once, as loops over one
hunt's arrays, and compiled by Numba (LLVM; no C compiler needed) the first time they run, the machine code
cached beside the module (``cache=True``), so a later process loads it in milliseconds. The same functions run
a single hunt (called from Python) and a batch of hunts (called from a compiled loop over the batch,
:mod:`mpc_hunt.sim.batch`): there is no second copy of any rule. Division follows NumPy (``error_model="numpy"``:
x / 0 is ±inf or NaN, not an exception), as the arrays the rules replaced did; nothing is reordered for speed
(no ``fastmath``), so a result is the same bits whatever the batch.

Numba's cache knows a function's own file only, not the rules it calls in other files: edit a rule and a caller
cached before would keep the old one. So the machine code is cached under a folder named by a digest of the whole
package's source (:func:`cache_folder`): any edit compiles everything afresh, once.

Without Numba (a platform it does not support), or with ``NUMBA_DISABLE_JIT=1``, the functions run as the plain
Python they are: the same results, slower (docs/engine.md).
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar, cast

F = TypeVar("F", bound=Callable)
PACKAGE = Path(__file__).resolve().parent


def cache_folder() -> Path:
    """Where the compiled rules are cached: ``kernels-<digest of every source file of the package>`` in the
    package's ``__pycache__`` (in ``NUMBA_CACHE_DIR`` if set; in the temporary folder if neither is writable); the
    folders of other versions of the sources there are removed when this one is made."""
    digest = hashlib.sha256()
    for path in sorted(PACKAGE.rglob("*.py")):
        digest.update(path.relative_to(PACKAGE).as_posix().encode() + b"\0" + path.read_bytes())
    name = f"kernels-{digest.hexdigest()[:16]}"
    given = os.environ.get("NUMBA_CACHE_DIR")
    for base in ([Path(given)] if given else []) + [PACKAGE / "__pycache__", Path(tempfile.gettempdir()) / "mpc-hunt"]:
        folder = base / name
        try:
            if not folder.exists():  # the sources changed: the other versions' code is dead weight
                for old in base.glob("kernels-*"):
                    shutil.rmtree(old, ignore_errors=True)
            folder.mkdir(parents=True, exist_ok=True)
            tempfile.TemporaryFile(dir=folder).close()
            return folder
        except OSError:
            continue
    return Path(tempfile.mkdtemp(prefix="mpc-hunt-kernels-"))


def _njit():
    """Numba's ``njit``, its cache in :func:`cache_folder`; None without Numba."""
    if importlib.util.find_spec("numba") is None:  # pragma: no cover - the fallback where Numba is not installed
        return None
    from numba import config, njit

    config.CACHE_DIR = str(cache_folder())
    return njit


_NJIT = _njit()


def kernel(function: F) -> F:
    """``function`` compiled (the module's docstring), or itself where Numba is absent."""
    if _NJIT is None:  # pragma: no cover
        return function
    return cast(F, _NJIT(cache=True, nogil=True, error_model="numpy")(function))

"""A CasADi Function generated to C, compiled once and cached on disk, loaded back as a Function.

``compiled(function, patch)`` generates ``function``'s C source, lets ``patch``
rewrite it (a backend fixes what CasADi's generator leaves out), and looks the
result up in the cache by the SHA-256 of the source, the compiler's identity
and its flags: the structure, the code's version and the solver's settings are
all in the source, so a changed model never loads a stale library. A miss
compiles it (under a lock, so parallel workers build it once) into the cache
directory: ``$MPC_HUNT_CACHE``, else ``$XDG_CACHE_HOME/mpc-hunt``, else
``~/.cache/mpc-hunt``. The compiler is ``$CC`` or ``gcc``.

The default flags optimise with ``-Og``: CasADi writes a structure's
linearisation as one straight-line function of tens of thousands of lines, on
which gcc's ``-O1`` takes minutes (measured: 110 s for three defenders at
N = 10, 8.5 s at ``-Og``, 4 s at ``-O0``) for a step no faster than ``-Og``'s;
HPIPM itself is the shipped, optimised library.

No compiler, or a failed build, is not an error: one warning, and ``None``,
so the caller keeps its interpreted Function.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import shutil
import subprocess
import tempfile
import warnings
from functools import cache
from pathlib import Path
from typing import Callable

FLAGS = ("-Og", "-fPIC", "-shared")  # see below
BUILD_TIMEOUT = 1800.0  # s: a build taking longer is abandoned (the interpreted step runs)


class CompilationWarning(UserWarning):
    """The compiled step could not be built or loaded; the interpreted one runs."""


def cache_directory() -> Path:
    if os.environ.get("MPC_HUNT_CACHE"):
        return Path(os.environ["MPC_HUNT_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "mpc-hunt"


def compiler() -> str | None:
    """The C compiler's path, or None when there is none."""
    return shutil.which(os.environ.get("CC", "gcc"))


@cache
def _compiler_identity(path: str) -> str:
    run = subprocess.run([path, "--version"], capture_output=True, text=True, timeout=30)
    return run.stdout.splitlines()[0] if run.stdout else path


def casadi_paths() -> tuple[str, str]:
    """CasADi's headers and libraries (HPIPM's and BLASFEO's among them)."""
    import casadi as ca

    root = os.path.dirname(ca.__file__)
    return os.path.join(root, "include"), root


def library_path(source: str, flags: tuple[str, ...], cc: str, extra: tuple[str, ...] = ()) -> Path:
    key = hashlib.sha256("\0".join([source, _compiler_identity(cc), *flags, *extra]).encode()).hexdigest()[:24]
    return cache_directory() / f"step-{key}.so"


def build(
    source: str, flags: tuple[str, ...], libraries: tuple[str, ...], cc: str, extra: tuple[str, ...] = ()
) -> Path:
    """The shared library of ``source``: from the cache, or compiled into it (with the compiler's ``extra``
    arguments: more sources, include folders). Raises on a failed build."""
    target = library_path(source, flags, cc, extra)
    if target.exists():
        return target
    target.parent.mkdir(parents=True, exist_ok=True)
    with open(target.with_suffix(".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # another process building the same library: wait for it
        if target.exists():
            return target
        include, lib = casadi_paths()
        with tempfile.TemporaryDirectory(dir=target.parent) as work:
            c_file, so_file = Path(work) / "step.c", Path(work) / "step.so"
            c_file.write_text(source, encoding="utf-8")
            command = [
                cc,
                *flags,
                str(c_file),
                *extra,
                "-o",
                str(so_file),
                f"-I{include}",
                f"-L{lib}",
                *[f"-l{name}" for name in libraries],
                f"-Wl,-rpath,{lib}",
                "-lm",
            ]
            run = subprocess.run(command, capture_output=True, text=True, timeout=BUILD_TIMEOUT)
            if run.returncode != 0:
                raise RuntimeError(f"{cc} exited with {run.returncode}: {run.stderr.strip()[:300]}")
            os.replace(so_file, target)
    return target


def compiled(
    function,
    patch: Callable[[str], str] = lambda source: source,
    flags: tuple[str, ...] = FLAGS,
    libraries: tuple[str, ...] = (),
):
    """``function`` compiled (a CasADi Function loaded from the cached library) and its path, or None."""
    import casadi as ca

    cc = compiler()
    if cc is None:
        warnings.warn(
            f"no C compiler ({os.environ.get('CC', 'gcc')}) found: the capture step runs interpreted",
            CompilationWarning,
            stacklevel=3,
        )
        return None
    generator = ca.CodeGenerator(f"{function.name()}.c", {"with_header": False})
    generator.add(function)
    source = patch(generator.dump())
    try:
        path = build(source, flags, libraries, cc)
        return ca.external(function.name(), str(path)), path
    except (OSError, RuntimeError, subprocess.SubprocessError) as exc:
        warnings.warn(
            f"the compiled capture step could not be built ({str(exc).splitlines()[0]}): it runs interpreted",
            CompilationWarning,
            stacklevel=3,
        )
        return None

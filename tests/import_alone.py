"""Run as a script: import each module named on stdin alone, in a process forked from one that has imported the
third-party modules named as arguments only (so each costs our own code's import, not NumPy's or CasADi's again),
one child a core at a time; print each module that fails, with its error's last line."""

from __future__ import annotations

import importlib
import os
import sys
import traceback


def preload(names: list[str]) -> None:
    """What our modules import from outside (``a.b.c``: module ``a.b.c``, or ``a.b``'s name ``c``)."""
    for name in names:
        for module in (name, name.rpartition(".")[0]):
            try:
                importlib.import_module(module)
                break
            except Exception:       # not a module, or an optional extra not installed: its importer's failure shows
                continue


def start(module: str) -> tuple[int, int]:
    """A child importing ``module``; its pid and the pipe its error comes back on."""
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(read)
        try:
            importlib.import_module(module)
            code = 0
        except BaseException:
            os.write(write, traceback.format_exc().strip().splitlines()[-1].encode())
            code = 1
        os._exit(code)              # no cleanup: the parent's state is the next child's
    os.close(write)
    return pid, read


def main() -> int:
    modules = sys.stdin.read().split()
    preload(sys.argv[1:])
    if any(m == "mpc_hunt" or m.startswith("mpc_hunt.") for m in sys.modules):
        print("preloading imported mpc_hunt itself")
        return 1
    running: dict[int, tuple[str, int]] = {}
    failed = 0
    pending = list(reversed(modules))
    while pending or running:
        while pending and len(running) < (os.cpu_count() or 1):
            module = pending.pop()
            pid, read = start(module)
            running[pid] = (module, read)
        pid, status = os.wait()
        module, read = running.pop(pid)
        with os.fdopen(read) as pipe:
            message = pipe.read()
        if status != 0:
            failed += 1
            print(f"{module}: {message or f'exit status {status}'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

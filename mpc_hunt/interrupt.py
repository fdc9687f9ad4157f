"""Ctrl-C that ends a command (of ``mpc-hunt`` or a study) at once: with nothing written, or after writing what
was finished."""

from __future__ import annotations

import os
import signal
import sys
from contextlib import contextmanager
from typing import Callable

CLEAR_FIRST: list[Callable[[], None]] = []  # what a stop calls before its line: the progress bars, cleared


def _clear_first() -> None:
    for clear in reversed(CLEAR_FIRST):
        clear()


@contextmanager
def _on_interrupt(handler: Callable[[int, object], None]):
    """``handler`` takes Ctrl-C (SIGINT) inside the block; the previous one is back after it."""
    previous = signal.signal(signal.SIGINT, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def stop_at_once(command: str):
    """Ctrl-C ends the command at once, status 130, with nothing written.

    Not by KeyboardInterrupt: a solver such as IPOPT takes it as a request to end its current solve, and the
    command would run on to its end. Output is written after this block, so nothing is half-written.
    """

    def _exit(signum, frame):
        _clear_first()
        os.write(2, f"mpc-hunt {command}: interrupted: nothing written\n".encode())
        os._exit(128 + signum)

    return _on_interrupt(_exit)


def stop_keeping(command: str, keep: Callable[[], None]):
    """Ctrl-C ends the command at once, status 130, after ``keep()`` has written what was finished (a run whose
    pieces take seconds each, which no solver's own Ctrl-C handling may hold up)."""

    def _exit(signum, frame):
        try:
            _clear_first()
            keep()
            sys.stdout.flush()
        finally:
            os.write(2, f"mpc-hunt {command}: interrupted: kept what was finished\n".encode())
            os._exit(128 + signum)

    return _on_interrupt(_exit)

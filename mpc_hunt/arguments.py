"""Command lines (``mpc-hunt``'s and the studies'): the parser whose usage errors are one line, a run whose errors are
one line (:func:`run_command`), and argument types: bounded whole numbers, positive numbers, output folders and files
checked before any work.

Every count has an upper bound (docs/robustness.md, "Limits"), so that no value forks processes without end, asks
for more memory than a machine has, or overflows a results file.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
import tempfile
from pathlib import Path
from typing import Callable

from mpc_hunt.errors import MpcHuntError

EXIT_USAGE = 2  # a usage error's exit status (argparse's, mpc-hunt's), and an error's at run time
EXIT_INTERRUPTED = 130  # Ctrl-C's (128 + SIGINT)
MAX_SEED = 2**63 - 1  # SQLite's largest integer (a sweep stores its seed); NumPy takes any
MAX_WORKERS_PER_CORE = 4  # a sweep's --workers: at most this many per core (each holds a solver's memory)


class CommandParser(argparse.ArgumentParser):
    """argparse, but a usage error is one line on stderr, ``PROG: error: MESSAGE (see --help)``, with exit status
    EXIT_USAGE: ``mpc-hunt`` and every study (``studies/*.py``) parse with it. :meth:`error` also refuses what
    only shows after parsing (counts that cannot run together), before any work."""

    def error(self, message: str):  # noqa: D102 - argparse's hook
        self.exit(EXIT_USAGE, f"{self.prog}: error: {' '.join(message.split())} (see --help)\n")


def run_command(
    prog: str, main: Callable[[], int], flag: Callable[[str], str] = str, interrupted: int = EXIT_INTERRUPTED
) -> int:
    """``main()``'s exit status, run as a command: an error of the toolkit's or of a file is one line on stderr,
    ``PROG: error: MESSAGE``, status EXIT_USAGE, never a traceback, each field it names shown as ``flag(field)``
    (:meth:`~mpc_hunt.errors.MpcHuntError.named`); Ctrl-C is ``PROG: interrupted``, status ``interrupted``; a
    reader gone away (``| head``) is nothing more, status EXIT_USAGE."""
    try:
        return main()
    except MpcHuntError as exc:
        message = exc.named(flag)
    except BrokenPipeError:
        return EXIT_USAGE
    except OSError as exc:
        message = (f"{exc.filename}: " if exc.filename else "") + str(exc.strerror or exc)  # names the file
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return interrupted
    print(f"{prog}: error: {' '.join(message.split())}", file=sys.stderr)
    return EXIT_USAGE


_WHOLE = re.compile(r"\s*([+-]?)0*([0-9]+)\s*")
SHOWN = 40  # characters of a bad value a message repeats


def shown(text: str) -> str:
    """``text`` quoted for a message, cut to its first SHOWN characters."""
    return repr(text) if len(text) <= SHOWN else f"{text[:SHOWN]!r}... ({len(text)} characters)"


def out_of_range(value: int, least: int, most: int) -> str | None:
    """Why the whole number ``value`` is not from ``least`` to ``most``, in the words of every count's refusal, or
    None."""
    if value < least:
        return f"{_below(least)}, got {_number(value)}"
    if value > most:
        return f"at most {most} (docs/robustness.md, Limits), got {_number(value)}"
    return None


def _below(least: int) -> str:
    return "must not be negative" if least == 0 else f"must be at least {least}"


def _number(value: int) -> str:
    """``value`` for a message: its digits, or about how many for a number too long to show."""
    if abs(value) < 10**SHOWN:
        return str(value)
    return f"a number of about {int(abs(value).bit_length() * math.log10(2)) + 1} digits"


def _whole(text: str, least: int, most: int) -> int:
    match = _WHOLE.fullmatch(text)
    if match is None:
        raise argparse.ArgumentTypeError(f"expected a whole number from {least} to {most}, got {shown(text)}")
    sign, digits = match.groups()
    if len(digits) > len(str(max(abs(least), abs(most)))):  # far out of range: no int() of thousands of digits
        if sign == "-":
            raise argparse.ArgumentTypeError(f"{_below(least)}, got a number of {len(digits)} digits")
        raise argparse.ArgumentTypeError(
            f"at most {most} (docs/robustness.md, Limits), got a number of {len(digits)} digits"
        )
    value = int(sign + digits)
    why = out_of_range(value, least, most)
    if why:
        raise argparse.ArgumentTypeError(why)
    return value


def count(most: int):
    """An argument type: a whole number from 1 to ``most``."""
    return lambda text: _whole(text, 1, most)


def max_workers() -> int:
    """The most local worker processes a sweep may start on this machine."""
    return MAX_WORKERS_PER_CORE * (os.cpu_count() or 1)


def cores_count(text: str) -> int:
    """An argument type: worker processes, from 1 to ``MAX_WORKERS_PER_CORE`` per core of this machine."""
    return count(max_workers())(text)


def non_negative(most: int):
    """An argument type: a whole number from 0 to ``most``."""
    return lambda text: _whole(text, 0, most)


def seed(text: str) -> int:
    return _whole(text, 0, MAX_SEED)


def positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive finite number, got {text}")
    return value


def cannot_write(folder: Path) -> str | None:
    """Why this process cannot create a file in ``folder`` (read-only, /proc, ...), or None."""
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        return f"cannot write in {folder} ({exc.strerror or exc})"
    return None


def output_folder(text: str) -> Path:
    """An argument type: a folder to write into, checked before any work: an existing folder this process can write
    in, or a new one whose parent is such a folder (never a file, never a missing parent)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("empty: give a folder")
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text}: is a file, not a folder")
    if not path.exists() and not path.parent.is_dir():
        raise argparse.ArgumentTypeError(f"{text}: folder {path.parent} does not exist (create it first)")
    why = cannot_write(path if path.exists() else path.parent)
    if why:
        raise argparse.ArgumentTypeError(f"{text}: {why}")
    return path


def output_file(text: str) -> Path:
    """An argument type: a file to write, checked before any work: not a folder, in an existing folder this process
    can write in."""
    if not text.strip():
        raise argparse.ArgumentTypeError("empty: give a file")
    path = Path(text)
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text}: is a folder, not a file")
    if not path.parent.is_dir():
        raise argparse.ArgumentTypeError(f"{text}: folder {path.parent} does not exist (create it first)")
    why = cannot_write(path.parent)
    if why:
        raise argparse.ArgumentTypeError(f"{text}: {why}")
    return path

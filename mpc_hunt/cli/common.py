"""What the command line's subcommands share: bounded argument types, the output-path check, Ctrl-C, progress."""

from __future__ import annotations

import argparse
import os
import signal
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path

from mpc_hunt.errors import MpcHuntError
from mpc_hunt.world.belief import Belief, parse_belief

# Every count the command line takes has an upper bound (docs/robustness.md, "Limits"), so that no value forks
# processes without end, asks for more memory than a machine has, or overflows the results file.
MAX_SEED = 2**63 - 1               # SQLite's largest integer (a sweep stores its seed); NumPy takes any
MAX_STARTS = 100                   # compare's reference starts per problem
MAX_PROBLEMS = 100_000             # compare --limit, problems --every (closed-loop states)
MAX_RUN_LENGTH = 1_000             # problems --run-length
MAX_RANDOM = 1_000                 # problems --random: states per family, each up to 200 draws with a solve
MAX_HUNTS = 1_000_000              # sweep --hunts per strategy
MAX_WORKERS_PER_CORE = 4           # sweep --workers: at most this many per core (each holds a solver's memory)


def max_workers() -> int:
    """The most local worker processes a sweep may start on this machine."""
    return MAX_WORKERS_PER_CORE * (os.cpu_count() or 1)


def _whole(text: str, least: int, most: int, rule: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < least:
        raise argparse.ArgumentTypeError(f"{rule}, got {value}")
    if value > most:
        raise argparse.ArgumentTypeError(f"at most {most} (docs/robustness.md, Limits), got {value}")
    return value


def count(most: int):
    """An argument type: a whole number from 1 to ``most``."""
    return lambda text: _whole(text, 1, most, "must be at least 1")


def cores_count(text: str) -> int:
    """Worker processes: from 1 to MAX_WORKERS_PER_CORE per core of this machine."""
    return _whole(text, 1, max_workers(), "must be at least 1")


def non_negative(most: int):
    """An argument type: a whole number from 0 to ``most``."""
    return lambda text: _whole(text, 0, most, "must not be negative")


def seed(text: str) -> int:
    return _whole(text, 0, MAX_SEED, "must not be negative")


def belief(text: str) -> Belief:
    """An argument type: the defenders' belief of the attacker (``perception_radius=1.3x,eta=3x,intent_heading=60``
    or ``exact``; :func:`mpc_hunt.world.belief.parse_belief`)."""
    try:
        return parse_belief(text)
    except MpcHuntError as exc:      # a ValueError too, which argparse would report without the message
        raise argparse.ArgumentTypeError(str(exc)) from None


def check_writable(folder: Path, option: str, path: Path) -> None:
    """Refuse, before any work, a folder this process cannot create a file in (read-only, /proc, ...)."""
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise MpcHuntError(f"{option} {path}: cannot write in {folder} ({exc.strerror or exc})") from None


@contextmanager
def stop_at_once(command: str):
    """Ctrl-C ends the command at once, status 130, with nothing written.

    Not by KeyboardInterrupt: a solver such as IPOPT takes it as a request to end its current solve, and the
    command would run on to its end. Output is written after this block, so nothing is half-written.
    """
    def _exit(signum, frame):
        os.write(2, f"mpc-hunt {command}: interrupted: nothing written\n".encode())
        os._exit(128 + signum)

    previous = signal.signal(signal.SIGINT, _exit)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive finite number, got {text}")
    return value


class Progress:
    """A progress bar on stderr (of simulated seconds, unless told another unit), shown for runs over 2 s."""

    def __init__(self, total: float, what: str, quiet: bool, unit: str = "sim s"):
        self.total, self.what, self.quiet, self.unit = total, what, quiet, unit

    def __enter__(self):
        if self.quiet:
            return None
        from tqdm import tqdm
        self.bar = tqdm(total=round(self.total, 1), desc=self.what, unit=f" {self.unit}", delay=2.0,
                        file=sys.stderr, leave=False,
                        bar_format=f"{{desc}}: {{percentage:3.0f}}%|{{bar}}| {{n:.0f}}/{{total:.0f}} {self.unit} "
                                   "[{elapsed}<{remaining}]")
        return self._update

    def _update(self, t: float) -> None:
        self.bar.update(round(t, 1) - self.bar.n)

    def __exit__(self, *exc) -> None:
        if not self.quiet:
            self.bar.close()

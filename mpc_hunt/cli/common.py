"""What the command line's subcommands share: the limits of its counts, the flag of each library field, the belief
type, the output-path check, progress (the argument types: mpc_hunt.arguments; Ctrl-C: mpc_hunt.interrupt)."""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import time
from pathlib import Path

from mpc_hunt.arguments import cannot_write
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.interrupt import CLEAR_FIRST
from mpc_hunt.world.belief import Belief, parse_belief

# The upper bounds of the command line's counts (docs/robustness.md, "Limits"; the seed's: mpc_hunt.arguments).
MAX_STARTS = 100  # compare's reference starts per problem
MAX_PROBLEMS = 100_000  # compare --limit, problems --every (closed-loop states)
MAX_RUN_LENGTH = 1_000  # problems --run-length
MAX_RANDOM = 1_000  # problems --random: states per family, each up to 200 draws with a solve
MAX_HUNTS = 1_000_000  # sweep --hunts per strategy


# A field the library's errors name (mpc_hunt.errors.field_name, SettingError.fields) and the flag that gives it,
# where that is not --the-field (horizon: --horizon, time_limit: --time-limit).
FLAGS = {
    "prediction": "--no-prediction",
    "path": "--output",  # path: a sweep's results file (SweepStore)
    "scheduler": "--dask-scheduler",
    "strategies": "--strategy",
    "attackers": "--attacker",
    "beliefs": "--belief",
    "pairs": "--pair",
    "random_per_case": "--random",
}


def flag(name: str) -> str:
    """The flag that gives the library's field ``name``: how an error's one line names it."""
    return FLAGS.get(name, "--" + name.replace("_", "-"))


_messages: list = []  # the real stderr while quiet_solvers drops the rest


@contextlib.contextmanager
def quiet_solvers(verbose: bool):
    """While a command runs, what the solver packages write to stderr (CasADi's and IPOPT's warnings, Python's
    warnings; local sweep workers inherit it) is dropped, unless ``verbose``. The command's own messages (progress,
    "interrupted") go to :func:`messages`, the real stderr."""
    _messages.append(sys.stderr)
    try:
        if verbose:
            yield
        else:
            with open(os.devnull, "w", encoding="utf-8") as sink, contextlib.redirect_stderr(sink):
                yield
    finally:
        _messages.pop()


def messages():
    """The stream for the command's own messages on stderr (not the solvers', :func:`quiet_solvers`)."""
    return _messages[-1] if _messages else sys.stderr


def belief(text: str) -> Belief:
    """An argument type: the defenders' belief of the attacker (``perception_radius=1.3x,eta=3x,intent_heading=60``
    or ``exact``; :func:`mpc_hunt.world.belief.parse_belief`)."""
    try:
        return parse_belief(text)
    except MpcHuntError as exc:  # a ValueError too, which argparse would report without the message
        raise argparse.ArgumentTypeError(str(exc)) from None


def check_writable(folder: Path, option: str, path: Path) -> None:
    """Refuse, before any work, a folder this process cannot create a file in (read-only, /proc, ...)."""
    why = cannot_write(folder)
    if why:
        raise MpcHuntError(f"{option} {path}: {why}")


class Progress:
    """A progress bar on stderr (of simulated seconds, unless told another unit), shown for runs over 2 s."""

    DELAY = 2.0

    def __init__(self, total: float, what: str, quiet: bool, unit: str = "sim s"):
        self.total, self.what, self.quiet, self.unit = total, what, quiet, unit

    def __enter__(self):
        if self.quiet:
            return None
        from tqdm import tqdm

        self.shown_from = time.monotonic() + self.DELAY
        self.bar = tqdm(
            total=round(self.total, 1),
            desc=self.what,
            unit=f" {self.unit}",
            delay=self.DELAY,
            file=messages(),
            leave=False,
            bar_format=f"{{desc}}: {{percentage:3.0f}}%|{{bar}}| {{n:.0f}}/{{total:.0f}} {self.unit} "
            "[{elapsed}<{remaining}]",
        )
        CLEAR_FIRST.append(self._clear)  # Ctrl-C's line on a line of its own (mpc_hunt.interrupt)
        return self._update

    def _update(self, t: float) -> None:
        self.bar.update(round(t, 1) - self.bar.n)

    def _clear(self) -> None:
        """The bar blanked, the cursor at its line's start: by hand, as tqdm's close would not clear a bar stopped
        while first drawn."""
        if time.monotonic() >= self.shown_from:
            self.bar.fp.write("\r" + " " * len(str(self.bar)) + "\r")
            self.bar.fp.flush()

    def __exit__(self, *exc) -> None:
        if not self.quiet:
            CLEAR_FIRST.remove(self._clear)
            self.bar.close()

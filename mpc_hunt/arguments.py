"""Argument types for command lines (``mpc-hunt``'s and the studies'): bounded whole numbers, positive numbers.

Every count has an upper bound (docs/robustness.md, "Limits"), so that no value forks processes without end, asks
for more memory than a machine has, or overflows a results file.
"""

from __future__ import annotations

import argparse
import re

MAX_SEED = 2**63 - 1               # SQLite's largest integer (a sweep stores its seed); NumPy takes any


_WHOLE = re.compile(r"\s*([+-]?)0*([0-9]+)\s*")
SHOWN = 40                         # characters of a bad value a message repeats


def shown(text: str) -> str:
    """``text`` quoted for a message, cut to its first SHOWN characters."""
    return repr(text) if len(text) <= SHOWN else f"{text[:SHOWN]!r}... ({len(text)} characters)"


def _whole(text: str, least: int, most: int, rule: str) -> int:
    match = _WHOLE.fullmatch(text)
    if match is None:
        raise argparse.ArgumentTypeError(f"expected a whole number from {least} to {most}, got {shown(text)}")
    sign, digits = match.groups()
    if len(digits) > len(str(max(abs(least), abs(most)))):    # far out of range: no int() of thousands of digits
        if sign == "-":
            raise argparse.ArgumentTypeError(f"{rule}, got a number of {len(digits)} digits")
        raise argparse.ArgumentTypeError(f"at most {most} (docs/robustness.md, Limits), got a number of "
                                         f"{len(digits)} digits")
    value = int(sign + digits)
    if value < least:
        raise argparse.ArgumentTypeError(f"{rule}, got {value}")
    if value > most:
        raise argparse.ArgumentTypeError(f"at most {most} (docs/robustness.md, Limits), got {value}")
    return value


def count(most: int):
    """An argument type: a whole number from 1 to ``most``."""
    return lambda text: _whole(text, 1, most, "must be at least 1")


def non_negative(most: int):
    """An argument type: a whole number from 0 to ``most``."""
    return lambda text: _whole(text, 0, most, "must not be negative")


def seed(text: str) -> int:
    return _whole(text, 0, MAX_SEED, "must not be negative")


def positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive finite number, got {text}")
    return value

"""Argument types for command lines (``mpc-hunt``'s and the studies'): bounded whole numbers, positive numbers.

Every count has an upper bound (docs/robustness.md, "Limits"), so that no value forks processes without end, asks
for more memory than a machine has, or overflows a results file.
"""

from __future__ import annotations

import argparse

MAX_SEED = 2**63 - 1               # SQLite's largest integer (a sweep stores its seed); NumPy takes any


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

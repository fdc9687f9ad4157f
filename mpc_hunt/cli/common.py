"""What the command line's subcommands share: argument types and the progress bar."""

from __future__ import annotations

import argparse
import sys


def _whole(text: str, least: int, rule: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < least:
        raise argparse.ArgumentTypeError(f"{rule}, got {value}")
    return value


def positive_int(text: str) -> int:
    return _whole(text, 1, "must be at least 1")


def non_negative_int(text: str) -> int:
    return _whole(text, 0, "must not be negative")


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

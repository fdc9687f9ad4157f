"""How a study's --check ends: the differences on stderr and status 1, or one line saying it is up to date."""

from __future__ import annotations

import sys


def check_result(errors: list[str], name: str, command: str, shown: int = 20) -> int:
    for line in errors[:shown]:
        print(line, file=sys.stderr)
    if errors:
        print(f"{len(errors)} differences: rerun {command}", file=sys.stderr)
        return 1
    print(f"{name}: up to date")
    return 0

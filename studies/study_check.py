"""How a study ends: its --check with the differences on stderr and status 1, or one line saying it is up to date;
any run with one line on stderr for an error, never a traceback (:func:`run_study`)."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Callable

from mpc_hunt.arguments import run_command
from mpc_hunt.errors import DataFileError


def run_study(main: Callable[[], int]) -> int:
    """A study's ``main()`` run as a command (:func:`mpc_hunt.arguments.run_command`): an error of the toolkit's or
    of a file is one line on stderr naming the study, status 2; Ctrl-C outside the study's own handling is one line,
    status 130."""
    return run_command(Path(sys.argv[0]).name, main)


def check_result(errors: list[str], name: str, command: str, shown: int = 20) -> int:
    for line in errors[:shown]:
        print(line, file=sys.stderr)
    if errors:
        print(f"{len(errors)} differences: rerun {command}", file=sys.stderr)
        return 1
    print(f"{name}: up to date")
    return 0


def read_json_file(path: Path, fix: str) -> object:
    """The data of the JSON file ``path``; a missing, unreadable or not-JSON file is a one-line DataFileError
    naming it, ending with ``fix``."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise DataFileError(f"{path}: no such file; {fix}") from None
    except OSError as exc:
        raise DataFileError(f"{path}: cannot read ({exc.strerror or exc}); {fix}") from None
    except (ValueError, RecursionError) as exc:      # not UTF-8, not JSON, nested too deeply
        raise DataFileError(f"{path}: not valid JSON ({exc}); {fix}") from None

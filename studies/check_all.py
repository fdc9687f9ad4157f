"""Every study's ``--check``, two at a time: the committed results still the code's (CI runs it after the tests).

A study is checked when it runs as a command (``python studies/NAME.py``) and takes ``--check`` (its own, or the
sweep studies' common options). Each check runs with this tree's code first on the path; a failing one prints its
differences. Exit status 1 when any fails.

    python studies/check_all.py [NAME ...]     # every study (or the ones named)
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

from mpc_hunt.arguments import CommandParser

ROOT = Path(__file__).resolve().parents[1]
AT_ONCE = 2         # checks side by side (none times anything)


def checked() -> list[str]:
    """The studies that take ``--check``, by name."""
    return sorted(p.stem for p in (ROOT / "studies").glob("*.py") if p.stem != "check_all"
                  and '\nif __name__ == "__main__":\n' in (text := p.read_text(encoding="utf-8"))
                  and ('"--check"' in text or "add_study_options" in text))


def check(name: str) -> tuple[str, subprocess.CompletedProcess, float]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    t0 = time.perf_counter()
    run = subprocess.run([sys.executable, f"studies/{name}.py", "--check"], cwd=ROOT, capture_output=True,
                         text=True, env=env)
    return name, run, time.perf_counter() - t0


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", metavar="NAME", help="the studies to check (default: every one)")
    names = parser.parse_args(argv).names or checked()
    unknown = sorted(set(names) - set(checked()))
    if unknown:
        parser.error(f"no study {unknown[0]!r} takes --check (known: {', '.join(checked())})")
    failed = 0
    with ThreadPoolExecutor(max_workers=AT_ONCE) as pool:
        for name, run, seconds in pool.map(check, names):
            ok = run.returncode == 0
            failed += not ok
            print(f"{'ok' if ok else 'FAILED'} {name} ({seconds:.0f} s)", flush=True)
            if not ok:
                print((run.stdout + run.stderr).strip()[-3000:], flush=True)
    print(f"{len(names) - failed} of {len(names)} studies' checks pass")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

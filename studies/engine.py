"""The batched engine against the engine before it: the same hunts, the same seeds, side by side on two cores.

Rule-based hunts, ``voronoi`` defenders (3 to 5) against the ``gap`` attacker on the sweep's random scenarios
of seed ``SEED`` (``studies/engine_worker.py``). The engine before the batched one (commit ``BEFORE``, its
``mpc_hunt/`` unpacked from git into a temporary folder) runs ``HUNTS`` of them one by one, as its sweeps did;
the batched engine runs the same hunts in batches of ``BATCH`` (the sweep's, ``mpc_hunt.sweep.runner.BATCH``),
then ``MORE`` hunts for its steady rate. Each engine runs on ``WORKERS`` processes at once, each timed inside
the process once warm (imports, compiled code's cache and a short hunt before the clock starts); a rate is the
hunts of all processes over the slowest process's seconds. The two engines' hunts must end alike (how, and
when): the study stops if one differs. Writes ``studies/engine/results.json`` and README.md, and the table in
docs/engine.md.

    python studies/engine.py            # measure (two or three minutes on two cores), write the results
    python studies/engine.py --check    # the docs' table and the report are the committed results'
"""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser, count
from mpc_hunt.bench.machine import describe_machine, machine_lines
from mpc_hunt.errors import DataFileError
from mpc_hunt.sweep.runner import BATCH

from studies.docs_block import read_block, write_block
from studies.study_check import check_result, read_json_file, run_study

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "studies" / "engine"
DOCS = ROOT / "docs" / "engine.md"
COMMAND = "python studies/engine.py"
BEFORE = "aba2141bca054dda51a67e3c13d827a12d78ede4"     # the last commit of the engine before the batched one
SEED, HUNTS, MORE, WORKERS = 46, 64, 2048, 2
MAX_HUNTS = 10_000


def unpacked(commit: str, folder: Path) -> Path:
    """``mpc_hunt/`` of ``commit`` written into ``folder`` (from this repository's git history)."""
    try:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", commit, "mpc_hunt"], capture_output=True,
                                 check=True).stdout
    except (OSError, subprocess.CalledProcessError) as exc:
        raise DataFileError(f"git archive {commit[:12]}: {exc}; the study needs this repository's git history "
                            "(a full clone)") from None
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(folder, filter="data")
    return folder


def side_by_side(path: Path, mode: str, first: int, hunts: int, batch: int) -> dict:
    """``hunts`` hunts from ``first`` on ``WORKERS`` processes with ``path`` first on the path: their rate and
    ends."""
    share = -(-hunts // WORKERS)
    env = {**os.environ, "PYTHONPATH": str(path)}
    runs = [subprocess.Popen([sys.executable, str(ROOT / "studies" / "engine_worker.py"), mode, str(SEED),
                              str(first + k * share), str(min(share, hunts - k * share)), str(batch)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
            for k in range(WORKERS) if k * share < hunts]
    outputs = []
    try:
        for r in runs:
            out, err = r.communicate()
            if r.returncode:
                raise DataFileError(f"a {mode} process failed: {err.strip().splitlines()[-1] if err.strip() else '?'}")
            outputs.append(json.loads(out))
    finally:
        for r in runs:
            r.kill()
    seconds = max(o["seconds"] for o in outputs)
    return {"hunts": hunts, "seconds": seconds, "steps": sum(o["steps"] for o in outputs),
            "hunts_per_s": hunts / seconds, "steps_per_s": sum(o["steps"] for o in outputs) / seconds,
            "ends": [e for o in outputs for e in o["ends"]]}


def measure(hunts: int, more: int) -> dict:
    with tempfile.TemporaryDirectory() as folder:
        before = side_by_side(unpacked(BEFORE, Path(folder)), "one", 0, hunts, 1)
        print(f"before: {before['hunts_per_s']:.2f} hunts/s", file=sys.stderr, flush=True)
    now = side_by_side(ROOT, "batch", 0, hunts, BATCH)
    if now["ends"] != before["ends"]:
        differ = [i for i, (a, b) in enumerate(zip(before["ends"], now["ends"])) if a != b]
        raise DataFileError(f"hunts {differ[:10]} end otherwise in the batched engine than before it")
    steady = side_by_side(ROOT, "batch", hunts, more, BATCH)
    print(f"batched: {now['hunts_per_s']:.1f} hunts/s on the same hunts, {steady['hunts_per_s']:.1f} on {more} "
          "more", file=sys.stderr, flush=True)
    for run in (before, now, steady):
        ends = run.pop("ends")
        run["outcomes"] = {end: sum(e[0] == end for e in ends) for end in
                           ("captured", "attacker_escaped", "time_limit", "non_finite_state")}
    return {"settings": {"seed": SEED, "hunts": hunts, "more": more, "workers": WORKERS, "batch": BATCH,
                         "before": BEFORE, "pair": "voronoi against gap, 3 to 5 defenders"},
            "before": before, "batched": now, "batched_more": steady}


def headline(results: dict) -> str:
    s, before = results["settings"], results["before"]
    rows = []
    for name, run in (("before the batched engine, one by one", before),
                      (f"batched ({s['batch']} hunts a batch), the same hunts", results["batched"]),
                      (f"batched, {s['more']} more hunts", results["batched_more"])):
        rows.append([name, f"{run['hunts']}", f"{run['seconds']:.2f}", f"{run['hunts_per_s']:.2f}",
                     f"{run['steps_per_s']:.0f}", f"{run['hunts_per_s'] / before['hunts_per_s']:.0f}x",
                     f"{run['outcomes']['captured']}"])
    lines = [f"`{COMMAND}` ({s['pair']}, the sweep's random scenarios of seed {s['seed']}; {s['workers']} "
             f"processes at once; before: commit `{s['before'][:12]}`; the same hunts end alike in both):", "",
             *markdown.table(["engine", "hunts", "s", "hunts/s", "steps/s", "vs before", "captured"], "lrrrrrr",
                             rows)]
    return "\n".join(lines) + "\n"


def write(results: dict, machine: dict) -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "results.json").write_text(json.dumps({"machine": machine, **results}, indent=1) + "\n", encoding="utf-8")
    (OUT / "README.md").write_text("\n".join(["# The batched engine against the engine before it", "",
                                              headline(results), *machine_lines(machine), ""]), encoding="utf-8")
    write_block("engine-speed", headline(results), DOCS)


def check() -> list[str]:
    committed = read_json_file(OUT / "results.json", f"rerun {COMMAND}")
    if not isinstance(committed, dict) or not {"settings", "before", "batched", "batched_more", "machine"} <= set(
            committed):
        return ["studies/engine/results.json: not the study's results"]
    errors = []
    s = committed["settings"]
    if (s.get("seed"), s.get("workers"), s.get("batch"), s.get("before")) != (SEED, WORKERS, BATCH, BEFORE):
        errors.append("results.json: measured with other settings than the study's")
    if read_block("engine-speed", DOCS) != headline(committed):
        errors.append("docs/engine.md: its table is not the committed results'")
    report = "\n".join(["# The batched engine against the engine before it", "", headline(committed),
                        *machine_lines(committed["machine"]), ""])
    if (OUT / "README.md").read_text(encoding="utf-8") != report:
        errors.append("studies/engine/README.md: not the committed results' report")
    return errors


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hunts", type=count(MAX_HUNTS), default=HUNTS,
                        help=f"hunts run by both engines (default {HUNTS})")
    parser.add_argument("--more", type=count(MAX_HUNTS), default=MORE,
                        help=f"more hunts for the batched engine's steady rate (default {MORE})")
    parser.add_argument("--check", action="store_true", help="check the docs' table against the committed results")
    args = parser.parse_args(argv)
    if args.check:
        return check_result(check(), "studies/engine", COMMAND)
    write(measure(args.hunts, args.more), describe_machine())
    print(f"wrote {OUT / 'README.md'} and the table of docs/engine.md")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

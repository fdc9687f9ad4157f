"""The compare benchmark: every installed (formulation, backend) pair on the shipped problem set.

At horizons N = 1, 5 and 10, in both modes (cold, replayed), accuracy
``default``, seed 0, no time limit: ``mpc-hunt compare`` as a study. It writes
into ``studies/compare/`` the Markdown report (README.md) with its figures and
``results.json`` (the machine's description, the settings, every row and every
solve), and the headline table of ``docs/benchmarks.md``. About ten minutes on
two cores.

    python studies/compare.py              # run it and rewrite studies/compare/
    python studies/compare.py --check      # the committed run's problems and pairs are what the code would run,
                                           # and a rerun at N = 1 gives its statuses, successes and gaps
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np
from tqdm import tqdm

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser
from mpc_hunt.solving import registry
from mpc_hunt.bench.compare import MODES, planned_solves, run_compare
from mpc_hunt.bench.compare_rows import best_known, gap
from mpc_hunt.bench.machine import describe_machine, load_average
from mpc_hunt.bench.problem_set import builtin_problem_set
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.plots.compare_report import write_report

from studies.docs_block import read_block, write_block
from studies.study_check import check_result, read_json_file, run_study

OUT = Path(__file__).resolve().parent / "compare"
HORIZONS, SEED, STARTS, ACCURACY = [1, 5, 10], 0, 4, "default"
COMMAND = "python studies/compare.py"
GAP_RTOL, GAP_ATOL = 1e-3, 1e-6     # a rerun's gaps: solvers converge to their tolerance, not to the last digit


def run(horizons: list[int], progress: bool = True):
    problem_set = builtin_problem_set("default")
    pairs = registry.pairs(objective="paper")
    total = planned_solves(problem_set, len(pairs), horizons, list(MODES), STARTS)
    with tqdm(total=total, desc="compare", unit=" solves", file=sys.stderr, disable=not progress) as bar:
        return run_compare(problem_set, pairs, horizons, list(MODES), np.random.default_rng(SEED),
                           accuracy=ACCURACY, starts=STARTS, progress=lambda: bar.update(1))


def extra() -> dict:
    return {"problem_set": "default", "tags": [], "limit": None, "seed": SEED}


def check() -> list[str]:
    """What differs between the committed run and the code: inputs, then each N = 1 solve's non-timing outcome."""
    committed = read_json_file(OUT / "results.json", f"rerun {COMMAND}")
    problems = [p.id for p in builtin_problem_set("default").problems]
    pairs = [f"{f}:{b}" for f, b in registry.pairs(objective="paper")]
    wanted = {"problems": problems, "pairs": pairs, "horizons": HORIZONS,
              "modes": list(MODES), "accuracy": ACCURACY, "seed": SEED, "reference_starts": STARTS}
    errors = [f"settings.{k}: committed {committed['settings'].get(k)!r}, the code runs {v!r}"
              for k, v in wanted.items() if committed["settings"].get(k) != v]
    if read_block("compare") != headline(committed):
        errors.append("docs/benchmarks.md: its compare table is not the committed results'")
    if errors:
        return errors
    rerun = run([1], progress=False)
    best = best_known(rerun)
    old = {(s["formulation"], s["backend"], s["mode"], s["problem"]): s for s in committed["solves"]
           if s["horizon"] == 1}
    for r in rerun.records:
        key = (r.formulation, r.backend, r.mode, r.problem)
        then = old.get(key)
        if then is None:
            errors.append(f"{key}: not in the committed run")
            continue
        if (then["status"], then["success"]) != (r.status, r.success):
            errors.append(f"{key}: status/success committed {then['status']}/{then['success']}, now "
                          f"{r.status}/{r.success}")
        new_gap = gap(r, best)
        old_gap = then.get("gap")
        if (new_gap is None) != (old_gap is None) or (
                new_gap is not None and abs(new_gap - old_gap) > GAP_ATOL + GAP_RTOL * abs(old_gap)):
            errors.append(f"{key}: optimality gap committed {old_gap}, now {new_gap}")
    return errors


def _cell(row: dict | None) -> str:
    if row is None:
        return "–"
    gap = "–" if row["optimality_gap_median"] is None else f"{row['optimality_gap_median']:.1e}"
    return f"{row['success_rate']:.0%} · {row['solve_time_median_s'] * 1e3:.1f} ms · {gap}"


def headline(results: dict) -> str:
    """The docs' table: per pair and mode, at each horizon, success rate · median all-in time · median gap."""
    horizons = results["settings"]["horizons"]
    by = {(r["formulation"], r["backend"], r["mode"], r["horizon"]): r for r in results["rows"]}
    pairs = [pair.split(":") for pair in results["settings"]["pairs"]]
    lines = markdown.table(["pair", "mode", *(f"N = {n}" for n in horizons)], "l" * (2 + len(horizons)),
                           ([f"{f}/{b}", mode, *(_cell(by.get((f, b, mode, n))) for n in horizons)]
                            for mode in results["settings"]["modes"] for f, b in pairs))
    m = results["machine"]
    return "\n".join(lines) + (f"\n\nMachine: {m['cpu']}, {m['cores']} cores, Python {m['python']}; load average "
                               f"{m['load_average'][0]} at the start, {m['load_average_end'][0]} at the end.\n")


def write_docs() -> None:
    """Rewrite the headline table in docs/benchmarks.md from the committed results."""
    write_block("compare", headline(json.loads((OUT / "results.json").read_text(encoding="utf-8"))))


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="check the committed run instead of running")
    args = parser.parse_args(argv)
    with stop_at_once("compare study"):          # Ctrl-C: at once, nothing written
        if args.check:
            return check_result(check(), "studies/compare", COMMAND)
        machine = describe_machine()
        result = run(HORIZONS)
        machine["load_average_end"] = load_average()
    for path in write_report(result, machine, OUT, COMMAND, extra()):
        print(f"wrote {path}")
    write_docs()
    print("wrote the compare table of docs/benchmarks.md")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

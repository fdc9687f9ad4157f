"""Closed-loop real-time factor of every (formulation, backend) pair: simulated seconds per wall-clock second.

Each installed pair drives the capture stage of both paper scenarios (the
paper's strategy, prediction on, horizon 1 unless told otherwise); the real-time
factor is the hunt's simulated time over the wall-clock time of the whole
closed loop (approach stage, simulation and every capture-stage solve, set-ups
included). Pairs take turns on each scenario, measured side by side in one run,
with each factor also given as a ratio to the NLP on IPOPT of the same run. It
writes ``studies/realtime/`` (README.md, results.json with the machine's
description) and the real-time table of ``docs/benchmarks.md``. A few minutes.

    python studies/realtime.py [--horizons 1]       # run it and rewrite studies/realtime/
    python studies/realtime.py --check              # the committed pairs and scenarios are the code's
    python studies/realtime.py --check-runs         # ... and rerunning the hunts gives the same non-timing figures
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

from mpc_hunt import HuntingStrategy, builtin_scenario, simulate

from mpc_hunt.solving import registry
from mpc_hunt.arguments import CommandParser
from mpc_hunt.control.spec import horizon_argument
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.bench.machine import describe_machine, load_average, machine_lines

from studies.docs_block import read_block, write_block
from studies.study_check import check_result, run_study

OUT = Path(__file__).resolve().parent / "realtime"
SCENARIOS = ("paper-open", "paper-obstacles")
HORIZONS = [1]
BASELINE = ("nlp", "ipopt")
CHECKED = ("captured", "termination", "steps", "failed_solves", "fallbacks")   # capture_time_s: within a step
COMMAND = "python studies/realtime.py"


def hunt(scenario_name: str, pair: tuple[str, str], horizon: int) -> dict:
    scenario = builtin_scenario(scenario_name)
    strategy = HuntingStrategy(scenario, formulation=pair[0], backend=pair[1], horizon=horizon)
    t0 = time.perf_counter()
    result = simulate(scenario, strategy)
    wall = time.perf_counter() - t0
    report = result.to_dict()
    simulated = result.steps * scenario.hunt.time_step
    report.update(simulated_s=simulated, wall_s=wall, real_time_factor=simulated / wall)
    return report


def run(horizons: list[int]) -> list[dict]:
    rows = []
    for name in SCENARIOS:
        for horizon in horizons:
            for pair in registry.pairs(objective="paper"):
                rows.append(hunt(name, pair, horizon))
                r = rows[-1]
                print(f"{name} {pair[0]}/{pair[1]} N={horizon}: real-time factor {r['real_time_factor']:.1f}, "
                      f"captured {r['captured']}", file=sys.stderr, flush=True)
    return rows


def table(rows: list[dict]) -> list[str]:
    base = {(r["scenario"], r["horizon"]): r["real_time_factor"] for r in rows
            if (r["formulation"], r["backend"]) == BASELINE}
    lines = ["| scenario | pair | N | real-time factor | ÷ nlp/ipopt | wall (s) | simulated (s) | captured "
             "| capture time (s) | solves | solve median (ms) | solve p95 (ms) | failed solves | fallbacks |",
             "| --- | --- | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for r in rows:
        t = r["solve_time"]
        capture = "–" if r["capture_time_s"] is None else f"{r['capture_time_s']:.1f}"
        lines.append(
            f"| {r['scenario']} | {r['formulation']}/{r['backend']} | {r['horizon']} | {r['real_time_factor']:.1f} | "
            f"{r['real_time_factor'] / base[(r['scenario'], r['horizon'])]:.2f} | {r['wall_s']:.1f} | "
            f"{r['simulated_s']:.1f} | {'yes' if r['captured'] else 'no'} | {capture} | {t['count']} | "
            f"{t['median_s'] * 1e3:.2f} | {t['p95_s'] * 1e3:.2f} | {r['failed_solves']} | {r['fallbacks']} |")
    return lines


def write(rows: list[dict], machine: dict, horizons: list[int]) -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    settings = {"scenarios": list(SCENARIOS), "pairs": [f"{f}:{b}" for f, b in registry.pairs(objective="paper")],
                "horizons": horizons}
    (OUT / "results.json").write_text(json.dumps({"machine": machine, "settings": settings, "rows": rows}) + "\n",
                                      encoding="utf-8")
    text = ["# Closed-loop real-time factor of each formulation × backend", "",
            f"Regenerate with `{COMMAND}`. Each row is one hunt, the paper's strategy with prediction, its "
            "capture stage solved by the pair. The real-time factor is simulated seconds per wall-clock second of "
            "the whole closed loop (approach stage, simulation, every capture-stage solve, set-ups included); "
            "above 1, the loop runs faster than the robots. The ratio column divides it by the NLP on IPOPT's "
            "in the same run (pairs take turns on each scenario). Solve times are per capture-stage step, all-in, "
            "set-up excluded. Every row's full report is in `results.json`.", "",
            "## Machine", "", *machine_lines(machine), "", "## Results", "", *table(rows), ""]
    (OUT / "README.md").write_text("\n".join(text), encoding="utf-8")


def headline(results: dict) -> str:
    """The docs' table: each pair's real-time factor on each scenario, and its ratio to the NLP on IPOPT's."""
    rows = results["rows"]
    base = {(r["scenario"], r["horizon"]): r["real_time_factor"] for r in rows
            if (r["formulation"], r["backend"]) == BASELINE}
    keys = [(s, n) for s in results["settings"]["scenarios"] for n in results["settings"]["horizons"]]
    by = {(r["formulation"], r["backend"], r["scenario"], r["horizon"]): r for r in rows}
    lines = ["| pair | " + " | ".join(f"{s}, N = {n}" for s, n in keys) + " |",
             "| --- | " + " | ".join("---:" for _ in keys) + " |"]
    for pair in results["settings"]["pairs"]:
        f, b = pair.split(":")
        cells = [by[(f, b, s, n)] for s, n in keys]
        lines.append(f"| {f}/{b} | " + " | ".join(
            f"{r['real_time_factor']:.1f} (× {r['real_time_factor'] / base[(r['scenario'], r['horizon'])]:.2f})"
            + ("" if r["captured"] else ", not captured") for r in cells) + " |")
    m = results["machine"]
    return "\n".join(lines) + (f"\n\nMachine: {m['cpu']}, {m['cores']} cores, Python {m['python']}; load average "
                               f"{m['load_average'][0]} at the start, {m['load_average_end'][0]} at the end.\n")


def check(rerun: bool) -> list[str]:
    committed = json.loads((OUT / "results.json").read_text(encoding="utf-8"))
    settings = committed["settings"]
    wanted = {"scenarios": list(SCENARIOS), "pairs": [f"{f}:{b}" for f, b in registry.pairs(objective="paper")]}
    errors = [f"settings.{k}: committed {settings.get(k)!r}, the code runs {v!r}"
              for k, v in wanted.items() if settings.get(k) != v]
    if read_block("realtime") != headline(committed):
        errors.append("docs/benchmarks.md: its real-time table is not the committed results'")
    if errors or not rerun:
        return errors
    for old in committed["rows"]:
        new = hunt(old["scenario"], (old["formulation"], old["backend"]), old["horizon"])
        key = f"{old['scenario']} {old['formulation']}/{old['backend']} N={old['horizon']}"
        errors += [f"{key}: {k} committed {old[k]!r}, now {new[k]!r}" for k in CHECKED if old[k] != new[k]]
        if (old["capture_time_s"] is None) != (new["capture_time_s"] is None) or (
                old["capture_time_s"] is not None and abs(old["capture_time_s"] - new["capture_time_s"]) > 0.15):
            errors.append(f"{key}: capture_time_s committed {old['capture_time_s']}, now {new['capture_time_s']}")
    return errors


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--horizons", type=horizon_argument, nargs="+", default=HORIZONS)
    parser.add_argument("--check", action="store_true", help="check the committed inputs against the code")
    parser.add_argument("--check-runs", action="store_true", help="also rerun every hunt (minutes)")
    args = parser.parse_args(argv)
    with stop_at_once("realtime study"):         # Ctrl-C: at once, nothing written
        if args.check or args.check_runs:
            return check_result(check(args.check_runs), "studies/realtime", COMMAND)
        machine = describe_machine()
        rows = run(args.horizons)
        machine["load_average_end"] = load_average()
    write(rows, machine, args.horizons)
    print(f"wrote {OUT / 'README.md'}")
    write_block("realtime", headline(json.loads((OUT / "results.json").read_text(encoding="utf-8"))))
    print("wrote the real-time table of docs/benchmarks.md")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

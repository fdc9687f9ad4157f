"""Random hunts at scale: the default sweep strategies on 500 random hunts (docs/robustness.md).

Runs the sweep of ``mpc-hunt sweep --hunts 500 --seed 1`` (``mpc_hunt.sweep.stored_run``) with the default
strategies (``mpc_hunt.sweep.runner.DEFAULT_STRATEGIES``) and the default scenario ranges into
``studies/sweep/sweep.db``, resuming it if it exists; then reruns the first
``SAMPLE`` hunts of each strategy ``MEMBERS`` times with every start moved by a
nanometre (``ensemble.json``: which outcomes a last-bit difference flips, and
each figure's band); then writes ``studies/sweep/`` (README.md, summary.json
with the machine's description, the figures) and the results table of
docs/robustness.md. About 1.5 hours on 2 cores; an interrupted sweep continues
where it stopped.

    python studies/sweep.py             # run (or resume) the sweep and its ensemble, then write the report
    python studies/sweep.py --rerun enclose:rti:hpipm:10   # one strategy again, after its controller changed
    python studies/sweep.py --check     # the committed report is the committed file's, for the code's strategies
                                        # and ranges; a few hunts whose outcome the ensemble shows robust, rerun,
                                        # keep that outcome and land inside their bands
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.world.ensemble import SCALE, band, outside_band, widened
from mpc_hunt.bench.machine import machine_lines
from mpc_hunt.sweep.random_scenario import ScenarioRanges, ranges_to_dict
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.plots.sweep import write_plots
from mpc_hunt.plots.typical_hunts import plot_typical_hunts
from mpc_hunt.sweep.runner import DEFAULT_STRATEGIES, Hunt, check_buildable, run_hunt, run_local, tasks
from mpc_hunt.world.behaviours import DEFAULT_BEHAVIOUR
from mpc_hunt.sweep.store import SweepStore, self_contained, stored_rows
from mpc_hunt.sweep.stored_run import run_into
from mpc_hunt.sweep.summary import summarise, table
from mpc_hunt.sweep.typical import typical_hunts

from studies.docs_block import read_block, write_block
from studies.study_check import check_result, read_json_file, run_study
from studies.sweep_study import measured_run

OUT = Path(__file__).resolve().parent / "sweep"
DB = OUT / "sweep.db"
DOCS = Path(__file__).resolve().parents[1] / "docs" / "robustness.md"
HUNTS, SEED = 500, 1
COMMAND = "python studies/sweep.py"
ENSEMBLE = OUT / "ensemble.json"
SAMPLE, MEMBERS = 30, 4   # the ensemble: hunts 0..SAMPLE-1 of each strategy, each rerun MEMBERS times
# --check reruns, per strategy, the quickest hunt of the sample that every member captured, and the quickest that
# every member lost in the same way after a capture-stage solve (any loss, for a strategy without one)
ROBUST = ("outcome", "cause", "termination")       # exact where every member agrees
BANDED = ("steps", "solves", "failed_solves", "fallbacks", "capture_time_s", "path_length_m",
          "min_obstacle_clearance_m", "min_defender_separation_m")
WIDEN, FLOOR_RTOL, FLOOR_ATOL = 0.5, 1e-6, 1e-9    # as studies/reproduce_paper.py


def arguments() -> dict:
    """What the sweep runs, as its results file stores it."""
    return {"strategies": [ControllerSpec.parse(s).label for s in DEFAULT_STRATEGIES], "hunts": HUNTS, "seed": SEED,
            "ranges": ranges_to_dict(ScenarioRanges())}


def wall_times(rows: list[dict]) -> dict:
    """Per strategy: the hunts' total, median and largest wall time on their workers."""
    out = {}
    for strategy in dict.fromkeys(r["strategy"] for r in rows):
        times = [r["wall_time_s"] for r in rows if r["strategy"] == strategy and r["wall_time_s"] is not None]
        out[strategy] = {"total_s": float(np.sum(times)), "median_s": float(np.median(times)),
                         "max_s": float(np.max(times))}
    return out


def _solve_lines(summaries: list[dict]) -> list[str]:
    def value(x, scale: float, digits: int, unit: str) -> str:
        return "–" if x is None else f"{scale * x:.{digits}f} {unit}"

    return [f"- `{s['strategy']}`: the longest capture-stage solve took "
            f"{value(s['solve_time_max_s'], 1e3, 1, 'ms')}; least obstacle clearance "
            f"{value(s['min_obstacle_clearance_m'], 1, 3, 'm')}, least defender separation "
            f"{value(s['min_defender_separation_m'], 1, 6, 'm')}, least arena margin "
            f"{value(s['min_arena_margin_m'], 1, 3, 'm')}; a defender came inside R_safe in "
            f"{s['safety_breaches_approach']} hunts while approaching and {s['safety_breaches_capture']} while "
            "capturing." for s in summaries]


def _escape_lines(rows: list[dict]) -> list[str]:
    """Per paper strategy: how many of its escapes came before any defender reached the capture stage."""
    lines = []
    for strategy in dict.fromkeys(r["strategy"] for r in rows if r["strategy"].startswith("paper:")):
        escaped = [r for r in rows if r["strategy"] == strategy and r["cause"] == "attacker_escaped"
                   and r["outcome"] == "failed"]
        early = [r for r in escaped if not r["solves"]]
        lines.append(f"- `{strategy}`: {len(early)} of its {len(escaped)} escapes came before any defender was "
                     f"within R_agg (no capture-stage solve); {sum(not r['reachable'] for r in early)} of those "
                     f"hunts are unreachable, {sum(not r['comfortable'] for r in early)} not comfortable "
                     "(the unreachable ones among them).")
    return lines


def report(summaries: list[dict], walls: dict, machine: dict, rows: list[dict], ensemble: dict) -> str:
    ranges = ranges_to_dict(ScenarioRanges())
    lines = [f"# {HUNTS} random hunts per strategy", "",
             f"Regenerate with `{COMMAND}` (it runs `mpc-hunt sweep --hunts {HUNTS} --seed {SEED}` with the "
             "default strategies and scenario ranges into `sweep.db`, then writes this report and the figures "
             f"from that file, as `mpc-hunt sweep-report sweep.db --plot .` does). Every strategy meets the same "
             f"hunts: hunt i is the scenario `random-{SEED}-i`, drawn by "
             f"`mpc_hunt.sweep.random_scenario.sweep_scenario({SEED}, i)` from the default ranges "
             f"(docs/robustness.md): `{json.dumps(ranges)}`. The success rate counts the hunts that can be "
             "captured by definition; the next column leaves out the unreachable ones too (no defender can come within "
             "R_agg of the attacker's undisturbed path before it leaves, or, with two defenders, no obstacle is within "
             "the attacker's reach to stand in for the third: lost by any controller, "
             "`mpc_hunt/sweep/reachability.py`), and the one after counts only the comfortable ones (three defenders, "
             "or all if fewer, can arrive 20 s before the attacker leaves: not a race only a perfect controller wins). "
             "Failures are by cause (docs/robustness.md); the hunts in which a defender came inside an obstacle's "
             "safety distance R_safe are counted by stage. One row per hunt, with its "
             "scenario's full parameters, is in `sweep.db` (SQLite).", "",
             "## Results", "", table(summaries), "", *_solve_lines(summaries), *_escape_lines(rows), "",
             "![success by defenders](success_by_n_defenders.png) "
             "![success by obstacles](success_by_n_obstacles.png)",
             "![success by speed ratio](success_by_speed_ratio.png) ![capture times](capture_times.png)", "",
             "The best strategy's typical captured and typical lost hunt (`mpc_hunt/sweep/typical.py`: the capture "
             "nearest its median capture time; of the reachable hunts lost by the commonest cause, the one whose "
             "closest approach is nearest their median), rerun and zoomed on the last 60 s:", "",
             "![typical hunts](typical_hunts.png)", "",
             "## What a nanometre changes", "", *ensemble_lines(ensemble), "",
             "## Cost", "",
             *markdown.table(["strategy", "wall time, all hunts", "per hunt, median", "longest hunt"], "lrrr",
                             ([s, f"{w['total_s'] / 3600:.2f} h", f"{w['median_s']:.1f} s", f"{w['max_s']:.0f} s"]
                              for s, w in walls.items())),
             "", "## Machine", "", *machine_lines(machine), ""]
    return "\n".join(lines)


def headline(summaries: list[dict]) -> str:
    return (f"Produced by `{COMMAND}` ({HUNTS} hunts per strategy, seed {SEED}; the report, figures and every row "
            f"are in [studies/sweep/](../studies/sweep/README.md)):\n\n{table(summaries)}\n")


def write(machine: dict) -> None:
    self_contained(DB)
    rows = stored_rows(DB)
    ensemble = json.loads(ENSEMBLE.read_text(encoding="utf-8")) if ENSEMBLE.exists() else \
        {"sample": SAMPLE, "members": MEMBERS, "scale_m": SCALE, "hunts": {}}
    missing = [s for s in arguments()["strategies"] if s not in ensemble["hunts"]]
    if missing:
        ensemble["hunts"].update(run_ensemble(rows, missing)["hunts"])
        ensemble["hunts"] = {s: ensemble["hunts"][s] for s in arguments()["strategies"]}
        ENSEMBLE.write_text(json.dumps(ensemble, indent=1) + "\n", encoding="utf-8")
    summaries = summarise(rows)
    walls = wall_times(rows)
    write_plots(rows, OUT)
    plot_typical_hunts(typical_hunts(rows, summaries), OUT)
    (OUT / "summary.json").write_text(json.dumps({"machine": machine, "arguments": arguments(),
                                                  "strategies": summaries, "wall_time": walls}, indent=1) + "\n",
                                      encoding="utf-8")
    (OUT / "README.md").write_text(report(summaries, walls, machine, rows, ensemble), encoding="utf-8")
    write_block("sweep", headline(summaries), DOCS)


def run_ensemble(rows: list[dict], strategies: list[str]) -> dict:
    """The sample's hunts rerun with their starts moved by a nanometre: per strategy and hunt, what every member
    (the committed row and the reruns) shares, and each figure's band."""
    nominal = {(r["strategy"], r["index"]): r for r in rows if r["index"] < SAMPLE and r["strategy"] in strategies}
    todo = [Hunt(s, SEED, i, arguments()["ranges"], member=m) for i in range(SAMPLE)
            for s in strategies for m in range(1, MEMBERS + 1)]
    members: dict[tuple, list[dict]] = {key: [row] for key, row in nominal.items()}
    for row in run_local(todo):
        members[(row["strategy"], row["index"])].append(row)
    hunts: dict[str, dict] = {}
    for (strategy, index), group in sorted(members.items(), key=lambda kv: kv[0][1]):
        bands = {}
        for k in BANDED:
            values = [r[k] for r in group]
            bands[k] = band(values) if None not in values else None
        hunts.setdefault(strategy, {})[str(index)] = {
            "robust": all(r[k] == group[0][k] for r in group for k in ROBUST),
            **{k: group[0][k] for k in ROBUST}, "outcomes": sorted({r["outcome"] for r in group}), "band": bands,
            "wall_time_s": group[0]["wall_time_s"]}
    return {"sample": SAMPLE, "members": MEMBERS, "scale_m": SCALE, "hunts": hunts}


def _flipped(hunts: dict) -> list[str]:
    return [i for i, h in hunts.items() if len(h["outcomes"]) > 1]


def ensemble_lines(ensemble: dict) -> list[str]:
    """What a nanometre does to the sample's hunts, per strategy."""
    lines = [f"Hunts 0–{ensemble['sample'] - 1} of each strategy were rerun {ensemble['members']} times with every "
             f"robot's start moved by at most {ensemble['scale_m']:g} m (`ensemble.json`): a difference no robot "
             "could tell, of the size a last-bit difference in arithmetic grows into within a few steps."]
    for strategy, hunts in ensemble["hunts"].items():
        flipped, moved = _flipped(hunts), [i for i, h in hunts.items() if not h["robust"]]
        spread = {i: h["band"]["steps"]["max"] - h["band"]["steps"]["min"] for i, h in hunts.items()}
        changed = [i for i, s in spread.items() if s > 0]
        widest = max(spread, key=lambda i: (spread[i], -int(i)))
        lines.append(f"- `{strategy}`: {len(flipped)} of {len(hunts)} hunts changed outcome in some member"
                     + (f" (hunts {', '.join(flipped)})" if flipped else "")
                     + f", {len(moved)} changed outcome, cause or termination; {len(changed)} took another number "
                     f"of steps" + (f", hunt {widest} from {hunts[widest]['band']['steps']['min']:.0f} to "
                                    f"{hunts[widest]['band']['steps']['max']:.0f}." if changed else "."))
    flips = any(not h["robust"] for hunts in ensemble["hunts"].values() for h in hunts.values())
    lines.append(("Some outcomes turn on a nanometre" if flips else "No sampled outcome turned on a nanometre, but "
                  "the figures of a hunt can") + ", so another machine's arithmetic can move this report's figures "
                 "(and, for hunts near the edge of an outcome, its counts) within their confidence intervals, not to "
                 "the bit. `--check` reruns only hunts every member agrees on, and holds their figures to the "
                 "ensemble's bands.")
    return lines


def rerun_choice(hunts: dict) -> list[str]:
    """The hunts --check reruns for one strategy (see above): at most one captured, one lost."""
    robust = sorted((i for i, h in hunts.items() if h["robust"]), key=lambda i: (hunts[i]["wall_time_s"], int(i)))
    captured = [i for i in robust if hunts[i]["outcome"] == "captured"]
    lost = [i for i in robust if hunts[i]["outcome"] != "captured"]
    solved = [i for i in lost if hunts[i]["band"]["solves"]["min"] > 0]
    return captured[:1] + (solved or lost)[:1]


def _off_band(label: str, old: dict, new: dict) -> list[str]:
    errors = [f"{label}: {k} was {old[k]!r} in every member, now {new[k]!r}" for k in ROBUST if new[k] != old[k]]
    for k in BANDED:
        b = old["band"][k]
        floor = FLOOR_RTOL * abs(b["median"]) + FLOOR_ATOL if b is not None else 0.0
        if outside_band(new[k], b, WIDEN, floor):
            shown = "none" if b is None else "{:.9g} to {:.9g}".format(*widened(b, WIDEN, floor))
            errors.append(f"{label}: {k} {new[k]!r} is outside its band ({shown})")
    return errors


def check() -> list[str]:
    store = SweepStore(DB)
    stored = store.arguments
    rows = store.rows()
    store.close()
    errors = [f"sweep.db: {k} is {stored.get(k)!r}, the study runs {v!r}"
              for k, v in arguments().items() if stored.get(k) != v]
    if len(rows) != HUNTS * len(stored["strategies"]):
        errors.append(f"sweep.db: {len(rows)} hunts, not {HUNTS} per strategy (resume it)")
    committed = read_json_file(OUT / "summary.json", f"rerun {COMMAND}")
    summaries = json.loads(json.dumps(summarise(rows)))
    if committed["strategies"] != summaries:
        errors.append("summary.json: not the summary of sweep.db")
    if read_block("sweep", DOCS) != headline(summaries):
        errors.append("docs/robustness.md: its results table is not the summary of sweep.db")
    won = [f"{r['strategy']} hunt {r['index']}" for r in rows if r["outcome"] == "captured" and not r["reachable"]]
    if won:
        errors.append(f"sweep.db: unreachable hunts were captured ({', '.join(won[:3])}): "
                      "mpc_hunt/sweep/reachability.py is wrong")
    ensemble = json.loads(ENSEMBLE.read_text(encoding="utf-8"))
    if (ensemble["sample"], ensemble["members"], ensemble["scale_m"]) != (SAMPLE, MEMBERS, SCALE):
        errors.append(f"ensemble.json: {ensemble['sample']} hunts × {ensemble['members']} members, the study runs "
                      f"{SAMPLE} × {MEMBERS}: delete it and rerun {COMMAND}")
    if errors:
        return errors
    for strategy in stored["strategies"]:
        hunts = ensemble["hunts"][strategy]
        for index in rerun_choice(hunts):
            new = run_hunt(Hunt(strategy, SEED, int(index), stored["ranges"]))
            errors += _off_band(f"{strategy} hunt {index}", hunts[index], new)
    return errors


def run_sweep() -> int:
    """Run (or resume) the sweep into sweep.db and print its summary, as ``mpc-hunt sweep --hunts HUNTS --seed SEED
    --output sweep.db --json [--resume]`` does."""
    strategies = arguments()["strategies"]
    check_buildable(strategies, (DEFAULT_BEHAVIOUR,), SEED, ScenarioRanges())   # each built once, before the file
    store = SweepStore(DB, arguments(), resume=DB.exists())
    try:
        stopped = run_into(store, tasks(strategies, HUNTS, SEED, ScenarioRanges(), store.done()))
        print(json.dumps({"strategies": summarise(store.rows())}))     # the summary so far, if stopped
    finally:
        store.close()
    if stopped:
        print(f"mpc-hunt sweep: {stopped}; finished hunts are in {DB} (continue with --resume)", file=sys.stderr)
        return 2
    return 0


def forget(strategies: list[str]) -> None:
    """Drop these strategies' hunts from sweep.db and their members from ensemble.json: the run redoes them."""
    store = SweepStore(DB, arguments(), resume=True)
    try:
        for strategy in strategies:
            print(f"{strategy}: {store.forget(strategy)} hunts to run again")
    finally:
        store.close()
    if ENSEMBLE.exists():
        ensemble = json.loads(ENSEMBLE.read_text(encoding="utf-8"))
        ensemble["hunts"] = {s: h for s, h in ensemble["hunts"].items() if s not in strategies}
        ENSEMBLE.write_text(json.dumps(ensemble, indent=1) + "\n", encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="check the committed results against the code")
    parser.add_argument("--rerun", action="append", default=[], metavar="STRATEGY",
                        help="run this strategy's hunts and ensemble again (its controller changed); repeatable. An "
                             "interrupted rerun continues without it")
    args = parser.parse_args(argv)
    if args.check:
        with stop_at_once("sweep study"):        # Ctrl-C: at once (the check writes nothing)
            return check_result(check(), "studies/sweep", COMMAND)
    if args.rerun:
        try:
            forget(args.rerun)
        except MpcHuntError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
    return measured_run(OUT, run_sweep, write, f"{OUT / 'README.md'} and the results table of docs/robustness.md",
                        error="mpc-hunt sweep: error")


if __name__ == "__main__":
    sys.exit(run_study(main))

"""Attackers the defenders do not know: every strategy against every attacker behaviour, and belief errors.

Runs the sweep machinery (``mpc_hunt.sweep.runner``) on the reachable hunts among the first ``--hunts`` of the
sweep ``--seed`` (unreachable hunts are lost by any controller, whatever the attacker: docs/robustness.md):
every strategy of ``STRATEGIES`` against every behaviour of ``mpc_hunt.world.behaviours.BEHAVIOURS`` with the
exact belief, and the contain controller and the Voronoi baseline with each belief error of ``BELIEFS``
(the trap controller reads nothing of the belief but the attacker's top speed, which no error changes).
Rows go into ``studies/attackers/sweep.db`` (resumed if it exists, so an interrupted run continues); then it
writes ``studies/attackers/`` (README.md, summary.json with the machine, the figures).

    python studies/attackers.py                   # run (or resume), then write the report
    python studies/attackers.py --hunts 200 --seed 3 --output /tmp/a   # another draw, into another folder
    python studies/attackers.py --check           # the committed report is the committed file's summary, and the
                                                  # contain controller's quickest capture per attacker still captures
"""

from __future__ import annotations

import json
import statistics
import sys
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

from mpc_hunt.arguments import CommandParser, count
from mpc_hunt.bench.machine import machine_lines
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.plots.capture_region import plot_capture_regions
from mpc_hunt.plots.sweep import write_plots
from mpc_hunt.sweep.random_scenario import ScenarioRanges, ranges_to_dict, sweep_scenario
from mpc_hunt.sweep.reachability import reachable
from mpc_hunt.sweep.runner import Hunt
from mpc_hunt.sweep.store import stored_rows
from mpc_hunt.sweep.summary import summarise, table
from mpc_hunt.sweep.typical import rerun, typical_rows
from mpc_hunt.world.behaviours import BEHAVIOURS

from studies.study_check import check_result, run_study
from studies.sweep_study import (add_study_options, keys, measured_run, missing, quickest_captures, run_file,
                                 still_captured, stop_status)

OUT = Path(__file__).resolve().parent / "attackers"
COMMAND = "python studies/attackers.py"
HUNTS, SEED = 20, 1
MAX_HUNTS = 1000
RECOMMENDED_LABEL = ControllerSpec().label
FOCUS = "trap:rti:hpipm:10"          # the controller built on the attacker's reachable set (docs/model.md, E16)
STRATEGIES = tuple(dict.fromkeys((RECOMMENDED_LABEL, FOCUS, "contain:rti:hpipm:10", "voronoi", "apf",
                                  "paper:rti:hpipm:5")))
EXACT = "exact"
BELIEFS = ("perception_radius=1.3x", "eta=3x", "intent_heading=60")   # errors run by the BELIEF_STRATEGIES
# The controllers that read the believed attacker beyond its top speed: contain (its floor R_agg + R_hunt / 2 while
# the attacker is not enclosed) and the Voronoi baseline (the same floor and its intercepts). Trap reads only the top
# speed, which no belief error changes, so its commands are the same under every error.
BELIEF_STRATEGIES = ("contain:rti:hpipm:10", "voronoi")


def hunt_indices(hunts: int, seed: int) -> list[int]:
    """The reachable hunts among the first ``hunts`` of the sweep ``seed`` (default ranges)."""
    return [i for i in range(hunts) if reachable(sweep_scenario(seed, i, ScenarioRanges()))]


def todo(indices: list[int], seed: int) -> list[Hunt]:
    """Every (strategy, attacker, belief, hunt) of the study."""
    ranges = ranges_to_dict(ScenarioRanges())
    combos = [(s, a, EXACT) for s in STRATEGIES for a in BEHAVIOURS] + \
             [(s, a, b) for s in BELIEF_STRATEGIES for a in BEHAVIOURS for b in BELIEFS]
    return [Hunt(s, seed, i, ranges, attacker=a, belief=b) for i in indices for s, a, b in combos]


def arguments(hunts: int, seed: int) -> dict:
    return {"strategies": [ControllerSpec.parse(s).label for s in STRATEGIES], "attackers": list(BEHAVIOURS),
            "beliefs": [EXACT, *BELIEFS], "hunts": hunts, "seed": seed, "ranges": ranges_to_dict(ScenarioRanges())}


def run(db: Path, hunts: int, seed: int, indices: list[int] | None = None) -> str | None:
    """The study's hunts (on the reachable draws ``indices``, found if not given) into ``db``; None when all
    finished, else why it stopped."""
    indices = hunt_indices(hunts, seed) if indices is None else indices
    return run_file(db, arguments(hunts, seed), todo(indices, seed))


def headline(summaries: list[dict]) -> list[str]:
    """Captured / hunts among the comfortable (and reachable) ones, strategy × attacker, exact belief; then the
    belief errors."""
    def cell(s: dict, kind: str) -> str:
        total = s["comfortable"] if kind == "comfortable" else s["hunts"] - s["unreachable"] \
            - s["uncapturable_by_definition"]
        rate = s[f"success_rate_{kind}"]
        lo, hi = s[f"success_rate_{kind}_ci95"]
        won = round(rate * total) if rate is not None else 0
        return f"{won} / {total}" + ("" if rate is None else f" ({100 * lo:.0f}–{100 * hi:.0f} %)")

    exact = [s for s in summaries if s["belief"] == EXACT]
    strategies = list(dict.fromkeys(s["strategy"] for s in exact))
    by = {(s["strategy"], s["attacker"], s["belief"]): s for s in summaries}
    lines = []
    for kind in ("comfortable", "reachable"):
        lines += [f"Captured / {kind} hunts (95 % interval), exact belief:", "",
                  "| attacker | " + " | ".join(f"`{s}`" for s in strategies) + " |",
                  "| --- |" + " ---: |" * len(strategies)]
        lines += [f"| {a} | " + " | ".join(cell(by[(s, a, EXACT)], kind) if (s, a, EXACT) in by else "–"
                                          for s in strategies) + " |" for a in BEHAVIOURS]
        lines.append("")
    beliefs = [b for b in dict.fromkeys(s["belief"] for s in summaries) if b != EXACT]
    for strategy in BELIEF_STRATEGIES:
        lines += [f"`{strategy}`, captured / comfortable hunts per belief error:", "",
                  "| attacker | " + " | ".join(beliefs) + " |", "| --- |" + " ---: |" * len(beliefs)]
        lines += [f"| {a} | " + " | ".join(cell(by[(strategy, a, b)], "comfortable") if (strategy, a, b) in by
                                          else "–" for b in beliefs) + " |" for a in BEHAVIOURS]
        lines.append("")
    return lines


def verdicts(rows: list[dict]) -> list[str]:
    """What the table says of the study's two questions, from the rows (exact belief): does the trap controller
    capture at least as many comfortable hunts as the Voronoi baseline against each attacker (and how fast, on the
    hunts both capture), and is the minimax attacker at least as hard for the baseline as the gap-seeker?"""
    exact = [r for r in rows if r["belief"] == EXACT and r["comfortable"]]

    def won(strategy: str, attacker: str) -> dict:
        return {r["index"]: r["capture_time_s"] for r in exact if r["strategy"] == ControllerSpec.parse(strategy).label
                and r["attacker"] == attacker and r["outcome"] == "captured"}

    lines = ["| attacker | comfortable | `trap` captured | `voronoi` captured | at least as many | median capture time "
             "on the hunts both capture, `trap` / `voronoi` |", "| --- | ---: | ---: | ---: | --- | --- |"]
    for attacker in BEHAVIOURS:
        total = len({r["index"] for r in exact if r["attacker"] == attacker})
        mine, theirs = won(FOCUS, attacker), won("voronoi", attacker)
        both = sorted(set(mine) & set(theirs))
        times = (f"{statistics.median(mine[i] for i in both):.1f} s / {statistics.median(theirs[i] for i in both):.1f} s"
                 f" ({len(both)} hunts)" if both else "–")
        lines.append(f"| {attacker} | {total} | {len(mine)} | {len(theirs)} | "
                     f"{'yes' if len(mine) >= len(theirs) else 'no'} | {times} |")
    gap, minimax = len(won("voronoi", "gap")), len(won("voronoi", "minimax"))
    verdict = "at least as hard for the Voronoi baseline as" if minimax <= gap else "easier for the Voronoi baseline than"
    lines += ["", f"The minimax attacker is {verdict} the gap-seeker: the baseline captures {minimax} comfortable "
              f"hunts against `minimax`, {gap} against `gap`.", ""]
    return lines


def lost_figure(rows: list[dict], folder: Path) -> list[Path]:
    """A typical lost hunt of the contain controller per attacker (exact belief), rerun and drawn."""
    cases = []
    for attacker in BEHAVIOURS:
        mine = [r for r in rows if r["attacker"] == attacker and r["belief"] == EXACT]
        row = typical_rows(mine, FOCUS).get("lost")
        if row is not None:
            scenario, result = rerun(row)
            cases.append((result, scenario, f"{attacker}: {row['name']}, lost ({row['cause']})"))
    if not cases:
        return []
    plot_capture_regions(cases, folder / "typical_lost.png")
    return [folder / "typical_lost.png"]


def report(rows: list[dict], summaries: list[dict], machine: dict, hunts: int, seed: int) -> str:
    indices = sorted({r["index"] for r in rows})
    return "\n".join([
        "# Attackers the defenders do not know", "",
        f"Regenerate with `{COMMAND}`. The reachable hunts among the first {hunts} of the sweep with seed {seed} "
        f"(default ranges, docs/robustness.md; {len(indices)} hunts), each run by every strategy against every "
        "attacker behaviour (docs/model.md, E13) with the exact belief, and by the contain controller (E15) and the "
        "Voronoi baseline with each belief error (E14: the world's value over the believed one; the heading error "
        "drawn per hunt; the trap controller, E16, reads nothing of the belief but the attacker's top speed, which "
        "no error changes). Every controller is built on the belief, never on the world's behaviour. One row per "
        "hunt is in `sweep.db` (`mpc-hunt sweep-report studies/attackers/sweep.db` recomputes the table).", "",
        *headline(summaries),
        f"`{FOCUS}` beside the Voronoi baseline, comfortable hunts, exact belief:", "", *verdicts(rows),
        "![success by attacker](success_by_attacker.png)", "",
        f"A typical lost hunt of `{FOCUS}` per attacker (`mpc_hunt/sweep/typical.py`), rerun:", "",
        "![typical lost hunts](typical_lost.png)", "", "## Every summary", "", table(summaries), "",
        "## Machine", "", *machine_lines(machine), ""])


def write(db: Path, folder: Path, machine: dict, hunts: int, seed: int) -> None:
    rows = stored_rows(db)
    summaries = summarise(rows)
    write_plots(rows, folder)
    lost_figure(rows, folder)
    (folder / "summary.json").write_text(json.dumps({"machine": machine, "arguments": arguments(hunts, seed),
                                                     "strategies": summaries}, indent=1) + "\n", encoding="utf-8")
    (folder / "README.md").write_text(report(rows, summaries, machine, hunts, seed), encoding="utf-8")


def check(folder: Path) -> list[str]:
    committed = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    hunts, seed = committed["arguments"]["hunts"], committed["arguments"]["seed"]
    errors = [] if committed["arguments"] == arguments(hunts, seed) else \
        ["summary.json: its strategies, attackers, beliefs or ranges are not the study's"]
    rows = stored_rows(folder / "sweep.db")
    if json.loads(json.dumps(summarise(rows))) != committed["strategies"]:
        errors.append("summary.json: not the summary of sweep.db")
    left = missing(todo(hunt_indices(hunts, seed), seed), keys(rows))
    if left:
        errors.append(f"sweep.db: {len(left)} hunts of the study are missing (resume it)")
    if errors:
        return errors
    return still_captured(quickest_captures(rows, FOCUS, EXACT), seed, committed["arguments"]["ranges"],
                          "sweep.db")


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hunts", type=count(MAX_HUNTS), default=HUNTS, help=f"draws to pick from (default {HUNTS})")
    add_study_options(parser, SEED, OUT)
    args = parser.parse_args(argv)
    if args.check:
        with stop_at_once("attackers study"):
            return check_result(check(args.output), "studies/attackers", COMMAND)
    try:
        indices = hunt_indices(args.hunts, args.seed)        # cheap: draws only, before any file is written
    except MpcHuntError as exc:
        parser.error(str(exc))
    if not indices:
        parser.error(f"--hunts {args.hunts}: none of the first {args.hunts} draws of --seed {args.seed} is "
                     "reachable by the defenders, so no hunt would run; give more hunts (the study keeps the "
                     "reachable ones)")
    db = args.output / "sweep.db"
    return measured_run(args.output, lambda: stop_status(run(db, args.hunts, args.seed, indices), "attackers.py", db),
                        lambda machine: write(db, args.output, machine, args.hunts, args.seed),
                        args.output / "README.md")


if __name__ == "__main__":
    sys.exit(run_study(main))

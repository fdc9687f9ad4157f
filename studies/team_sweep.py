"""The distributed capture stage beside the centralised one on random hunts, against every attacker, and in teams.

Two sweeps of the sweep machinery (``mpc_hunt.sweep.runner``), each into its own file in
``studies/team_sweep/`` (resumed if it exists, so an interrupted run continues):

* ``attackers.db``: the first ``--hunts`` hunts of the sweep ``--seed`` (default ranges, docs/robustness.md),
  each run by the enclose controller (``enclose``, ``rti`` on ``hpipm``, N = 10) and by the same
  controller with its capture stage distributed (``distributed``: one QP per robot, one Jacobi round a step),
  against every attacker behaviour (docs/model.md, E13), exact belief;
* ``teams.db``: the first ``--team-hunts`` hunts of the same seed with 6 to 12 defenders (``n_defenders`` =
  [6, 12]), the paper's attacker, both controllers: how long their solves take in teams (a distributed step
  is here every robot's QP one after another in one process; on the robots, the slowest robot's).

Then writes ``studies/team_sweep/`` (README.md, summary.json with the machine).

    python studies/team_sweep.py                 # run (or resume), then write the report
    python studies/team_sweep.py --hunts 300     # the draws of the sweep `mpc-hunt sweep --hunts 300 --seed 4`
    python studies/team_sweep.py --keep-previous # before a rerun at another size: each file's rows kept beside it
                                                 # (attackers.previous.json, teams.previous.json), which the
                                                 # rerun's report sets beside its own (studies/previous_rows.py)
    python studies/team_sweep.py --check         # the committed report is the files' summary for the code's
                                                 # strategies and ranges; the distributed stage's quickest capture
                                                 # per attacker still captures
"""

from __future__ import annotations

import json
import sys
from dataclasses import replace
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser, count
from mpc_hunt.bench.machine import machine_lines
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.sweep import paired
from mpc_hunt.sweep.random_scenario import ScenarioRanges, ranges_to_dict
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.sweep.runner import Hunt
from mpc_hunt.sweep.store import stored_rows
from mpc_hunt.sweep.summary import summarise, table
from mpc_hunt.world.behaviours import BEHAVIOURS

from studies.study_check import check_result, read_json_file, run_study
from studies.previous_rows import WHY, again, against_last_run, kept_path, read
from studies.sweep_study import (MAX_HUNTS, add_study_options, costs, keep_previous, keys, measured_run, missing,
                                 quickest_captures, run_file, still_captured, stop_status)

OUT = Path(__file__).resolve().parent / "team_sweep"
COMMAND = "python studies/team_sweep.py"
HUNTS, TEAM_HUNTS, SEED = 200, 40, 4  # 3280 hunts, about 1.5 h of two cores; the two stages end alike in most
                                      # hunts, so the paired interval is narrow already (about ±1 point where none
                                      # differs), and 300 would cost half as much again
CENTRAL, DISTRIBUTED = "enclose:rti:hpipm:10", "enclose:distributed:hpipm:10"
STRATEGIES = (CENTRAL, DISTRIBUTED)
TEAM_ATTACKER = "apf"
TEAMS = (6, 12)               # n_defenders of the teams' sweep
FILES = ("attackers.db", "teams.db")


def sweeps(hunts: int, team_hunts: int, seed: int) -> dict[str, tuple[dict, list[Hunt]]]:
    """Per file: its arguments and every hunt of it."""
    default = ranges_to_dict(ScenarioRanges())
    teams = ranges_to_dict(replace(ScenarioRanges(), n_defenders=TEAMS))
    labels = [ControllerSpec.parse(s).label for s in STRATEGIES]
    return {
        FILES[0]: ({"strategies": labels, "attackers": list(BEHAVIOURS), "hunts": hunts, "seed": seed,
                    "ranges": default},
                   [Hunt(s, seed, i, default, attacker=a) for i in range(hunts) for s in STRATEGIES
                    for a in BEHAVIOURS]),
        FILES[1]: ({"strategies": labels, "attackers": [TEAM_ATTACKER], "hunts": team_hunts, "seed": seed,
                    "ranges": teams},
                   [Hunt(s, seed, i, teams, attacker=TEAM_ATTACKER) for i in range(team_hunts) for s in STRATEGIES]),
    }


def run(folder: Path, hunts: int, team_hunts: int, seed: int, workers: int | None = None) -> str | None:
    """Both sweeps into their files on ``workers`` processes (None: one a core); None when all finished, else why
    it stopped."""
    for name, (arguments, hunts_of) in sweeps(hunts, team_hunts, seed).items():
        stopped = run_file(folder / name, arguments, hunts_of, workers)
        if stopped:
            return stopped
    return None


def _cell(s: dict, kind: str) -> str:
    key = "success_rate" if kind == "all" else f"success_rate_{kind}"
    total = {"all": s["hunts"] - s["uncapturable_by_definition"], "comfortable": s["comfortable"],
             "reachable": s["hunts"] - s["unreachable"] - s["uncapturable_by_definition"]}[kind]
    rate, (lo, hi) = s[key], s[f"{key}_ci95"]
    won = round(rate * total) if rate is not None else 0
    return f"{won} / {total}" + ("" if rate is None else f" ({100 * lo:.0f}–{100 * hi:.0f} %)")


def paired_cell(rows: list[dict], attacker: str, kind: str) -> str:
    """The distributed stage's captures minus the centralised one's on the same hunts against ``attacker`` (those
    :func:`_cell` counts for ``kind``: capturable by definition, or comfortable), with Newcombe's 95 % interval
    (:mod:`mpc_hunt.sweep.paired`)."""
    column = "comfortable" if kind == "comfortable" else "capturable_by_definition"
    return paired.cell(paired.summary(paired.paired_counts(
        rows, DISTRIBUTED, CENTRAL, lambda r: r["attacker"] == attacker and bool(r[column]))))


def headline(attackers: list[dict], teams: list[dict], rows: list[dict]) -> list[str]:
    lines = []
    for kind in ("all", "comfortable"):
        by = {(s["strategy"], s["attacker"]): s for s in attackers}
        lines += [f"Captured / {'' if kind == 'all' else 'comfortable '}hunts (95 % interval), exact belief; "
                  "*paired*: the distributed stage's captures minus the centralised one's on the same hunts, in "
                  "points, with the 95 % interval (Newcombe's for paired proportions) and the hunts paired:", "",
                  *markdown.table(["attacker", f"`{CENTRAL}`", f"`{DISTRIBUTED}`", "paired"], "lrrl",
                                  ([a, _cell(by[(CENTRAL, a)], kind), _cell(by[(DISTRIBUTED, a)], kind),
                                    paired_cell(rows, a, kind)] for a in BEHAVIOURS
                                   if (CENTRAL, a) in by and (DISTRIBUTED, a) in by)), ""]
    lines += ["Safety over every hunt of both sweeps (obstacle collisions, defender contacts, arena exits; the "
              "least obstacle clearance and defender separation):", ""]
    safety = []
    for sweep, summaries in (("attackers", attackers), ("teams", teams)):
        for strategy in STRATEGIES:
            mine = [s for s in summaries if s["strategy"] == strategy]
            clear = [s["min_obstacle_clearance_m"] for s in mine if s["min_obstacle_clearance_m"] is not None]
            apart = [s["min_defender_separation_m"] for s in mine if s["min_defender_separation_m"] is not None]
            safety.append([sweep, f"`{strategy}`", sum(s["collisions"] for s in mine),
                           sum(s["failures"].get("outside_arena", 0) for s in mine),
                           f"{min(clear, default=float('nan')):.3f}", f"{min(apart, default=float('nan')):.3f}"])
    lines += markdown.table(["sweep", "strategy", "collisions and contacts", "arena exits", "least clearance (m)",
                             "least separation (m)"], "llrrrr", safety)
    lines += ["", f"Teams of {TEAMS[0]} to {TEAMS[1]} defenders ({TEAM_ATTACKER} attacker): the solve times per "
              "control step (the distributed stage's: every robot's QP one after another here):", ""]
    lines += markdown.table(
        ["strategy", "captured / hunts", "median of the hunts' median solve (ms)", "largest solve (ms)",
         "solves over the time step"], "lrrrr",
        ([f"`{s['strategy']}`", _cell(s, "all"), f"{1e3 * (s['solve_time_p50_median_s'] or 0):.2f}",
          f"{1e3 * (s['solve_time_max_s'] or 0):.1f}",
          "–" if s["over_time_step_share"] is None else f"{100 * s['over_time_step_share']:.2f} %"] for s in teams))
    return lines + [""]


def last_run(folder: Path) -> list[str]:
    """The section setting this run beside the last one kept, file by file (:mod:`studies.previous_rows`; none
    kept: no section): per file the hunts both ran; per attacker the distributed stage's captures minus the
    centralised one's, paired, then and now."""
    lines = []
    for name in FILES:
        previous = read(folder / name)
        if previous is None:
            continue
        rows = stored_rows(folder / name)
        lines += [f"`{name}`: the last run's {len(previous)} hunts (`{kept_path(folder / name).name}`, kept by "
                  f"`{COMMAND} --keep-previous` before this run replaced the file), those this run ran too:", "",
                  *again(rows, previous)]
        if name == FILES[0]:
            lines += [f"Per attacker, `{DISTRIBUTED}`'s captures minus `{CENTRAL}`'s on the same hunts (all of them), "
                      "in points with the 95 % interval (Newcombe's) and the hunts paired, in the last run and now:",
                      "", *against_last_run(rows, previous, [(DISTRIBUTED, CENTRAL)], BEHAVIOURS,
                                            lambda attacker: lambda r: r["attacker"] == attacker)]
    return ["## The last run's hunts, again", "", WHY, "", *lines] if lines else []


def report(attackers: list[dict], teams: list[dict], machine: dict, arguments: dict, rows: list[dict],
           team_rows: list[dict], last: list[str] | None = None) -> str:
    """The study's README: ``rows``, the attackers file's, pair the two stages hunt by hunt; with ``team_rows``, the
    teams file's, they give what a hunt costs."""
    return "\n".join([
        "# The distributed capture stage on random hunts", "",
        f"Regenerate with `{COMMAND} --hunts {arguments['attackers.db']['hunts']} --team-hunts "
        f"{arguments['teams.db']['hunts']}`. The first {arguments['attackers.db']['hunts']} hunts of the sweep with "
        f"seed {arguments['attackers.db']['seed']} (default ranges, docs/robustness.md), each run by the "
        f"enclose controller (`{CENTRAL}`) and by the same controller with its capture stage distributed "
        f"(`{DISTRIBUTED}`: one QP per robot, one Jacobi round a step, docs/formulations.md) against every attacker "
        f"behaviour, exact belief; and the first {arguments['teams.db']['hunts']} hunts of the same seed with "
        f"{TEAMS[0]} to {TEAMS[1]} defenders. One row per hunt in `attackers.db` and `teams.db` "
        "(`mpc-hunt sweep-report studies/team_sweep/attackers.db` recomputes a table).", "",
        *headline(attackers, teams, rows), *(last or []), "## What a hunt costs", "", "Attackers:", "",
        *costs(rows, "`attackers.db`"), "Teams:", "", *costs(team_rows, "`teams.db`"),
        "## Every summary", "", "Attackers:", "", table(attackers),
        "", "Teams:", "", table(teams), "", "## Machine", "", *machine_lines(machine), ""])


def write(folder: Path, machine: dict, hunts: int, team_hunts: int, seed: int) -> None:
    plan = sweeps(hunts, team_hunts, seed)
    summaries = {name: summarise(stored_rows(folder / name)) for name in plan}
    arguments = {name: args for name, (args, _) in plan.items()}
    (folder / "summary.json").write_text(json.dumps({"machine": machine, "arguments": arguments,
                                                     "summaries": summaries}, indent=1) + "\n", encoding="utf-8")
    (folder / "README.md").write_text(report(summaries["attackers.db"], summaries["teams.db"], machine, arguments,
                                             stored_rows(folder / FILES[0]), stored_rows(folder / FILES[1]),
                                             last_run(folder)), encoding="utf-8")


def check(folder: Path) -> list[str]:
    committed = read_json_file(folder / "summary.json", f"rerun {COMMAND}")
    a, t = committed["arguments"]["attackers.db"], committed["arguments"]["teams.db"]
    plan = sweeps(a["hunts"], t["hunts"], a["seed"])
    errors = []
    for name, (arguments, hunts_of) in plan.items():
        if committed["arguments"][name] != json.loads(json.dumps(arguments)):
            errors.append(f"summary.json: the strategies, attackers or ranges of {name} are not the study's")
            continue
        rows = stored_rows(folder / name)
        if json.loads(json.dumps(summarise(rows))) != committed["summaries"][name]:
            errors.append(f"summary.json: not the summary of {name}")
        left = missing(hunts_of, keys(rows))
        if left:
            errors.append(f"{name}: {len(left)} hunts of the study are missing (resume it)")
    if (folder / "README.md").read_text(encoding="utf-8") != report(
            committed["summaries"]["attackers.db"], committed["summaries"]["teams.db"], committed["machine"],
            committed["arguments"], stored_rows(folder / FILES[0]), stored_rows(folder / FILES[1]), last_run(folder)):
        errors.append("README.md: not what summary.json renders")
    if errors:
        return errors
    return still_captured(quickest_captures(stored_rows(folder / "attackers.db"), DISTRIBUTED), a["seed"],
                          a["ranges"], "attackers.db")


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    add_study_options(parser, HUNTS, "hunts per attacker", SEED, OUT)
    parser.add_argument("--team-hunts", type=count(MAX_HUNTS), default=TEAM_HUNTS,
                        help=f"hunts with {TEAMS[0]}–{TEAMS[1]} defenders (default {TEAM_HUNTS})")
    args = parser.parse_args(argv)
    if args.keep_previous:
        return keep_previous([args.output / name for name in FILES])
    if args.check:
        with stop_at_once("team sweep study"):
            return check_result(check(args.output), "studies/team_sweep", COMMAND)
    return measured_run(args.output,
                        lambda: stop_status(run(args.output, args.hunts, args.team_hunts, args.seed, args.workers),
                                            "team_sweep.py", args.output),
                        lambda machine: write(args.output, machine, args.hunts, args.team_hunts, args.seed),
                        args.output / "README.md")


if __name__ == "__main__":
    sys.exit(run_study(main))

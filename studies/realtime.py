"""Every formulation × backend in its own receding-horizon loop, under a 50 Hz budget: which pair is fit to embed.

Each installed pair drives the capture stage of the paper's strategy (prediction on) through hunts, at N = 1, 5
and 10, from the same starts: the two paper scenarios and the first ``RANDOM_HUNTS`` random ones (drawn as the
sweep draws hunts 0, 1, … of ``RANDOM_SEED``) that reach the capture stage, each from where the paper's own
strategy first reaches it, for at most ``WINDOW`` seconds, each pair meeting the states its own plans lead to
(:mod:`mpc_hunt.bench.own_loop`, what ``mpc-hunt compare --mode own-loop`` runs). Every step is handed the
robots' budget, ``BUDGET`` s (50 Hz) as its time limit (the solves of a step sharing it), and every step is
counted against it and against the time step T; a hunt whose capture stage has failed ``ABANDON_AFTER`` s in a row
is stopped, *abandoned*. A pair is
*fit to embed* at a horizon when at most ``MISSES`` of its steps took longer than the budget (its p99
within it), no run of failed solves was longer than ``STREAK`` steps and no usable plan broke a hard constraint
beyond the tolerance (captures are the paper's controller's, reported beside it).
Pairs take turns on each hunt. It writes ``studies/realtime/`` (README.md, results.json with the machine's
description) and the own-loop table of ``docs/benchmarks.md``; each finished hunt goes to ``hunts.jsonl`` as it
ends, so a stopped run resumes where it stopped (``--fresh`` starts over). 28 minutes on two cores (measured).

    python studies/realtime.py [--workers 2]     # run it (or resume) and rewrite studies/realtime/
    python studies/realtime.py --check           # the committed pairs, horizons, hunts and table are the code's
"""

from __future__ import annotations

import itertools
import json
import sys
from functools import cache
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

from mpc_hunt import builtin_scenario

from mpc_hunt.arguments import CommandParser, count
from mpc_hunt.bench.machine import describe_machine, load_average, machine_lines
from mpc_hunt.bench.own_loop import (ABANDON_AFTER, WINDOW, OwnLoopRun, capture_stage_hunts, hunt_summary,
                                     markdown_table, rows_of, run_tasks)
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.markdown import Column
from mpc_hunt.interrupt import stop_keeping
from mpc_hunt.solving import registry
from mpc_hunt.solving.accuracy import VIOLATION_TOLERANCE
from mpc_hunt.sweep.random_scenario import sweep_scenario

from studies.docs_block import read_block, write_block
from studies.study_check import check_result, read_json_file, run_study

OUT = Path(__file__).resolve().parent / "realtime"
PROGRESS = OUT / "hunts.jsonl"
PAPER_SCENARIOS = ("paper-open", "paper-obstacles")
RANDOM_SEED, RANDOM_HUNTS = 1, 10
HORIZONS = [1, 5, 10]
BUDGET = 0.02          # s: the robots' 50 Hz, as each solve's time limit and the step's deadline
STREAK = 5             # the longest run of failed solves a pair fit to embed may have (0.5 s on its fallback)
MISSES = 0.01          # the share of its steps a pair fit to embed may take past the budget (its p99 within it)
TOLERANCE = VIOLATION_TOLERANCE["default"]
COMMAND = "python studies/realtime.py"
MAX_WORKERS = 2


@cache
def scenarios() -> list:
    """The hunts, each from its capture stage's start for at most WINDOW seconds (mpc_hunt/bench/own_loop.py)."""
    return capture_stage_hunts([builtin_scenario(name) for name in PAPER_SCENARIOS],
                               (sweep_scenario(RANDOM_SEED, i) for i in itertools.count()), RANDOM_HUNTS, WINDOW)


def pairs() -> list[tuple[str, str]]:
    """Every installed pair of the paper's objective."""
    return registry.pairs(objective="paper")


def tasks() -> list:
    """Every pair × horizon through every hunt, the pairs taking turns on each hunt (mpc_hunt/bench/own_loop.py)."""
    return OwnLoopRun(scenarios(), pairs(), HORIZONS, time_limit=BUDGET, deadline=BUDGET,
                      abandon_after=ABANDON_AFTER).tasks()


def key(horizon: int, scenario: str, pair: tuple[str, str]) -> str:
    return f"{pair[0]}:{pair[1]} N={horizon} {scenario}"


def task_key(task) -> str:
    return key(task.horizon, task.scenario.name, (task.formulation, task.backend))


SUMMARY_KEYS = {"formulation", "backend", "horizon", "scenario", "past_limit_on_cpu", "past_limit_stolen"}   # of a kept hunt


def finished() -> dict[str, dict]:
    if not PROGRESS.exists():
        return {}
    done = {}
    for line in PROGRESS.read_text(encoding="utf-8").splitlines():
        try:
            h = json.loads(line)
        except json.JSONDecodeError:      # a line cut short by a stop: that hunt runs again
            continue
        if not isinstance(h, dict) or not SUMMARY_KEYS <= h.keys():   # another file's, or an older version's
            continue
        done[key(h["horizon"], h["scenario"], (h["formulation"], h["backend"]))] = h
    return done


def run(workers: int) -> list[dict]:
    OUT.mkdir(parents=True, exist_ok=True)
    wanted = {task_key(t) for t in tasks()}
    done = {name: h for name, h in finished().items() if name in wanted}   # the study's own hunts only
    todo = [t for t in tasks() if task_key(t) not in done]
    print(f"{len(done)} hunts kept, {len(todo)} to run", file=sys.stderr, flush=True)
    with open(PROGRESS, "a", encoding="utf-8") as out:
        for hunt in run_tasks(todo, workers):
            summary = hunt_summary(hunt)
            out.write(json.dumps(summary) + "\n")
            out.flush()
            name = key(summary["horizon"], summary["scenario"], (summary["formulation"], summary["backend"]))
            done[name] = summary
            print(f"{len(done)}/{len(wanted)} {name}: captured {summary['captured']}, {summary['wall_s']:.1f} s",
                  file=sys.stderr, flush=True)
    return list(done.values())


def fit(row: dict) -> bool:
    """Fit to embed: at most ``MISSES`` of the steps past the budget (the p99 within it: this machine is shared,
    and a step here and there is held up by the operating system, not the solver), no failure streak over
    ``STREAK``, no usable plan beyond the tolerance (captures are the controller's: reported beside, against the
    other pairs')."""
    return (row["deadline_misses"] <= MISSES * row["solves"] and row["longest_failure_streak"] <= STREAK
            and row["violating_plans"] == 0)


def table(rows: list[dict]) -> list[str]:
    return markdown_table(rows, Column("fit to embed", lambda r: "yes" if fit(r) else "no", "l"))


def settings() -> dict:
    return {"scenarios": [s.name for s in scenarios()], "window_s": WINDOW, "pairs": [f"{f}:{b}" for f, b in pairs()],
            "horizons": HORIZONS, "budget_s": BUDGET, "abandon_after_s": ABANDON_AFTER, "streak": STREAK, "misses": MISSES, "tolerance_m": TOLERANCE}


def fit_line(rows: list[dict]) -> str:
    fits = [f"{r['formulation']}/{r['backend']} N = {r['horizon']}" for r in rows if fit(r)]
    return "Fit to embed: " + (", ".join(fits) if fits else "none") + "."


def headline(results: dict) -> str:
    m = results["machine"]
    return "\n".join(table(results["rows"])) + (
        f"\n\n{fit_line(results['rows'])}\n\n{overrun_line(results['overruns'])}\n\n"
        f"Machine: {m['cpu']}, {m['cores']} cores, Python {m['python']}; load average "
        f"{m['load_average'][0]} at the start, {m['load_average_end'][0]} at the end.\n")


OVERRUN = 0.005       # s: a step past the budget by more than this is reported by name (one IPOPT iteration at N = 10
                      # is about 0.7 ms, a loaded core's scheduling slice several ms)


def overruns(summaries: list[dict]) -> dict:
    """How far steps went past the budget: how many passed it, how many by more than ``OVERRUN``, the longest."""
    steps = [(t, h) for h in summaries for t in h["solve_times_s"]]
    past = [(t, h) for t, h in steps if t > BUDGET]
    worst_t, worst = max(past, key=lambda p: p[0]) if past else (None, None)
    beyond = [h for h in summaries if h["past_limit_and_overhead"]]
    farthest = max(summaries, key=lambda h: h["largest_overrun_s"] or -1.0, default=None)
    return {"steps": len(steps), "past_budget": len(past), "past_by_overrun": sum(t > BUDGET + OVERRUN for t, _ in past),
            "longest_s": worst_t, "longest_pair": _named(worst),
            "past_limit_and_overhead": sum(h["past_limit_and_overhead"] for h in beyond),
            "pairs_past_limit_and_overhead": sorted({f"{h['formulation']}/{h['backend']} N = {h['horizon']}"
                                                     for h in beyond}),
            "largest_overrun_s": None if farthest is None else farthest["largest_overrun_s"],
            "largest_overrun_pair": _named(farthest),
            "past_limit_on_cpu": sum(h["past_limit_on_cpu"] for h in summaries),
            "largest_overrun_on_cpu_s": max((h["largest_overrun_on_cpu_s"] for h in summaries), default=None),
            "past_limit_stolen": sum(h["past_limit_stolen"] for h in summaries),
            "pairs_past_limit_on_cpu": sorted({f"{h['formulation']}/{h['backend']} N = {h['horizon']}"
                                               for h in summaries if h["past_limit_on_cpu"]}),
            "hunts_core_s": sum(h["wall_s"] for h in summaries)}


def _named(hunt: dict | None) -> str | None:
    if hunt is None:
        return None
    return f"{hunt['formulation']}/{hunt['backend']} N = {hunt['horizon']} ({hunt['scenario']})"


def overrun_line(o: dict) -> str:
    if not o["past_budget"]:
        head = f"No step of the {o['steps']} went past the {BUDGET:g} s budget."
    else:
        head = (f"Of the {o['steps']} steps, {o['past_budget']} went past the {BUDGET:g} s budget, "
                f"{o['past_by_overrun']} by more than {OVERRUN * 1e3:g} ms; the longest, "
                f"{o['longest_s'] * 1e3:.1f} ms, was {o['longest_pair']}'s.")
    if not o["past_limit_and_overhead"]:
        bound = ("No step took longer than the time limit plus its own overhead (our work around the solver: "
                 "building its data, reading its answer, the certificate).")
    else:
        bound = (f"{o['past_limit_and_overhead']} steps took longer than the time limit plus their own overhead (our "
                 f"work around the solver: building its data, reading its answer, the certificate), the farthest by "
                 f"{o['largest_overrun_s'] * 1e3:.1f} ms ({o['largest_overrun_pair']}); pairs with such steps: "
                 f"{', '.join(o['pairs_past_limit_and_overhead'])}.")
    ran = ("Counting only the time the process ran (mpc_hunt/solving/step_timing.py: neither off the CPU nor taken by "
           f"the hypervisor, which {o['past_limit_stolen']} of the steps past it saw)")
    if not o["past_limit_on_cpu"]:
        cpu = (f"{ran}, no step did: the farthest "
               f"came within {-o['largest_overrun_on_cpu_s'] * 1e3:.1f} ms of it; every step past it was the machine's "
               f"(its core given to another process), not the step's code.")
    else:
        cpu = (f"{ran}, {o['past_limit_on_cpu']} "
               f"did, the farthest by {o['largest_overrun_on_cpu_s'] * 1e3:.1f} ms; pairs with such steps: "
               f"{', '.join(o['pairs_past_limit_on_cpu'])}.")
    return f"{head} {bound} {cpu} The hunts took {o['hunts_core_s'] / 60:.0f} core-minutes."


def write(summaries: list[dict], machine: dict) -> None:
    rows = rows_of(summaries, pairs(), HORIZONS, TOLERANCE, BUDGET)
    hunts = [{k: v for k, v in h.items() if k not in ("solve_times_s", "iterations")} for h in summaries]
    results = {"machine": machine, "settings": settings(), "rows": rows, "hunts": hunts, "overruns": overruns(summaries)}
    (OUT / "results.json").write_text(json.dumps(results) + "\n", encoding="utf-8")
    (OUT / "README.md").write_text(readme(results), encoding="utf-8")
    write_block("realtime", headline(results))


def readme(results: dict) -> str:
    """studies/realtime/README.md, from the results."""
    rows, machine = results["rows"], results["machine"]
    text = ["# Every pair in its own loop, under a 50 Hz budget", "",
            f"Regenerate with `{COMMAND}` (it resumes from `hunts.jsonl`, kept out of the repository). "
            f"{len(results['hunts'])} hunts: each pair drives the paper's capture stage (prediction on) through "
            f"{len(scenarios())} hunts ({', '.join(PAPER_SCENARIOS)} and the first {RANDOM_HUNTS} random hunts of the "
            f"sweep with seed {RANDOM_SEED} that reach the capture stage, each from where the paper's strategy first "
            f"reaches it, for at most {WINDOW:g} s) at N = {', '.join(map(str, HORIZONS))}, every step handed a "
            f"{BUDGET:g} s time limit (its solves sharing it), every step counted against it and the time step T, "
            f"a hunt whose capture stage failed {ABANDON_AFTER:g} s in a row stopped (abandoned). Times are the "
            f"capture-stage solves', "
            f"as the controller waits for them (the evaluator's scoring apart; a new structure's one-off set-up, "
            f"which a robot does before its loop, counted apart). `> limit`: steps that took longer than the time "
            f"limit plus their own overhead (our work around the solver), on the wall clock; `> limit on CPU`: the "
            f"same counting only the time the process ran, neither off the CPU nor taken by the hypervisor "
            f"(mpc_hunt/solving/step_timing.py). `violating`: "
            f"usable plans the loop refused, a hard constraint (Eqs. 13, 15, separation, attacker distance) broken "
            f"beyond {TOLERANCE:g} m; `max hard viol`: the largest such violation of an applied plan; the residuals "
            f"are the certificates' of the usable solves, of the QP each solver was handed "
            f"(mpc_hunt/capture/certificate.py). Fit to embed: at most {MISSES:.0%} of the steps past {BUDGET:g} s "
            f"(the p99 within it), no run of more than {STREAK} failed solves, no violating plan (captures are the "
            f"paper's controller's, reported beside).", "",
            "## Machine", "", *machine_lines(machine), "", "## Results", "", *table(rows), "",
            fit_line(rows), "", overrun_line(results["overruns"]), ""]
    return "\n".join(text)


def check() -> list[str]:
    path = OUT / "results.json"
    if not path.exists():
        return [f"{path}: missing; run {COMMAND}"]
    committed = read_json_file(path, f"rerun {COMMAND}")
    errors = [f"settings.{k}: committed {committed['settings'].get(k)!r}, the code runs {v!r}"
              for k, v in settings().items() if committed["settings"].get(k) != v]
    if len(committed["hunts"]) != len(tasks()):
        errors.append(f"hunts: {len(committed['hunts'])} committed, the study runs {len(tasks())}")
    if read_block("realtime") != headline(committed):
        errors.append("docs/benchmarks.md: its own-loop table is not the committed results'")
    if (OUT / "README.md").read_text(encoding="utf-8") != readme(committed):
        errors.append("studies/realtime/README.md: not what results.json renders")
    return errors


def run_machine(now: dict) -> dict:
    """The machine the kept hunts ran on: the committed results' description when they are the same run's (same
    settings), so that rewriting the results after a change to how they are shown keeps it; else ``now``."""
    path = OUT / "results.json"
    try:
        committed = read_json_file(path, f"rerun {COMMAND}")
    except (OSError, ValueError):
        return now
    if not isinstance(committed, dict) or committed.get("settings") != settings() or "machine" not in committed:
        return now
    return committed["machine"]


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true", help="check the committed settings and table against the code")
    parser.add_argument("--workers", type=count(MAX_WORKERS), default=1,
                        help=f"hunts at once (1 to {MAX_WORKERS}; default 1, leaving a core free)")
    mode.add_argument("--fresh", action="store_true", help="forget the hunts kept in hunts.jsonl and start over")
    args = parser.parse_args(argv)
    if args.check:
        return check_result(check(), "studies/realtime", COMMAND)
    if args.fresh and PROGRESS.exists():
        PROGRESS.unlink()
    machine, kept = describe_machine(), len(finished())
    with stop_keeping("realtime study", lambda: None):   # Ctrl-C: at once; each finished hunt is in hunts.jsonl
        summaries = run(args.workers)
    machine["load_average_end"] = load_average()
    if kept >= len(tasks()):                      # no hunt ran: rewritten with the machine of the run that ran them
        machine = run_machine(machine)
    if len(summaries) != len(tasks()):
        raise MpcHuntError(f"{len(summaries)} of {len(tasks())} hunts finished; rerun {COMMAND} to finish them")
    write(summaries, machine)
    print(f"wrote {OUT / 'README.md'} and the own-loop table of docs/benchmarks.md")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

"""Attackers the defenders do not know: every strategy against every attacker behaviour, and belief errors.

Runs the sweep machinery (``mpc_hunt.sweep.runner``) on the first ``--hunts`` reachable draws of the sweep
``--seed`` (unreachable hunts are lost by any controller, whatever the attacker: docs/robustness.md): every
strategy of ``STRATEGIES`` against every behaviour of ``mpc_hunt.world.behaviours.BEHAVIOURS`` with the exact
belief; on the first ``BELIEF_HUNTS`` of them, the enclose and contain controllers too (``FIRST``), and contain
and the Voronoi baseline with each belief error of ``BELIEFS`` (the trap controller reads nothing of the belief
but the attacker's top speed, which no error changes).
Rows go into ``studies/attackers/sweep.db`` (resumed if it exists, so an interrupted run continues); then it
writes ``studies/attackers/`` (README.md, summary.json with the machine, the figures).

    python studies/attackers.py                   # run (or resume), then write the report
    python studies/attackers.py --hunts 200 --seed 3 --output /tmp/a   # other hunts, into another folder
    python studies/attackers.py --check           # the committed report is the committed file's summary, the
                                                  # recommended controller is the one to recommend (the solving
                                                  # controller that captures most, or the quickest of those its
                                                  # interval cannot tell from it), and its quickest capture per
                                                  # attacker still captures
    python studies/attackers.py --keep-previous   # before a rerun at another size: the rows of sweep.db kept in
                                                  # sweep.previous.json, which the rerun's report sets beside its
                                                  # own (studies/previous_rows.py)
"""

from __future__ import annotations

import json
import statistics
import sys
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser
from mpc_hunt.bench.machine import machine_lines
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.control.controllers import SOLVING
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.plots.capture_region import plot_capture_regions
from mpc_hunt.plots.sweep import write_plots
from mpc_hunt.sweep.random_scenario import ScenarioRanges, ranges_to_dict, sweep_scenario
from mpc_hunt.sweep.reachability import reachable
from mpc_hunt.sweep.runner import Hunt
from mpc_hunt.sweep.store import stored_rows
from mpc_hunt.sweep.paired import PairedCounts, cell, newcombe, paired_counts, summary, time_cell, time_summary
from mpc_hunt.sweep.summary import summarise, table
from mpc_hunt.sweep.typical import rerun, typical_rows
from mpc_hunt.world.behaviours import BEHAVIOURS

from studies.previous_rows import WHY, again, against_last_run, read
from studies.study_check import check_result, read_json_file, run_study
from studies.sweep_study import (add_study_options, costs, keep_previous, keys, measured_run, missing,
                                 quickest_captures, run_file, still_captured, stop_status)

EXACT = "exact"
OUT = Path(__file__).resolve().parent / "attackers"
COMMAND = "python studies/attackers.py"
HUNTS, SEED = 300, 1      # 300 hunts a cell (199 comfortable on seed 1): 95 % intervals of about ±7 points, not ±13
BELIEF_HUNTS = 15         # FIRST and the belief errors: on the first this many hunts
DRAWS_PER_HUNT = 20       # the draws searched for reachable ones: at most this many per hunt asked for
FOCUS = ControllerSpec().label       # the recommended controller, measured against the Voronoi baseline
BASELINE = "voronoi"
LEARNED_TEAM, LEARNED_ATTACKER = "ppo", "ppo"     # the PPO team (a strategy) and the PPO attacker (a behaviour)
STRATEGIES = tuple(dict.fromkeys((FOCUS, "trap:rti:hpipm:10", BASELINE, "apf", "paper:rti:hpipm:5", LEARNED_TEAM)))
# On the first BELIEF_HUNTS only: enclose (given the paper's attacker model, the slowest per hunt) and contain
# (the capture problem tracking the baseline's places), with the exact belief.
FIRST = ("enclose:rti:hpipm:10", "contain:rti:hpipm:10")
MARGIN_POINTS = 8         # how much more of the comfortable hunts, averaged over the attackers, the focus should take
APF_BAR, TWO_BAR = 0.9, 0.5   # its share of the comfortable hunts against apf; of the reachable two-robot hunts
BELIEFS = ("perception_radius=1.3x", "eta=3x", "intent_heading=60")   # errors run by the BELIEF_STRATEGIES
# The controllers that read the believed attacker beyond its top speed: contain (its floor R_agg + R_hunt / 2 while
# the attacker is not enclosed) and the Voronoi baseline (the same floor and its intercepts). Trap reads only the top
# speed, which no belief error changes, so its commands are the same under every error.
BELIEF_STRATEGIES = ("contain:rti:hpipm:10", "voronoi")


def hunt_indices(hunts: int, seed: int) -> list[int]:
    """The first ``hunts`` reachable draws of the sweep ``seed`` (default ranges), searched among the first
    ``DRAWS_PER_HUNT`` × ``hunts`` draws (fewer if that many hold fewer)."""
    found = []
    for i in range(DRAWS_PER_HUNT * hunts):
        if len(found) == hunts:
            break
        if reachable(sweep_scenario(seed, i, ScenarioRanges())):
            found.append(i)
    return found


def todo(indices: list[int], seed: int) -> list[Hunt]:
    """Every (strategy, attacker, belief, hunt) of the study: every strategy with the exact belief on every hunt;
    ``FIRST`` with the exact belief, and the belief errors, on the first ``BELIEF_HUNTS``."""
    ranges = ranges_to_dict(ScenarioRanges())
    every = [(s, a, EXACT) for s in STRATEGIES for a in BEHAVIOURS]
    first = [(s, a, EXACT) for s in FIRST for a in BEHAVIOURS] + \
            [(s, a, b) for s in BELIEF_STRATEGIES for a in BEHAVIOURS for b in BELIEFS]
    return [Hunt(s, seed, i, ranges, attacker=a, belief=b) for n, i in enumerate(indices)
            for s, a, b in every + (first if n < BELIEF_HUNTS else [])]


def arguments(hunts: int, seed: int) -> dict:
    return {"strategies": [ControllerSpec.parse(s).label for s in STRATEGIES + FIRST],
            "attackers": list(BEHAVIOURS), "beliefs": [EXACT, *BELIEFS], "hunts": hunts, "seed": seed,
            "ranges": ranges_to_dict(ScenarioRanges())}


def run(db: Path, hunts: int, seed: int, indices: list[int] | None = None, workers: int | None = None) -> str | None:
    """The study's hunts (on the reachable draws ``indices``, found if not given) into ``db`` on ``workers``
    processes (None: one a core); None when all finished, else why it stopped."""
    indices = hunt_indices(hunts, seed) if indices is None else indices
    return run_file(db, arguments(hunts, seed), todo(indices, seed), workers)


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
                  *markdown.table(["attacker", *(f"`{s}`" for s in strategies)], "l" + "r" * len(strategies),
                                  ([a, *(cell(by[(s, a, EXACT)], kind) if (s, a, EXACT) in by else "–"
                                         for s in strategies)] for a in BEHAVIOURS)), ""]
    beliefs = [b for b in dict.fromkeys(s["belief"] for s in summaries) if b != EXACT]
    for strategy in BELIEF_STRATEGIES:
        lines += [f"`{strategy}`, captured / comfortable hunts per belief error:", "",
                  *markdown.table(["attacker", *beliefs], "l" + "r" * len(beliefs),
                                  ([a, *(cell(by[(strategy, a, b)], "comfortable") if (strategy, a, b) in by
                                         else "–" for b in beliefs)] for a in BEHAVIOURS)), ""]
    return lines


def mean_comfortable(summaries: list[dict]) -> dict[str, float]:
    """Each strategy's share of the comfortable hunts it captures, averaged over the attackers (exact belief; the
    strategies run on every hunt, ``STRATEGIES``)."""
    rates: dict[str, list[float]] = {}
    for s in summaries:
        if s["belief"] == EXACT and s["strategy"] in STRATEGIES and s["success_rate_comfortable"] is not None:
            rates.setdefault(s["strategy"], []).append(s["success_rate_comfortable"])
    return {k: sum(v) / len(v) for k, v in rates.items() if len(v) == len(BEHAVIOURS)}


def solving_shares(rows: list[dict]) -> tuple[dict[str, float], int]:
    """The solving controllers' (those with a capture stage, the candidates for the recommended one) shares of the
    comfortable hunts captured, averaged over the attackers, on the hunts every one of them ran (exact belief);
    and how many hunts that is."""
    exact = [r for r in rows if r["belief"] == EXACT and r["comfortable"]
             and ControllerSpec.parse(r["strategy"]).controller in SOLVING]
    labels = list(dict.fromkeys(r["strategy"] for r in exact))
    common = set.intersection(*({(r["attacker"], r["index"]) for r in exact if r["strategy"] == k} for k in labels)) \
        if labels else set()
    shares = {}
    for label in labels:
        won = {(r["attacker"], r["index"]) for r in exact if r["strategy"] == label and r["outcome"] == "captured"}
        per = [len(won & {h for h in common if h[0] == a}) / n for a in BEHAVIOURS
               if (n := sum(h[0] == a for h in common))]
        shares[label] = sum(per) / len(per) if per else 0.0
    return shares, len(common)


def recommended_choice(rows: list[dict]) -> str | None:
    """The solving controller with the largest share of :func:`solving_shares`, or, among those the paired 95 %
    interval cannot tell from it on the hunts every solving controller ran (Newcombe's interval of the
    difference of their paired captures, :mod:`mpc_hunt.sweep.paired`, holding 0), the one with the shortest
    median capture time on the hunts they all capture (exact belief)."""
    shares, _ = solving_shares(rows)
    if not shares:
        return None
    best = max(shares, key=shares.get)
    won = {k: {(r["attacker"], r["index"]): int(r["outcome"] == "captured") for r in rows if r["strategy"] == k
               and r["belief"] == EXACT and r["comfortable"]} for k in shares}
    common = sorted(set.intersection(*(set(w) for w in won.values())))
    tied = [k for k in shares if k == best or
            newcombe(PairedCounts.of((won[best][h], won[k][h]) for h in common))[0] <= 0]
    times = {k: {(r["attacker"], r["index"]): r["capture_time_s"] for r in rows if r["strategy"] == k
                 and r["belief"] == EXACT and r["outcome"] == "captured"} for k in tied}
    both = set.intersection(*(set(t) for t in times.values()))
    return min(tied, key=lambda k: statistics.median(times[k][h] for h in both) if both else 0.0)


def bars(rows: list[dict], summaries: list[dict]) -> list[tuple[str, str, bool]]:
    """(what, measured, met) for each bar the recommended controller is held to against the Voronoi baseline."""
    exact = [r for r in rows if r["belief"] == EXACT]

    def mine(strategy: str, attacker: str | None = None, **where) -> list[dict]:
        return [r for r in exact if r["strategy"] == strategy and (attacker is None or r["attacker"] == attacker)
                and all(r[k] == v for k, v in where.items())]

    def won(rs: list[dict]) -> int:
        return sum(r["outcome"] == "captured" for r in rs)

    out = []
    behind = [a for a in BEHAVIOURS if won(mine(FOCUS, a, comfortable=1)) < won(mine(BASELINE, a, comfortable=1))]
    out.append((f"captures at least as many comfortable hunts as `{BASELINE}` against every attacker",
                "behind against " + ", ".join(behind) if behind else "every attacker", not behind))
    means = mean_comfortable(summaries)
    what = f"at least {MARGIN_POINTS} points more of the comfortable hunts, averaged over the attackers"
    if FOCUS in means and BASELINE in means:
        gain = 100 * (means[FOCUS] - means[BASELINE])
        out.append((what, f"{100 * means[FOCUS]:.1f} % against {100 * means[BASELINE]:.1f} % ({gain:+.1f} points)",
                    gain >= MARGIN_POINTS))
    else:
        out.append((what, "not every attacker has comfortable hunts", False))
    apf = mine(FOCUS, "apf", comfortable=1)
    out.append((f"at least {100 * APF_BAR:.0f} % of the comfortable hunts against `apf`",
                f"{won(apf)} / {len(apf)}", bool(apf) and won(apf) >= APF_BAR * len(apf)))
    for attacker in ("apf", "gap"):
        two = mine(FOCUS, attacker, reachable=1, n_defenders=2)
        out.append((f"at least {100 * TWO_BAR:.0f} % of the reachable two-robot hunts against `{attacker}`",
                    f"{won(two)} / {len(two)}", bool(two) and won(two) >= TWO_BAR * len(two)))
    times = {}
    for strategy in (FOCUS, BASELINE):
        times[strategy] = {(r["attacker"], r["index"]): r["capture_time_s"] for r in mine(strategy)
                           if r["outcome"] == "captured"}
    both = sorted(set(times[FOCUS]) & set(times[BASELINE]))
    if both:
        ours, theirs = (statistics.median(times[k][h] for h in both) for k in (FOCUS, BASELINE))
        out.append((f"a median capture time no longer than `{BASELINE}`'s on the hunts both capture",
                    f"{ours:.1f} s against {theirs:.1f} s ({len(both)} hunts)", ours <= theirs))
    unsafe = [r for r in mine(FOCUS) if r["cause"] in ("obstacle_collision", "defender_contact", "outside_arena")]
    late = sum(r["solves_over_time_step"] or 0 for r in mine(FOCUS))
    out.append(("no obstacle collision, defender contact or robot outside the arena; every solve inside the time "
                "step", f"{len(unsafe)} unsafe hunts, {late} solves over the time step", not unsafe and not late))
    return out


def verdicts(rows: list[dict]) -> list[str]:
    """What the table says of the study's questions, from the rows (exact belief): does the recommended controller
    capture at least as many comfortable hunts as the Voronoi baseline against each attacker (and how fast, on the
    hunts both capture, with the paired difference's interval), and is the minimax attacker at least as hard for
    the baseline as the gap-seeker?"""
    exact = [r for r in rows if r["belief"] == EXACT and r["comfortable"]]

    def won(strategy: str, attacker: str, column: str = "capture_time_s") -> dict:
        return {r["index"]: r[column] for r in exact if r["strategy"] == ControllerSpec.parse(strategy).label
                and r["attacker"] == attacker and r["outcome"] == "captured"}

    body = []
    for attacker in BEHAVIOURS:
        total = len({r["index"] for r in exact if r["attacker"] == attacker})
        mine, theirs = won(FOCUS, attacker), won(BASELINE, attacker)
        both = sorted(set(mine) & set(theirs))
        times = paths = "–"
        if both:
            times = (f"{statistics.median(mine[i] for i in both):.1f} s / "
                     f"{statistics.median(theirs[i] for i in both):.1f} s ({len(both)} hunts)")
            walked = [won(k, attacker, "path_length_m") for k in (FOCUS, BASELINE)]
            paths = " / ".join(f"{statistics.median(w[i] for i in both):.1f} m" for w in walked)
        body.append([attacker, total, len(mine), len(theirs), "yes" if len(mine) >= len(theirs) else "no", times,
                     time_cell(time_summary(rows, FOCUS, BASELINE, comfortable_against(attacker))), paths])
    lines = markdown.table(["attacker", "comfortable", f"`{FOCUS}` captured", f"`{BASELINE}` captured",
                            "at least as many", f"median capture time on the hunts both capture, `{FOCUS}` / "
                            f"`{BASELINE}`", "its paired difference, median (sign-test 95 % interval)",
                            "median path length there (all defenders)"], "lrrrllll", body)
    gap, minimax = len(won(BASELINE, "gap")), len(won(BASELINE, "minimax"))
    verdict = "at least as hard for the Voronoi baseline as" if minimax <= gap else "easier for the Voronoi baseline than"
    lines += ["", f"The minimax attacker is {verdict} the gap-seeker: the baseline captures {minimax} comfortable "
              f"hunts against `minimax`, {gap} against `gap`.", ""]
    return lines


def then_and_now(rows: list[dict], previous: list[dict]) -> list[str]:
    """Per attacker, the recommended controller's captures minus the PPO team's and the Voronoi baseline's, paired,
    on the last run's hunts (``previous``) and on this run's: what the rerun tells apart that the last did not."""
    return [f"Per attacker, `{FOCUS}`'s captures minus the other's on the same comfortable hunts (exact belief), "
            "in points with the 95 % interval (Newcombe's) and the hunts paired, in the last run and now:", "",
            *against_last_run(rows, previous, [(FOCUS, LEARNED_TEAM), (FOCUS, BASELINE)], BEHAVIOURS,
                              comfortable_against)]


def comfortable_against(attacker: str):
    """The rows the study pairs against ``attacker``: its comfortable hunts, exact belief."""
    return lambda r: r["attacker"] == attacker and r["belief"] == EXACT and bool(r["comfortable"])


def league(rows: list[dict]) -> list[str]:
    """The learned agents against the recommended controller: per attacker, the recommended controller's captures
    against the PPO team's and the Voronoi baseline's, paired on the same hunts."""
    lines = [f"Per attacker, comfortable hunts captured (exact belief); the difference is `{FOCUS}`'s minus the "
             "other's on the same hunts, with its 95 % interval (Newcombe's for paired proportions): "
             "an interval holding 0 does not tell the two apart.", ""]
    body = []
    for attacker in BEHAVIOURS:
        counts = []
        for strategy in (FOCUS, LEARNED_TEAM, BASELINE):
            mine = [r for r in rows if r["strategy"] == strategy and r["attacker"] == attacker
                    and r["belief"] == EXACT and r["comfortable"]]
            counts.append(f"{sum(r['outcome'] == 'captured' for r in mine)} / {len(mine)}")
        cells = [cell(summary(paired_counts(rows, FOCUS, other, comfortable_against(attacker))))
                 for other in (LEARNED_TEAM, BASELINE)]
        body.append([attacker, *counts, *cells])
    return lines + markdown.table(["attacker", f"`{FOCUS}`", f"`{LEARNED_TEAM}` team", f"`{BASELINE}`",
                                   f"`{FOCUS}` − `{LEARNED_TEAM}`", f"`{FOCUS}` − `{BASELINE}`"], "lrrrll",
                                  body) + [""]


def learned_figure(rows: list[dict], folder: Path) -> list[Path]:
    """A typical hunt each learned side wins against the recommended controller, rerun and drawn: the PPO
    attacker escaping it, and the PPO team capturing a comfortable hunt it loses (exact belief)."""
    exact = [r for r in rows if r["belief"] == EXACT]
    cases = []
    escaped = typical_rows([r for r in exact if r["attacker"] == LEARNED_ATTACKER], FOCUS).get("lost")
    if escaped is not None:
        scenario, result = rerun(escaped)
        cases.append((result, scenario, f"attacker {LEARNED_ATTACKER} escapes {FOCUS}: {escaped['name']}"))
    lost = {(r["attacker"], r["index"]) for r in exact if r["strategy"] == FOCUS and r["comfortable"]
            and r["outcome"] != "captured"}
    team_wins = [r for r in exact if r["strategy"] == LEARNED_TEAM and r["outcome"] == "captured"
                 and (r["attacker"], r["index"]) in lost]
    if team_wins:
        row = typical_rows(team_wins, LEARNED_TEAM)["captured"]
        scenario, result = rerun(row)
        cases.append((result, scenario, f"the {LEARNED_TEAM} team captures ({row['attacker']}), {FOCUS} does not: "
                                        f"{row['name']}"))
    if not cases:
        return []
    plot_capture_regions(cases, folder / "learned_wins.png")
    return [folder / "learned_wins.png"]


def lost_figure(rows: list[dict], folder: Path) -> list[Path]:
    """A typical lost hunt of the recommended controller per attacker (exact belief), rerun and drawn."""
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


def last_run(rows: list[dict], previous: list[dict] | None) -> list[str]:
    """The section setting this run beside the last one kept (:mod:`studies.previous_rows`; none: no section)."""
    if previous is None:
        return []
    return ["## The last run's hunts, again", "",
            f"The last run's {len(previous)} hunts (`sweep.previous.json`, kept from its `sweep.db` by "
            f"`{COMMAND} --keep-previous` before this run replaced it), those this run ran too set beside its rows. "
            f"{WHY}", "", *again(rows, previous), *then_and_now(rows, previous)]


def report(rows: list[dict], summaries: list[dict], machine: dict, hunts: int, seed: int,
           previous: list[dict] | None = None) -> str:
    indices = sorted({r["index"] for r in rows})
    means = mean_comfortable(summaries)
    ranked = sorted(means, key=means.get, reverse=True)
    shares, common = solving_shares(rows)
    solving = sorted(shares, key=shares.get, reverse=True)
    return "\n".join([
        "# Attackers the defenders do not know", "",
        f"Regenerate with `{COMMAND}`. The first {hunts} reachable hunts of the sweep with seed {seed} (default "
        f"ranges, docs/robustness.md; draws {indices[0]}–{indices[-1]}), each run by every strategy against every "
        "attacker behaviour (docs/model.md, E13) with the exact belief; on the first "
        f"{BELIEF_HUNTS} of them, the enclose controller (E12: given the paper's attacker model, the slowest a hunt) "
        "and the contain controller (E15) too, and contain and the Voronoi baseline with each belief error (E14: "
        "the world's value over the believed one; the heading error drawn per hunt; the trap "
        "controller, E16, reads nothing of the belief but the attacker's top speed, which no error changes). Every "
        "controller is built on the belief, never on the world's behaviour. One row per hunt is in `sweep.db` "
        "(`mpc-hunt sweep-report studies/attackers/sweep.db` recomputes the table).", "",
        "Share of the comfortable hunts captured, averaged over the attackers (exact belief), on every hunt: " +
        ", ".join(f"`{k}` {100 * means[k]:.1f} %" for k in ranked) + ". The solving controllers (those with a "
        f"capture stage) on the {common} comfortable hunts each of them ran: " +
        ", ".join(f"`{k}` {100 * shares[k]:.1f} %" for k in solving) +
        f". The recommended controller (`mpc_hunt/control/recommended.py`) is `{FOCUS}`; `--check` fails unless it "
        "is first among the solving controllers, or not told apart from the first by the 95 % interval (Newcombe's "
        "for paired proportions) of their captures on those hunts and the quickest of those so tied (the shortest "
        "median capture time on the hunts they all capture). How it fares against the Voronoi baseline, which has "
        "no capture stage, is the next section's.", "",
        *headline(summaries),
        f"## `{FOCUS}` against the Voronoi baseline", "",
        *markdown.table(["bar", "measured", ""], "lll", ([what, measured, "met" if met else "missed"]
                                                         for what, measured, met in bars(rows, summaries))),
        "", "Per attacker, comfortable hunts, exact belief:", "", *verdicts(rows),
        "![success by attacker](success_by_attacker.png)", "",
        f"A typical lost hunt of `{FOCUS}` per attacker (`mpc_hunt/sweep/typical.py`), rerun:", "",
        "![typical lost hunts](typical_lost.png)", "",
        "## The learned agents", "",
        f"The `{LEARNED_ATTACKER}` attacker and the `{LEARNED_TEAM}` team are PPO policies (Stable-Baselines3; "
        "`python studies/train_ppo.py`, docs/envs.md), the attacker trained against the recommended controller, "
        "the team against the other attackers; neither trained on these hunts.", "", *league(rows),
        f"A typical hunt each learned side wins against `{FOCUS}`, rerun:", "",
        "![learned sides' wins](learned_wins.png)", "", *last_run(rows, previous), "## What a hunt costs", "",
        *costs(rows),
        "## Every summary", "", table(summaries), "",
        "## Machine", "", *machine_lines(machine), ""])


def write(db: Path, folder: Path, machine: dict, hunts: int, seed: int) -> None:
    rows = stored_rows(db)
    summaries = summarise(rows)
    write_plots(rows, folder)
    lost_figure(rows, folder)
    learned_figure(rows, folder)
    (folder / "summary.json").write_text(json.dumps({"machine": machine, "arguments": arguments(hunts, seed),
                                                     "strategies": summaries}, indent=1) + "\n", encoding="utf-8")
    (folder / "README.md").write_text(report(rows, summaries, machine, hunts, seed, read(folder / "sweep.db")),
                                      encoding="utf-8")


def check(folder: Path) -> list[str]:
    committed = read_json_file(folder / "summary.json", f"rerun {COMMAND}")
    hunts, seed = committed["arguments"]["hunts"], committed["arguments"]["seed"]
    errors = [] if committed["arguments"] == arguments(hunts, seed) else \
        ["summary.json: its strategies, attackers, beliefs or ranges are not the study's"]
    rows = stored_rows(folder / "sweep.db")
    if json.loads(json.dumps(summarise(rows))) != committed["strategies"]:
        errors.append("summary.json: not the summary of sweep.db")
    elif (folder / "README.md").read_text(encoding="utf-8") != report(rows, summarise(rows), committed["machine"],
                                                                       hunts, seed, read(folder / "sweep.db")):
        errors.append("README.md: not the report of sweep.db")
    left = missing(todo(hunt_indices(hunts, seed), seed), keys(rows))
    if left:
        errors.append(f"sweep.db: {len(left)} hunts of the study are missing (resume it)")
    best = recommended_choice(rows)
    if best != FOCUS:
        errors.append(f"mpc_hunt/control/recommended.py: the recommended controller is {FOCUS}, but {best} is the "
                      "solving controller to recommend (the largest share of the comfortable hunts, or the quickest "
                      "of those its interval cannot tell from it)")
    if errors:
        return errors
    return still_captured(quickest_captures(rows, FOCUS, EXACT), seed, committed["arguments"]["ranges"],
                          "sweep.db")


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    add_study_options(parser, HUNTS, "reachable hunts a strategy and attacker", SEED, OUT)
    args = parser.parse_args(argv)
    if args.keep_previous:
        return keep_previous([args.output / "sweep.db"])
    if args.check:
        with stop_at_once("attackers study"):
            return check_result(check(args.output), "studies/attackers", COMMAND)
    try:
        indices = hunt_indices(args.hunts, args.seed)        # cheap: draws only, before any file is written
    except MpcHuntError as exc:
        parser.error(str(exc))
    if not indices:
        parser.error(f"--hunts {args.hunts}: none of the first {DRAWS_PER_HUNT * args.hunts} draws of --seed "
                     f"{args.seed} is reachable by the defenders, so no hunt would run; give another --seed")
    db = args.output / "sweep.db"
    return measured_run(args.output,
                        lambda: stop_status(run(db, args.hunts, args.seed, indices, args.workers), "attackers.py", db),
                        lambda machine: write(db, args.output, machine, args.hunts, args.seed),
                        args.output / "README.md")


if __name__ == "__main__":
    sys.exit(run_study(main))

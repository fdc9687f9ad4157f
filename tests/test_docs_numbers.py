"""Numbers the docs quote from a study are the study's committed numbers (the study's own ``--check`` holds those
to the code)."""

from __future__ import annotations

import functools
import json
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SUMMARY = json.loads((ROOT / "studies" / "attackers" / "summary.json").read_text())
EXACT = [row for row in SUMMARY["strategies"] if row["belief"] == "exact"]
WORDS = ("no", "one", "two", "three", "four", "five", "six", "seven", "eight")     # counts as the docs write them


def _section(text: str, heading: str) -> str:
    start = text.index(heading)
    following = text.find("\n### ", start + len(heading))
    return text[start:following if following >= 0 else len(text)]


def _captured(strategy: str, attacker: str) -> tuple[int, int]:
    """(comfortable hunts captured, comfortable hunts) of a strategy (its name before any ':') and attacker."""
    row, = [r for r in EXACT if r["strategy"].split(":")[0] == strategy and r["attacker"] == attacker]
    return round(row["success_rate_comfortable"] * row["comfortable"]), row["comfortable"]


def _share(strategy: str) -> str:
    """A strategy's share of the comfortable hunts averaged over the attackers, as the docs print it."""
    rates = [r["success_rate_comfortable"] for r in EXACT if r["strategy"].split(":")[0] == strategy]
    return f"{100 * sum(rates) / len(rates):.1f} %"


def test_the_trap_table_of_e16_is_the_attackers_studys_summary():
    e16 = _section((ROOT / "docs" / "model.md").read_text(), "### E16")
    rows = re.findall(r"^\| (\w+) \| (\d+) \| (\d+) \|$", e16, flags=re.M)
    assert {attacker for attacker, _, _ in rows} == set(SUMMARY["arguments"]["attackers"])
    for attacker, trap, voronoi in rows:
        assert (int(trap), int(voronoi)) == (_captured("trap", attacker)[0], _captured("voronoi", attacker)[0])


def test_the_baselines_and_the_defaults_shares_quoted_are_the_attackers_studys():
    assert f"{_share('voronoi')} of the comfortable hunts\nto its {_share('trap')}" in (
        ROOT / "docs" / "getting-started.md").read_text()
    assert f"{_share('voronoi')} to its {_share('trap')}" in (ROOT / "mpc_hunt" / "control"
                                                             / "recommended.py").read_text()


def _captured_before(strategy: str, attacker: str) -> tuple[int, int]:
    """:func:`_captured` on the study's last run (its rows kept in ``sweep.previous.json``)."""
    mine = [r for r in _kept_rows() if r["strategy"].split(":")[0] == strategy and r["attacker"] == attacker
            and r["belief"] == "exact" and r["comfortable"]]
    return sum(r["outcome"] == "captured" for r in mine), len(mine)


@functools.cache
def _kept_rows() -> list[dict]:
    kept = json.loads((ROOT / "studies" / "attackers" / "sweep.previous.json").read_text())
    return [dict(zip(kept["fields"], row)) for row in kept["rows"]]


def test_the_adversarial_loops_table_after_retraining_is_the_attackers_studys_summary():
    """After retraining: on the last run's 60 hunts a cell (its kept rows) and on the study's own."""
    loop = _section((ROOT / "docs" / "envs.md").read_text(), "### The adversarial loop, once")
    rows = {label: (before, now) for label, before, now in
            re.findall(r"^\| (.+?) \| \d+ / \d+ \| (\d+ / \d+) \| (\d+ / \d+) \|$", loop, flags=re.M)}
    names = {"`trap`": "trap", "`voronoi`": "voronoi", "`ppo` team": "ppo", "`apf`": "apf",
             "paper's strategy": "paper", "`contain`": "contain", "`enclose`": "enclose"}
    assert set(rows) == set(names)
    for label, strategy in names.items():
        assert rows[label] == ("{} / {}".format(*_captured_before(strategy, "ppo")),
                               "{} / {}".format(*_captured(strategy, "ppo"))), label


def test_the_shares_times_and_two_robot_hunts_e16_quotes_are_the_attackers_studys_readme():
    e16 = " ".join(_section((ROOT / "docs" / "model.md").read_text(), "### E16").split())
    study = (ROOT / "studies" / "attackers" / "README.md").read_text()
    solving = dict(re.findall(r"`(\w+):rti:hpipm:\d+` (\d+\.\d %)", study.split("each of them ran:")[1]
                              .split(". ")[0]))
    quoted = re.search(r"`trap` captures (\S+ %), `contain` (\S+ %) \(it copies the baseline's places\), "
                       r"`enclose` (\S+ %)", e16)
    assert quoted.groups() == (solving["trap"], solving["contain"], solving["enclose"])
    median = re.search(r"on the hunts both capture \| (\S+) s against (\S+) s \((\d+) hunts\)",
                       study)
    assert (f"On the {median[3]} hunts both capture, the median capture time is {median[1]} s against "
            f"{median[2]} s") in e16
    two = re.search(r"two-robot hunts against `apf` \| (\d+) / (\d+) \|", study)
    assert f"It captures {two[1]} of {two[2]} reachable ones against `apf`" in e16
    (flee,), (gap,) = ([r for r in EXACT if r["strategy"].startswith("trap:") and r["attacker"] == a]
                       for a in ("flee", "gap"))
    assert (f"({flee['failures']['attacker_escaped']} of the {flee['hunts'] - flee['captured']} hunts of "
            f"{flee['hunts']} it loses against `flee`, {gap['failures']['attacker_escaped']} of "
            f"{gap['hunts'] - gap['captured']} against `gap`)") in e16


def test_the_paired_differences_e16_quotes_are_the_attackers_studys_league():
    """E16's paired differences of ``trap`` against the Voronoi baseline (and the PPO attacker's) are the study's
    league table's, interval and verdict (``+9 (-1 to +22), 43: not told apart`` quoted as ``+9 points, −1 to +22,
    not told apart``)."""
    e16 = " ".join(_section((ROOT / "docs" / "model.md").read_text(), "### E16").split()).replace("−", "-")
    study = (ROOT / "studies" / "attackers" / "README.md").read_text()
    section = study.split("## The learned agents")[1].split("\n## ")[0]
    league = {row[0]: row[5] for row in ([c.strip() for c in line.strip().strip("|").split("|")]
                                         for line in section.splitlines() if line.startswith("| "))}
    for attacker in ("apf", "noisy", "ppo", "flee", "gap"):
        difference, lo, hi, verdict = re.fullmatch(r"(\S+) \((\S+) to (\S+)\), \d+: (.+)", league[attacker]).groups()
        quoted = f"({difference} points, {lo} to {hi}"
        if verdict == "not told apart":      # gap's is said after it: "neither told apart"
            assert f"{quoted}, not told apart)" in e16 or (attacker == "gap" and f"{quoted}), neither told apart"
                                                            in e16), attacker
        else:
            assert f"{quoted})" in e16 and f"{verdict} against" in e16, attacker
        if verdict == "behind":
            assert f"It is behind against `{attacker}` {quoted})" in e16, attacker


def test_the_capture_time_differences_e16_quotes_are_the_attackers_studys():
    """E16's paired capture-time differences (``trap`` quicker against some attackers, not told apart against the
    others) are the study's verdicts table's."""
    e16 = " ".join(_section((ROOT / "docs" / "model.md").read_text(), "### E16").split()).replace("−", "-")
    study = (ROOT / "studies" / "attackers" / "README.md").read_text()
    rows = {cells[0]: cells[6] for cells in ([c.strip() for c in line.strip().strip("|").split("|")]
                                             for line in study.splitlines() if " s / " in line)
            if len(cells) == 8}                                 # the verdicts' rows: "154.3 s / 176.6 s (34 hunts)"
    quicker = [a for a, cell in rows.items() if cell.endswith(": quicker")]
    apart = [a for a, cell in rows.items() if cell.endswith(": not told apart")]
    assert sorted(quicker + apart) == sorted(SUMMARY["arguments"]["attackers"])      # no attacker it is slower against
    assert f"it is quicker against {WORDS[len(quicker)]} attackers" in e16
    assert f"against {' and '.join(f'`{a}`' for a in apart)} the two are not told apart" in e16
    for attacker in quicker:
        median, lo, hi = re.fullmatch(r"(\S+) s \((\S+) to (\S+)\), \d+: quicker", rows[attacker]).groups()
        assert f"`{attacker}` ({median} s, {lo} to {hi})" in e16


def test_the_own_loops_overruns_quoted_are_the_realtime_studys():
    """docs/benchmarks.md's reading of the own loop quotes the committed run's counts of late steps."""
    o = json.loads((ROOT / "studies" / "realtime" / "results.json").read_text())["overruns"]
    text = " ".join(_section((ROOT / "docs" / "benchmarks.md").read_text(), "### Every pair in its own loop, under").split())
    assert f"Of the {o['steps']:,} steps, {o['past_budget']:,} went past 0.02 s" in text
    assert f"{o['past_by_overrun']} by more than 5 ms. {o['past_limit_and_overhead']} took longer than the limit" in text
    machines = o["past_limit_and_overhead"] - o["past_limit_on_cpu"]
    assert f"on the wall clock; {machines} of those were the machine's" in text
    assert f"Counting only the time the process ran, {o['past_limit_on_cpu']} did" in text


def test_the_team_sweeps_counts_against_the_ppo_attacker_quoted_are_its_summarys():
    """docs/envs.md's adversarial loop quotes the team sweep's captures against the retrained PPO attacker."""
    team = json.loads((ROOT / "studies" / "team_sweep" / "summary.json").read_text())["summaries"]["attackers.db"]
    loop = " ".join(_section((ROOT / "docs" / "envs.md").read_text(), "### The adversarial loop, once").split())
    central, distributed = ([s for s in team if s["attacker"] == "ppo" and s["strategy"].startswith(f"enclose:{f}:")]
                            for f in ("rti", "distributed"))
    (c,), (d,) = central, distributed
    can = c["hunts"] - c["uncapturable_by_definition"]
    assert (f"captures {c['captured']} of the {can} hunts against it that can be captured "
            f"({round(c['success_rate_comfortable'] * c['comfortable'])} of its {c['comfortable']} comfortable ones) "
            f"centralised, and {d['captured']} ({round(d['success_rate_comfortable'] * d['comfortable'])}) "
            "distributed") in loop

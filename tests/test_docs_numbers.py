"""Numbers the docs quote from a study are the study's committed numbers (the study's own ``--check`` holds those
to the code)."""

from __future__ import annotations

import json
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _section(text: str, heading: str) -> str:
    start = text.index(heading)
    following = text.find("\n### ", start + len(heading))
    return text[start:following if following >= 0 else len(text)]


def test_the_trap_table_of_e16_is_the_attackers_studys_summary():
    e16 = _section((ROOT / "docs" / "model.md").read_text(), "### E16")
    rows = re.findall(r"^\| (\w+) \| (\d+) \| (\d+) \|$", e16, flags=re.M)
    summary = json.loads((ROOT / "studies" / "attackers" / "summary.json").read_text())
    captured = {(row["strategy"].split(":")[0], row["attacker"]): round(row["success_rate_comfortable"]
                                                                       * row["comfortable"])
                for row in summary["strategies"] if row["belief"] == "exact"}
    assert {attacker for attacker, _, _ in rows} == set(summary["arguments"]["attackers"])
    for attacker, trap, voronoi in rows:
        assert (int(trap), int(voronoi)) == (captured["trap", attacker], captured["voronoi", attacker]), attacker


def test_the_baselines_and_the_defaults_shares_quoted_are_the_attackers_studys():
    summary = json.loads((ROOT / "studies" / "attackers" / "summary.json").read_text())

    def share(strategy: str) -> str:
        rates = [row["success_rate_comfortable"] for row in summary["strategies"]
                 if row["belief"] == "exact" and row["strategy"].split(":")[0] == strategy]
        return f"{100 * sum(rates) / len(rates):.1f} %"

    quoted = f"{share('voronoi')} of the comfortable hunts\nto its {share('trap')}"
    assert quoted in (ROOT / "README.md").read_text()
    assert f"{share('voronoi')[:-2]} % to its {share('trap')}" in (ROOT / "mpc_hunt" / "control"
                                                                 / "recommended.py").read_text()


def test_the_adversarial_loops_table_after_retraining_is_the_attackers_studys_summary():
    loop = _section((ROOT / "docs" / "envs.md").read_text(), "### The adversarial loop, once")
    rows = dict(re.findall(r"^\| (.+?) \| \d+ / \d+ \| (\d+ / \d+) \|$", loop, flags=re.M))
    summary = json.loads((ROOT / "studies" / "attackers" / "summary.json").read_text())
    names = {"`trap`": "trap", "`voronoi`": "voronoi", "`ppo` team": "ppo", "`apf`": "apf",
             "paper's strategy": "paper", "`contain`": "contain", "`enclose`": "enclose"}
    assert set(rows) == set(names)
    for label, strategy in names.items():
        row, = [r for r in summary["strategies"] if r["belief"] == "exact" and r["attacker"] == "ppo"
                and r["strategy"].split(":")[0] == strategy]
        assert rows[label] == f"{round(row['success_rate_comfortable'] * row['comfortable'])} / {row['comfortable']}"

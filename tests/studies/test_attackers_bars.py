"""The attackers study's verdicts (studies/attackers.py): the recommended controller against the Voronoi baseline,
and the recommended controller being the one that captures most, on rows made up for the purpose."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from mpc_hunt.world.behaviours import BEHAVIOURS  # noqa: E402
from studies import attackers  # noqa: E402
from mpc_hunt.sweep.paired import newcombe, paired_counts  # noqa: E402


def _row(strategy, attacker, index, captured, *, defenders=4, time=100.0, cause=None):
    return {"strategy": strategy, "attacker": attacker, "belief": "exact", "seed": 1, "index": index, "comfortable": 1,
            "reachable": 1, "n_defenders": defenders, "outcome": "captured" if captured else "failed",
            "capture_time_s": time if captured else None, "cause": None if captured else (cause or "time_limit"),
            "solves_over_time_step": 0}


def _summary(strategy, attacker, rate):
    return {"strategy": strategy, "attacker": attacker, "belief": "exact", "success_rate_comfortable": rate}


def test_the_mean_over_attackers_ranks_only_strategies_run_on_every_attacker():
    summaries = [_summary(attackers.FOCUS, a, 0.5) for a in BEHAVIOURS] + \
                [_summary(attackers.BASELINE, a, 0.25) for a in BEHAVIOURS] + \
                [_summary("contain:rti:hpipm:10", a, 1.0) for a in BEHAVIOURS] + \
                [_summary("apf", "apf", 1.0)]
    means = attackers.mean_comfortable(summaries)
    assert means == {attackers.FOCUS: 0.5, attackers.BASELINE: 0.25}   # contain: not one of STRATEGIES; apf: one


def test_the_bars_count_each_attacker_the_two_robot_hunts_the_times_and_the_unsafe_hunts():
    focus, base = attackers.FOCUS, attackers.BASELINE
    rows, summaries = [], []
    for a in BEHAVIOURS:
        rows += [_row(focus, a, 0, True, time=90.0), _row(focus, a, 1, True, defenders=2, time=150.0),
                 _row(base, a, 0, True, time=100.0), _row(base, a, 1, False, defenders=2)]
        summaries += [_summary(focus, a, 1.0), _summary(base, a, 0.5)]
    last, n = list(BEHAVIOURS)[-1], len(BEHAVIOURS)
    rows[-4] = _row(focus, last, 0, False, cause="obstacle_collision")     # unsafe, and behind against the last
    rows[-1] = _row(base, last, 1, True, defenders=2, time=100.0)           # attacker: the baseline takes both there
    summaries[-2] = _summary(focus, last, 0.5)
    verdict = {what: (measured, met) for what, measured, met in attackers.bars(rows, summaries)}
    as_many, gain, apf, two_apf, two_gap, times, safe = verdict.values()
    assert as_many == (f"behind against {last}", False)
    # ((n − 1) × 100 % + 50 %) / n against 50 %
    assert gain[1] and f"{100 * (n - 0.5) / n - 50:+.1f} points" in gain[0]
    assert apf == ("2 / 2", True) and two_apf == ("1 / 1", True) and two_gap == ("1 / 1", True)
    assert times == (f"90.0 s against 100.0 s ({n} hunts)", True)
    assert safe == ("1 unsafe hunts, 0 solves over the time step", False)


def test_the_recommended_is_the_solving_controller_that_captures_most_then_the_quickest():
    # trap and contain each capture one of two comfortable hunts per attacker on the hunts both ran, enclose none;
    # the baseline (no capture stage) captures both but is no candidate; contain's extra hunt is not shared; on the
    # tie the quicker, trap, is chosen. A contain that captures one hunt more is still not told apart from trap
    # (the paired interval holds 0): the quicker stays. A contain that captures every hunt is chosen.
    rows = []
    for a in BEHAVIOURS:
        rows += [_row("trap:rti:hpipm:10", a, 0, True, time=90.0), _row("trap:rti:hpipm:10", a, 1, False),
                 _row("contain:rti:hpipm:10", a, 0, True, time=120.0), _row("contain:rti:hpipm:10", a, 1, False),
                 _row("contain:rti:hpipm:10", a, 2, True), _row("enclose:rti:hpipm:10", a, 0, False),
                 _row("enclose:rti:hpipm:10", a, 1, False), _row("voronoi", a, 0, True), _row("voronoi", a, 1, True)]
    shares, common = attackers.solving_shares(rows)
    assert common == 2 * len(BEHAVIOURS)
    assert shares == {"trap:rti:hpipm:10": 0.5, "contain:rti:hpipm:10": 0.5, "enclose:rti:hpipm:10": 0.0}
    assert attackers.recommended_choice(rows) == "trap:rti:hpipm:10"
    rows.append(_row("contain:rti:hpipm:10", "apf", 1, True))
    rows.remove(_row("contain:rti:hpipm:10", "apf", 1, False))
    assert attackers.solving_shares(rows)[0]["contain:rti:hpipm:10"] > 0.5
    assert attackers.recommended_choice(rows) == "trap:rti:hpipm:10"
    for a in BEHAVIOURS:
        if _row("contain:rti:hpipm:10", a, 1, False) in rows:
            rows.remove(_row("contain:rti:hpipm:10", a, 1, False))
            rows.append(_row("contain:rti:hpipm:10", a, 1, True))
    assert attackers.recommended_choice(rows) == "contain:rti:hpipm:10"


def test_the_league_pairs_the_hunts_and_tells_apart_only_what_its_interval_does():
    focus, team = attackers.FOCUS, attackers.LEARNED_TEAM
    rows = [_row(focus, "apf", i, True) for i in range(40)] + [_row(team, "apf", i, i < 10) for i in range(40)]
    rows += [_row(focus, "gap", i, i % 2 == 0) for i in range(40)]
    rows += [_row(team, "gap", i, i % 2 == 1) for i in range(40)]
    rows += [_row(team, "flee", i, True) for i in range(5)]             # the recommended one ran none of these
    apf = paired_counts(rows, focus, team, attackers.comfortable_against("apf"))
    lo, hi = newcombe(apf)
    assert apf.hunts == 40 and apf.difference == 0.75 and 0 < lo < 0.75 < hi < 1   # 30 of 40 won by focus alone
    gap = paired_counts(rows, focus, team, attackers.comfortable_against("gap"))
    lo, hi = newcombe(gap)
    assert gap.hunts == 40 and gap.difference == 0.0 and lo < 0 < hi   # as many each way: not told apart
    assert paired_counts(rows, focus, team, attackers.comfortable_against("flee")).hunts == 0
    table = "\n".join(attackers.league(rows))
    assert "| apf | 40 / 40 | 10 / 40 |" in table and "+75 (" in table and ", 40: ahead" in table
    assert "not told apart" in table

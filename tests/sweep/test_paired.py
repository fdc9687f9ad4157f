"""Two strategies told apart on the same hunts (mpc_hunt/sweep/paired.py): Newcombe's interval for paired
proportions, the pairing of a results file's rows, and ``mpc-hunt sweep-report --versus``."""

from __future__ import annotations

import contextlib
import io
import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt.cli import main
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.sweep.paired import (PairedCounts, cell, median_interval, newcombe, paired_counts, summary,
                                   time_summary, versus, versus_table)
from mpc_hunt.sweep.store import SweepStore

COUNTS = st.tuples(*(st.integers(0, 60),) * 4).map(lambda t: PairedCounts(*t))


@pytest.mark.parametrize("n, cells", [(20, (0.3, 0.1, 0.1)), (60, (0.4, 0.15, 0.08)), (300, (0.4, 0.15, 0.08)),
                                      (43, (0.5, 0.05, 0.02)), (43, (0.1, 0.4, 0.3))])
def test_the_interval_covers_the_true_difference_about_95_times_in_100(n, cells):
    # Drawn tables of n paired hunts: (both, first alone, second alone) with these chances. Newcombe's method is a
    # little conservative (measured 95.4-97.6 % here); an interval that forgot the pairs' correlation covers
    # ~99.9 % where they agree, one as narrow as the normal approximation's on the differences 92-93 % at n = 20.
    rng = np.random.default_rng(7)
    both, first, second = cells
    tables = rng.multinomial(n, [both, first, second, 1 - both - first - second], size=2000)
    covered = [lo <= first - second <= hi for lo, hi in (newcombe(PairedCounts(*t)) for t in tables)]
    assert 0.935 <= np.mean(covered) <= 0.985


@settings(max_examples=300, deadline=None)
@given(COUNTS)
def test_the_interval_holds_the_difference_within_minus_one_to_one_and_turns_with_the_pair(counts):
    lo, hi = newcombe(counts)
    assert -1.0 <= lo <= counts.difference <= hi <= 1.0
    swapped = newcombe(PairedCounts(counts.both, counts.second, counts.first, counts.neither))
    np.testing.assert_allclose(swapped, (-hi, -lo), atol=1e-12)
    if counts.hunts:
        more = newcombe(PairedCounts(*(4 * k for k in (counts.both, counts.first, counts.second, counts.neither))))
        assert more[1] - more[0] <= hi - lo + 1e-12             # four times the hunts alike: no wider


def test_no_discordant_hunt_is_not_a_certain_tie():
    lo, hi = newcombe(PairedCounts(3, 0, 0, 4))                 # 7 hunts, the same outcome each
    assert lo < -0.2 and hi > 0.2                               # (normal approximation: 0 to 0)
    assert newcombe(PairedCounts(0, 0, 0, 0)) == (-1.0, 1.0)
    lo, hi = newcombe(PairedCounts(0, 7, 0, 0))                 # 7 of 7 won by the first alone
    assert 0.4 < lo < 1.0 == hi


def _row(strategy, index, captured, attacker="gap", belief="exact", comfortable=1, time=100.0):
    return {"strategy": strategy, "attacker": attacker, "belief": belief, "seed": 1, "index": index,
            "outcome": "captured" if captured else "failed", "comfortable": comfortable,
            "capture_time_s": time if captured else None}


def test_a_difference_of_a_hunt_in_hundreds_is_printed_with_its_sign_not_as_0():
    assert cell(summary(PairedCounts(both=100, first=0, second=1, neither=99))).startswith("-0.5 (")
    assert cell(summary(PairedCounts(both=100, first=0, second=0, neither=100))).startswith("+0 (-1 to +1)")
    assert cell(summary(PairedCounts(both=20, first=3, second=0, neither=17))) == "+8 (-2 to +16), 40: not told apart"


def test_the_median_interval_is_the_sign_tests_order_statistics():
    assert median_interval(list(range(20, 0, -1))) == (10.5, 6, 15)       # n = 20: the 6th and the 15th
    assert median_interval([3.0, 1.0, 2.0, 6.0, 5.0, 4.0]) == (3.5, 1.0, 6.0)   # n = 6: the extremes (96.9 %)
    median, lo, hi = median_interval([1.0, 2.0, 3.0, 4.0, 5.0])         # n = 5: no interval reaches 95 %
    assert median == 3.0 and lo == -np.inf and hi == np.inf
    rng = np.random.default_rng(3)                                      # at least 95 % on any distribution
    covered = [lo <= 0.0 <= hi for lo, hi in (median_interval(list(rng.standard_cauchy(15)))[1:]
                                              for _ in range(3000))]
    assert 0.95 <= np.mean(covered) <= 0.975                            # n = 15: exactly 96.5 %


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-300, 300), min_size=6, max_size=60), st.floats(-50, 50))
def test_the_median_interval_holds_the_median_and_moves_with_the_values(values, shift):
    median, lo, hi = median_interval(values)
    assert lo <= median <= hi
    moved = median_interval([v + shift for v in values])
    np.testing.assert_allclose(moved, (median + shift, lo + shift, hi + shift), atol=1e-9)


def test_capture_times_are_paired_on_the_hunts_both_captured():
    rows = [_row("a", i, True, time=100.0 + i) for i in range(12)] + [_row("b", i, i != 3, time=120.0 + i)
                                                                          for i in range(12)]
    rows += [_row("a", 20, False), _row("b", 20, True, time=1.0)]        # b alone: not paired
    summary = time_summary(rows, "a", "b")
    assert summary["hunts"] == 11 and summary["median_difference_s"] == -20.0
    assert summary["ci95_s"] == [-20.0, -20.0] and summary["verdict"] == "quicker"
    assert time_summary(rows[:5] + rows[12:17], "a", "b")["verdict"] == "too few"
    assert time_summary(rows, "b", "a")["verdict"] == "slower"
    mixed = [_row("a", i, True, time=100.0 + d) for i, d in enumerate([-5, 5, -3, 3, -1, 1, 0, 2, -2, 4, -4])]
    mixed += [_row("b", i, True) for i in range(11)]
    assert time_summary(mixed, "a", "b")["verdict"] == "not told apart"
    assert time_summary(rows, "a", "b", lambda r: r["index"] > 50)["verdict"] == "none captured by both"


def test_only_the_hunts_both_ran_are_paired_by_attacker_and_belief():
    rows = [_row("a", i, i < 6) for i in range(10)] + [_row("b", i, i % 2 == 0) for i in range(8)]
    rows += [_row("b", i, True, attacker="flee") for i in range(5)]             # a ran none of these
    counts = paired_counts(rows, "a", "b")
    assert counts == PairedCounts(both=3, first=3, second=1, neither=1) and counts.difference == 0.25
    legacy = [{k: v for k, v in r.items() if k not in ("attacker", "belief")} for r in rows[:18]]
    assert paired_counts(legacy, "a", "b") == counts       # rows of an older file: the paper's attacker, exact
    entries = versus(rows, "a", "b")
    assert [(e["attacker"], e["all"]["hunts"]) for e in entries] == [("gap", 8)]
    assert entries[0]["all"]["verdict"] == "not told apart" and "+25 (" in versus_table(entries)
    for bad, message in (("c", "not a strategy of this file"), ("a", "give two different strategies")):
        with pytest.raises(MpcHuntError, match=message):
            versus(rows, "a", bad)
    apart = [_row("a", i, True) for i in range(3)] + [_row("b", i, True, attacker="flee") for i in range(3)]
    with pytest.raises(MpcHuntError, match="a b: no hunt of this file was run by both"):
        versus(apart, "a", "b")


def test_sweep_report_versus_prints_the_table_or_its_json_and_refuses_in_one_line(tmp_path, capsys):
    path = tmp_path / "s.db"
    store = SweepStore(path, {"strategies": ["apf", "voronoi"], "attackers": ["gap"], "beliefs": ["exact"],
                              "hunts": 30, "seed": 1, "ranges": {}})
    for i in range(30):
        store.add(_row("apf", i, i < 10) | {"name": f"h{i}"})
        store.add(_row("voronoi", i, i < 25) | {"name": f"h{i}"})
    store.close()
    assert main(["sweep-report", str(path), "--versus", "apf", "voronoi"]) == 0
    table = capsys.readouterr().out
    assert "| gap | exact | -50 (" in table and ", 30: behind |" in table
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["sweep-report", str(path), "--versus", "voronoi", "apf", "--json"]) == 0
    entry = json.loads(out.getvalue())["versus"][0]
    assert entry["all"]["first"] == 15 and entry["all"]["verdict"] == "ahead" and entry["all"]["ci95"][0] > 0.25
    assert entry["capture_time"] == {"hunts": 10, "median_difference_s": 0.0, "ci95_s": [0.0, 0.0],
                                     "verdict": "not told apart"}
    assert main(["sweep-report", str(path), "--versus", "apf", "trap"]) == 2
    err = capsys.readouterr().err
    assert "--versus trap:rti:hpipm:10: not a strategy of this file (it holds apf, voronoi)" in err
    assert len(err.strip().splitlines()) == 1

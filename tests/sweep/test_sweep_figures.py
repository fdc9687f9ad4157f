"""The sweep's figures: success among reachable hunts with Wilson intervals, the typical hunts chosen and drawn;
several attackers and beliefs."""

from __future__ import annotations

import numpy as np
import pytest

from mpc_hunt.cli.commands import main
from mpc_hunt.plots.sweep import lines_by_attacker, rate_by
from mpc_hunt.sweep.random_scenario import ScenarioRanges, ranges_to_dict, ranges_with
from mpc_hunt.sweep.runner import Hunt, run_hunt
from mpc_hunt.sweep.store import SweepStore
from mpc_hunt.sweep.summary import best_strategy, wilson
from mpc_hunt.sweep.typical import rerun, typical_rows

SMALL_ARENA = {"time_limit": 20.0, "arena": [0, 0, 6, 6], "n_obstacles": 0, "n_defenders": 4}


def _row(index, outcome, **extra):
    return {"strategy": "s", "index": index, "outcome": outcome, "reachable": True, "cause": None,
            "capture_time_s": None, "min_attacker_distance_m": 1.0, "n_defenders": 3, "speed_ratio": 0.3} | extra


def test_success_by_group_counts_reachable_hunts_only_and_carries_wilson_intervals():
    rows = [_row(0, "captured", n_defenders=2), _row(1, "failed", n_defenders=2),
            _row(2, "failed", n_defenders=2, reachable=False), _row(3, "uncapturable", n_defenders=3),
            _row(4, "captured", n_defenders=3), _row(5, "captured", n_defenders=3, speed_ratio=0.6)]
    xs, rates, bounds = rate_by(rows, "n_defenders")
    assert list(xs) == [2, 3] and list(rates) == [0.5, 1.0]
    assert np.array_equal(bounds, np.array([wilson(1, 2), wilson(2, 2)]).T)
    xs, rates, _ = rate_by(rows, "speed_ratio")
    assert list(xs) == [0.375, 0.625] and list(rates) == [2 / 3, 1.0]     # bins of 0.25, at their centres


def test_the_typical_hunts_are_the_median_capture_and_the_median_loss_of_the_commonest_cause():
    rows = [_row(0, "captured", capture_time_s=100.0), _row(1, "captured", capture_time_s=190.0),
            _row(2, "captured", capture_time_s=200.0), _row(3, "captured", capture_time_s=300.0),
            _row(4, "failed", cause="time_limit", min_attacker_distance_m=0.3),
            _row(5, "failed", cause="attacker_escaped", min_attacker_distance_m=2.0),
            _row(6, "failed", cause="attacker_escaped", min_attacker_distance_m=1.0),
            _row(7, "failed", cause="attacker_escaped", min_attacker_distance_m=0.1),
            _row(8, "failed", cause="time_limit", min_attacker_distance_m=0.5, reachable=False),
            _row(9, "failed", cause="time_limit", min_attacker_distance_m=0.5, reachable=False),
            _row(10, "captured", capture_time_s=195.0, strategy="other")]
    typical = typical_rows(rows, "s")
    assert typical["captured"]["index"] == 1      # median 195 s: 190 and 200 tie, the lower index wins
    assert typical["lost"]["index"] == 6          # escapes outnumber the reachable time limits; median 1.0 m
    assert typical_rows([r for r in rows if r["outcome"] == "captured"], "s").keys() == {"captured"}


@pytest.fixture(scope="module")
def small_sweep(tmp_path_factory):
    path = tmp_path_factory.mktemp("sweep") / "s.db"
    assert main(["sweep", "--hunts", "4", "--seed", "3", "--strategy", "apf", "--workers", "1", "--json",
                 "--output", str(path)]) == 0
    return path


def test_a_rerun_row_reproduces_its_hunt(small_sweep):
    store = SweepStore(small_sweep)
    row = store.rows()[0]
    store.close()
    scenario, result = rerun(row)
    assert scenario.name == row["name"] and result.steps == row["steps"]
    assert result.captured == (row["outcome"] == "captured")


def test_sweep_report_draws_every_figure_and_the_typical_hunts(small_sweep, tmp_path, capsys):
    assert main(["sweep-report", str(small_sweep), "--plot", str(tmp_path)]) == 0
    names = {p.name for p in tmp_path.iterdir()}
    assert {"success_by_n_defenders.png", "success_by_n_obstacles.png", "success_by_speed_ratio.png",
            "capture_times.png", "typical_hunts.png"} <= names
    assert all(p.stat().st_size > 10_000 for p in tmp_path.iterdir())
    assert f"wrote {tmp_path / 'typical_hunts.png'}" in capsys.readouterr().out


def test_a_rerun_row_reproduces_its_hunt_with_its_attacker_and_belief():
    """The noisy attacker draws from the world's generator, the belief's heading error from its own."""
    ranges = ranges_to_dict(ranges_with(ScenarioRanges(), SMALL_ARENA))
    row = run_hunt(Hunt("enclose:rti:hpipm:10", 4, 1, ranges, attacker="noisy", belief="intent_heading=60"))
    scenario, result = rerun(row)
    assert scenario.attacker.behaviour == "noisy" and result.steps == row["steps"]
    assert (result.min_attacker_distance, float(np.sum(result.path_lengths))) == \
        (row["min_attacker_distance_m"], row["path_length_m"])
    _, exact = rerun(row | {"belief": "exact"})             # the belief reaches the controller
    assert float(np.sum(exact.path_lengths)) != row["path_length_m"]


def test_lines_are_strategies_with_their_belief_when_there_are_several_and_panels_attackers():
    rows = [_row(0, "captured", attacker="apf", belief="exact"), _row(0, "failed", attacker="gap", belief="exact"),
            _row(0, "captured", attacker="apf", belief="eta=3x"),
            _row(1, "failed", strategy="t", attacker="gap", belief="exact")]
    attackers, lines = lines_by_attacker(rows)
    assert attackers == ["apf", "gap"]
    assert {name: list(by) for name, by in lines.items()} == {"s, exact": ["apf", "gap"], "s, eta=3x": ["apf"],
                                                              "t, exact": ["gap"]}
    assert list(lines_by_attacker([r for r in rows if r["belief"] == "exact"])[1]) == ["s", "t"]


def test_the_best_strategy_pools_its_attackers_and_beliefs():
    def summary(strategy, captured, uncapturable=0):
        return {"strategy": strategy, "hunts": 10, "uncapturable_by_definition": uncapturable, "captured": captured}

    # b has the best single summary (10 of 10), a the best over all its hunts (15 of 20 against 10 of 18)
    assert best_strategy([summary("a", 9), summary("b", 10), summary("a", 6), summary("b", 0, 2)]) == "a"
    assert best_strategy([summary("a", 5), summary("b", 5)]) == "a"           # a tie: the first listed


@pytest.fixture(scope="module")
def two_attackers(tmp_path_factory):
    path = tmp_path_factory.mktemp("sweep") / "s.db"
    sets = [f"--set={k}={v}" for k, v in SMALL_ARENA.items()]
    assert main(["sweep", "--hunts", "3", "--seed", "4", "--strategy", "apf", "--attacker", "apf", "--attacker",
                 "noisy", "--workers", "1", "--json", "--output", str(path), *sets]) == 0
    return path


def test_sweep_report_draws_success_per_strategy_per_attacker(two_attackers, tmp_path, capsys):
    capsys.readouterr()
    assert main(["sweep-report", str(two_attackers), "--plot", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "| apf | apf | exact | 3 (" in out and "| apf | noisy | exact | 3 (" in out
    names = {p.name for p in tmp_path.iterdir()}
    assert {"success_by_n_defenders.png", "success_by_n_obstacles.png", "success_by_speed_ratio.png",
            "success_by_attacker.png", "capture_times.png"} <= names
    assert all(p.stat().st_size > 10_000 for p in tmp_path.iterdir())

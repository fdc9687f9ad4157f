"""Ensembles: a nanometre's move of the starts, the bands a rerun must land in, and checks that still bind."""

from __future__ import annotations

import dataclasses
import importlib
import json
import sys
from pathlib import Path

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt import builtin_scenario, simulate
from mpc_hunt.ensemble import SCALE, band, outside, perturbed, widened
from mpc_hunt.geometry import dot2
from strategies import floats

ROOT = Path(__file__).resolve().parents[1]
values = st.lists(floats(min_value=-1e3, max_value=1e3), min_size=1, max_size=20)


def _study(name: str):
    sys.path.insert(0, str(ROOT / "studies"))
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(str(ROOT / "studies"))


@settings(deadline=None, max_examples=30)
@given(st.integers(0, 2**32 - 1))
def test_a_member_moves_each_start_by_at_most_the_scale_and_nothing_else(seed):
    scenario = builtin_scenario("paper-obstacles")
    moved = perturbed(scenario, np.random.default_rng(seed))
    before = np.vstack([scenario.attacker.start, scenario.defender_starts])
    after = np.vstack([moved.attacker.start, moved.defender_starts])
    assert np.all(np.abs(after - before) <= SCALE) and np.any(after != before)
    assert dataclasses.replace(moved, attacker=scenario.attacker, defenders=scenario.defenders) == scenario


def test_the_same_generator_gives_the_same_member():
    scenario = builtin_scenario("paper-open")
    assert perturbed(scenario, np.random.default_rng(3)) == perturbed(scenario, np.random.default_rng(3))


@given(values)
def test_every_member_lies_in_its_band(xs):
    b = band(xs)
    assert b["min"] <= b["median"] <= b["max"]
    assert not any(outside(x, b, 0.0, 0.0) for x in xs)


@given(values, floats(min_value=0.0, max_value=2.0), floats(min_value=0.0, max_value=1.0))
def test_the_band_widens_by_its_width_or_the_floor(xs, fraction, floor):
    b = band(xs)
    low, high = widened(b, fraction, floor)
    margin = max(fraction * (b["max"] - b["min"]), floor)
    assert low == b["min"] - margin and high == b["max"] + margin
    assert outside(high + 1e-3 + abs(high) * 1e-9, b, fraction, floor)
    assert outside(None, b, fraction, floor) and outside(1.0, None, fraction, floor)
    assert not outside(None, None, fraction, floor)


@given(st.tuples(floats(min_value=-1e100, max_value=1e100), floats(min_value=-1e100, max_value=1e100)),
       st.tuples(floats(min_value=-1e100, max_value=1e100), floats(min_value=-1e100, max_value=1e100)))
def test_dot2_is_the_two_products_summed_in_order(a, b):
    assert dot2(np.array(a), np.array(b)) == a[0] * b[0] + a[1] * b[1]


def test_the_reproduction_check_fails_for_a_one_percent_change_of_the_field_gain():
    """The band must not be so wide that a real change of the model passes: η × 1.01 on one robust run."""
    reproduce = _study("reproduce_paper")
    committed = json.loads((ROOT / "studies" / "reproduction" / "results.json").read_text(encoding="utf-8"))
    scenario = builtin_scenario("paper-open")
    nominal = reproduce.report(simulate(scenario, prediction=False))
    assert reproduce.differing(committed, {"paper-open-no-prediction": nominal}) == []
    changed = dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, eta=1.01 * scenario.hunt.eta))
    errors = reproduce.differing(committed, {"paper-open-no-prediction": reproduce.report(
        simulate(changed, prediction=False))})
    assert any("path_lengths_m" in e for e in errors), errors


def test_the_sweep_check_reruns_robust_hunts_and_holds_them_to_their_bands():
    sweep = _study("sweep")
    steps = {"median": 100.0, "min": 98.0, "max": 104.0}
    entry = {"robust": True, "outcome": "captured", "cause": None, "termination": "captured", "wall_time_s": 1.0,
             "band": {k: steps if k in ("steps", "solves") else None for k in sweep.BANDED}}
    hunts = {"0": {**entry, "robust": False}, "1": entry, "2": {**entry, "wall_time_s": 0.5},
             "3": {**entry, "outcome": "failed", "cause": "attacker_escaped", "termination": "escaped"}}
    assert sweep.rerun_choice(hunts) == ["2", "3"]
    row = {k: None for k in sweep.BANDED} | {"outcome": "captured", "cause": None, "termination": "captured",
                                              "steps": 101, "solves": 101}
    assert sweep._off_band("h", entry, row) == []
    assert [e.split(":")[1].split()[0] for e in sweep._off_band("h", entry, row | {"steps": 108})] == ["steps"]
    assert sweep._off_band("h", entry, row | {"outcome": "failed"})

"""Ensembles: a nanometre's move of the starts, and the bands a rerun must land in."""

from __future__ import annotations

import dataclasses

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt import builtin_scenario
from mpc_hunt.world.ensemble import SCALE, band, outside_band, perturbed, widened
from strategies import floats

values = st.lists(floats(min_value=-1e3, max_value=1e3), min_size=1, max_size=20)


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
    assert not any(outside_band(x, b, 0.0, 0.0) for x in xs)


@given(values, floats(min_value=0.0, max_value=2.0), floats(min_value=0.0, max_value=1.0))
def test_the_band_widens_by_its_width_or_the_floor(xs, fraction, floor):
    b = band(xs)
    low, high = widened(b, fraction, floor)
    margin = max(fraction * (b["max"] - b["min"]), floor)
    assert low == b["min"] - margin and high == b["max"] + margin
    assert outside_band(high + 1e-3 + abs(high) * 1e-9, b, fraction, floor)
    assert outside_band(None, b, fraction, floor) and outside_band(1.0, None, fraction, floor)
    assert not outside_band(None, None, fraction, floor)


"""Random scenarios (mpc_hunt/sweep/random_scenario.py), their rows and labels (mpc_hunt/sweep/scenario_row.py), the arena."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt.sim.world_step import ESCAPED, stand
from mpc_hunt.world.arena import beyond_edge
from mpc_hunt.errors import ScenarioError
from mpc_hunt.sweep.random_scenario import (ScenarioRanges, dumps_ranges, load_ranges, loads_ranges, random_scenario,
                                      ranges_from_dict, ranges_to_dict, ranges_with, sweep_rng, sweep_scenario)
from mpc_hunt.world.scenario import Attacker, Defender, Obstacle, Scenario
from mpc_hunt.world.scenario_io import builtin_scenario, dumps_scenario, loads_scenario
from mpc_hunt.sweep.scenario_row import capturable_by_definition, scenario_row

PROPERTY = settings(deadline=None, max_examples=100)
seeds = st.integers(min_value=0, max_value=2**64 - 1)


def finite(lo: float, hi: float):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False, allow_subnormal=False)


def ordered(elements):
    return st.tuples(elements, elements).map(lambda p: tuple(sorted(p)))


@st.composite
def ranges(draw) -> ScenarioRanges:
    """Ranges roomy enough that rejection sampling never runs out of tries (arena ≥ 12 m, radii ≤ 1 m)."""
    x0, y0 = draw(finite(-1e3, 1e3)), draw(finite(-1e3, 1e3))
    w, h = draw(finite(12.0, 60.0)), draw(finite(12.0, 60.0))
    return ScenarioRanges(
        arena=(x0, y0, x0 + w, y0 + h),
        n_defenders=draw(ordered(st.integers(1, 5))), n_obstacles=draw(ordered(st.integers(0, 5))),
        obstacle_radius=draw(ordered(finite(0.05, 1.0))), defender_speed=draw(ordered(finite(0.01, 2.0))),
        speed_ratio=draw(ordered(finite(0.01, 0.99))), perception_radius=draw(ordered(finite(0.1, 3.0))),
        min_spacing=draw(finite(0.2, 2.0)), margin=draw(finite(0.0, 0.5)), time_limit=draw(finite(1.0, 1e3)))


def check_generated(s: Scenario, r: ScenarioRanges) -> None:
    """Every rule random_scenario promises."""
    x_min, y_min, x_max, y_max = r.arena
    assert s.arena == r.arena
    assert r.n_defenders[0] <= len(s.defenders) <= r.n_defenders[1]
    assert r.n_obstacles[0] <= len(s.obstacles) <= r.n_obstacles[1]
    for i, o in enumerate(s.obstacles):
        assert r.obstacle_radius[0] <= o.radius <= r.obstacle_radius[1]
        assert x_min + o.radius <= o.centre[0] <= x_max - o.radius
        assert y_min + o.radius <= o.centre[1] <= y_max - o.radius
        for other in s.obstacles[:i]:
            assert math.dist(o.centre, other.centre) >= o.radius + other.radius + r.margin
    starts = [s.attacker.start] + [d.start for d in s.defenders]
    for p in starts:
        assert x_min <= p[0] <= x_max and y_min <= p[1] <= y_max
        for o in s.obstacles:
            assert math.dist(p, o.centre) > o.radius + s.hunt.safety_distance + r.margin
    for i, p in enumerate(starts):
        for q in starts[:i]:
            assert math.dist(p, q) >= r.min_spacing
    assert not attacker_escaped(s, s.attacker.start)
    slowest = min(d.max_speed for d in s.defenders)
    assert all(r.defender_speed[0] <= d.max_speed <= r.defender_speed[1] for d in s.defenders)
    ratio = s.attacker.max_speed / slowest
    assert r.speed_ratio[0] * (1 - 1e-12) <= ratio <= r.speed_ratio[1] * (1 + 1e-12)
    assert s.attacker.max_speed < slowest
    assert math.hypot(*s.attacker.nominal_velocity) == pytest.approx(s.attacker.max_speed, rel=1e-12)
    assert r.perception_radius[0] <= s.attacker.perception_radius <= r.perception_radius[1]
    assert s.hunt == dataclasses.replace(type(s.hunt)(), time_limit=r.time_limit)


# --- the generator -------------------------------------------------------------------------------

@PROPERTY
@given(seed=seeds)
def test_default_ranges_give_valid_scenarios(seed):
    s = random_scenario(np.random.default_rng(seed))
    check_generated(s, ScenarioRanges())
    assert loads_scenario(dumps_scenario(s)) == s   # validates again, arena included


@PROPERTY
@given(seed=seeds, r=ranges())
def test_any_roomy_ranges_give_valid_scenarios(seed, r):
    s = random_scenario(np.random.default_rng(seed), r, name="r")
    check_generated(s, r)
    assert loads_scenario(dumps_scenario(s)) == s


@PROPERTY
@given(seed=seeds, r=ranges())
def test_same_seed_same_scenario_bit_for_bit(seed, r):
    a = random_scenario(np.random.default_rng(seed), r)
    b = random_scenario(np.random.default_rng(seed), r)
    assert a == b
    assert dumps_scenario(a) == dumps_scenario(b)


def test_different_seeds_differ():
    assert len({dumps_scenario(random_scenario(np.random.default_rng(seed))) for seed in range(20)}) == 20


def test_defaults_are_the_documented_ones():
    r = ScenarioRanges()
    assert r.arena == (0.0, 0.0, 20.0, 20.0)
    assert (r.n_defenders, r.n_obstacles) == ((2, 5), (0, 5))
    assert r.obstacle_radius == (0.3, 1.2)
    assert r.defender_speed == (0.08, 0.08)
    assert r.speed_ratio[1] < 1 and r.speed_ratio[0] <= 0.03 / 0.08 <= r.speed_ratio[1]
    assert r.perception_radius[0] <= 1.0 <= r.perception_radius[1]
    assert r.time_limit == 300.0


def test_counts_cover_their_ranges():
    seen = {(len(s.defenders), len(s.obstacles)) for s in (sweep_scenario(3, i) for i in range(300))}
    assert {n for n, _ in seen} == {2, 3, 4, 5}
    assert {m for _, m in seen} == {0, 1, 2, 3, 4, 5}


# --- sweeps --------------------------------------------------------------------------------------

@pytest.mark.parametrize("seed, index", [(0, 0), (7, 3), (2**40 + 1, 123)])
def test_sweep_rng_is_the_seed_sequence_child(seed, index):
    child = np.random.SeedSequence(seed).spawn(index + 1)[index]
    expected = np.random.default_rng(child).random(5)
    np.testing.assert_array_equal(sweep_rng(seed, index).random(5), expected)


def test_sweep_scenarios_are_reproducible_and_independent():
    a = [dumps_scenario(sweep_scenario(11, i)) for i in range(5)]
    assert a == [dumps_scenario(sweep_scenario(11, i)) for i in range(5)]
    assert len(set(a)) == 5
    s = sweep_scenario(11, 2)
    assert s.name == "random-11-2" and "seed 11" in s.description
    # Child i is not the stream of a plain seed.
    assert dumps_scenario(s) != dumps_scenario(dataclasses.replace(
        random_scenario(np.random.default_rng(11)), name=s.name, description=s.description))


@pytest.mark.parametrize("seed, index, field", [(-1, 0, "seed"), (1.5, 0, "seed"), (True, 0, "seed"),
                                                ("7", 0, "seed"), (0, -2, "index"), (0, 0.0, "index")])
def test_bad_sweep_seeds(seed, index, field):
    with pytest.raises(ScenarioError, match=f"^{field}:"):
        sweep_rng(seed, index)


# --- ranges: validation, TOML, overrides ---------------------------------------------------------

@pytest.mark.parametrize("overrides, field", [
    ({"n_defenders": [6, 5]}, "n_defenders"),
    ({"n_defenders": [0, 3]}, "n_defenders"),
    ({"n_defenders": 21}, "n_defenders"),
    ({"n_defenders": "3"}, "n_defenders"),
    ({"n_defenders": 2.5}, "n_defenders"),
    ({"n_defenders": [1, 2, 3]}, "n_defenders"),
    ({"n_obstacles": [-1, 2]}, "n_obstacles"),
    ({"n_obstacles": 101}, "n_obstacles"),
    ({"obstacle_radius": [1.0, 0.5]}, "obstacle_radius"),
    ({"obstacle_radius": 0.0}, "obstacle_radius"),
    ({"obstacle_radius": 10.5}, "obstacle_radius"),          # wider than the 20 m arena
    ({"defender_speed": 0.0}, "defender_speed"),
    ({"defender_speed": 2e3}, "defender_speed"),
    ({"speed_ratio": 1.0}, "speed_ratio"),
    ({"speed_ratio": [0.5, 1.2]}, "speed_ratio"),
    ({"speed_ratio": 0.0}, "speed_ratio"),
    ({"perception_radius": -1.0}, "perception_radius"),
    ({"perception_radius": float("nan")}, "perception_radius"),
    ({"min_spacing": 0.1}, "min_spacing"),                   # below the hunt's min_separation
    ({"min_spacing": True}, "min_spacing"),
    ({"margin": -0.1}, "margin"),
    ({"time_limit": 0.05}, "time_limit"),
    ({"time_limit": 2e6}, "time_limit"),
    ({"arena": [0.0, 0.0, 0.0, 20.0]}, "arena"),
    ({"arena": [0.0, 0.0, 20.0]}, "arena"),
    ({"arena": [0.0, 0.0, float("inf"), 20.0]}, "arena"),
    ({"max_tries": 0}, "max_tries"),
    ({"max_tries": 1.5}, "max_tries"),
    ({"colour": "red"}, "colour"),
])
def test_bad_ranges_name_the_field(overrides, field):
    with pytest.raises(ScenarioError) as info:
        ranges_with(ScenarioRanges(), overrides)
    assert str(info.value).startswith(f"ranges.{field}:"), str(info.value)


@pytest.mark.parametrize("overrides, field", [
    ({"n_obstacles": 100, "obstacle_radius": 1.2, "max_tries": 20}, "n_obstacles"),
    ({"arena": [0.0, 0.0, 3.0, 3.0], "n_obstacles": 1, "obstacle_radius": 1.5, "margin": 1.0}, "n_obstacles"),
    ({"n_defenders": 20, "min_spacing": 10.0, "max_tries": 100}, "n_defenders"),
])
def test_impossible_ranges_fail_naming_the_count(overrides, field):
    r = ranges_with(ScenarioRanges(), overrides)
    with pytest.raises(ScenarioError) as info:
        random_scenario(np.random.default_rng(0), r)
    assert str(info.value).startswith(f"ranges.{field}:") and "draws" in str(info.value)


def test_overrides_replace_field_by_field():
    r = ranges_with(ScenarioRanges(), {"n_defenders": 3, "speed_ratio": [0.3, 0.4]})
    assert r.n_defenders == (3, 3) and r.speed_ratio == (0.3, 0.4)
    assert dataclasses.replace(r, n_defenders=(2, 5), speed_ratio=(0.25, 0.75)) == ScenarioRanges()
    assert ranges_from_dict({}) == ScenarioRanges()


@PROPERTY
@given(r=ranges())
def test_ranges_round_trip_through_toml_text(r):
    assert loads_ranges(dumps_ranges(r)) == r
    assert ranges_from_dict(ranges_to_dict(r)) == r


def test_ranges_round_trip_through_a_file(tmp_path):
    r = ranges_with(ScenarioRanges(), {"n_obstacles": [1, 3], "arena": [-5, -5, 5, 5], "obstacle_radius": 0.5})
    path = tmp_path / "ranges.toml"
    path.write_text(dumps_ranges(r), encoding="utf-8")
    assert load_ranges(path) == r


def test_ranges_file_with_scalars_and_defaults(tmp_path):
    path = tmp_path / "ranges.toml"
    path.write_text("[ranges]\nn_defenders = 3\nspeed_ratio = [0.3, 0.5]\n", encoding="utf-8")
    assert load_ranges(path) == ranges_with(ScenarioRanges(), {"n_defenders": [3, 3], "speed_ratio": [0.3, 0.5]})


@pytest.mark.parametrize("text, start", [
    ("[ranges]\nn_defenders = [6, 5]\n", "ranges.n_defenders: min 6 exceeds max 5"),
    ("[ranges]\ncolour = 1\n", "ranges.colour: unknown key"),
    ("n_defenders = 3\n", "n_defenders: unknown key"),
    ("ranges = 3\n", "ranges: expected a table"),
    ("[ranges\n", "{path}: not valid TOML"),
    ("# nothing\n", "{path}: empty"),
])
def test_bad_ranges_files_name_file_and_field(tmp_path, text, start):
    path = tmp_path / "ranges.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_ranges(path)
    message = str(info.value)
    assert message.startswith(start.format(path=path)) and str(path) in message


# --- labels and rows ----------------------------------------------------------------------------

def _with(n_defenders: int, n_obstacles: int) -> Scenario:
    return Scenario(name="count", defenders=tuple(Defender((float(i), 0.0), 0.08) for i in range(n_defenders)),
                    attacker=Attacker((0.0, 5.0), (0.03, 0.0), 0.03, 1.0),
                    obstacles=tuple(Obstacle((10.0 + 3 * j, 10.0), 1.0) for j in range(n_obstacles)))


@pytest.mark.parametrize("n_defenders, n_obstacles, capturable", [
    (1, 0, False), (2, 0, False), (1, 1, False), (3, 0, True), (2, 1, True), (1, 2, True), (5, 5, True)])
def test_capturable_by_definition_counts_robots_and_obstacles(n_defenders, n_obstacles, capturable):
    assert capturable_by_definition(_with(n_defenders, n_obstacles)) is capturable


@pytest.mark.parametrize("name", ["paper-open", "paper-obstacles"])
def test_paper_scenarios_are_capturable_by_definition(name):
    assert capturable_by_definition(builtin_scenario(name))


def test_scenario_row_is_flat_and_complete():
    s = sweep_scenario(5, 1)
    row = scenario_row(s, seed=5, index=1)
    assert all(v is None or isinstance(v, (str, int, float, bool)) for v in row.values())
    assert (row["seed"], row["index"], row["name"]) == (5, 1, "random-5-1")
    assert row["n_defenders"] == len(s.defenders) and row["n_obstacles"] == len(s.obstacles)
    assert row["speed_ratio"] == s.attacker.max_speed / min(d.max_speed for d in s.defenders)
    assert row["perception_radius"] == s.attacker.perception_radius
    assert (row["arena_x_min"], row["arena_y_min"], row["arena_x_max"], row["arena_y_max"]) == s.arena
    assert row["hunt_time_limit"] == 300.0 and row["hunt_hunt_radius"] == 0.5
    assert row["capturable_by_definition"] == capturable_by_definition(s)
    assert loads_scenario(row["scenario_toml"]) == s


def test_scenario_row_of_a_paper_scenario():
    row = scenario_row(builtin_scenario("paper-open"))
    assert row["seed"] is None and row["arena_x_min"] is None and row["obstacle_radius_min"] is None
    assert row["speed_ratio"] == 0.03 / 0.08
    assert row["attacker_heading"] == pytest.approx(-math.pi / 4)


# --- the arena ------------------------------------------------------------------------------------

def test_paper_scenarios_have_no_arena_and_never_escape():
    for name in ("paper-open", "paper-obstacles"):
        s = builtin_scenario(name)
        assert s.arena is None
        assert not attacker_escaped(s, np.array([1e5, -1e5]))


def attacker_escaped(s, p) -> bool:
    """Does the world's judgement (:func:`mpc_hunt.sim.world_step.stand`) say the attacker at ``p`` escaped?"""
    return bool(stand(np.asarray(p, dtype=float), s.defender_starts, s.obstacle_centres, s.obstacle_radii,
                      s.packed) == ESCAPED)


@pytest.mark.parametrize("p, escaped", [
    ((10.0, 10.0), False), ((0.0, 20.0), False), ((20.0, 0.0), False),     # an edge is inside
    ((-1e-9, 5.0), True), ((5.0, 20.000001), True), ((25.0, 25.0), True),
    ((float("nan"), 5.0), False)])                                         # non-finite: the simulator's case
def test_attacker_escaped(p, escaped):
    s = dataclasses.replace(builtin_scenario("paper-open"), arena=(0.0, 0.0, 20.0, 20.0))
    assert attacker_escaped(s, np.array(p)) is escaped
    assert beyond_edge(s.arena, p) is escaped


def test_arena_round_trips_through_toml():
    s = dataclasses.replace(builtin_scenario("paper-obstacles"), arena=(-1.0, -2.0, 30.0, 40.5))
    assert "arena" in dumps_scenario(s)
    assert loads_scenario(dumps_scenario(s)) == s
    assert "arena" not in dumps_scenario(builtin_scenario("paper-obstacles"))


@settings(deadline=None, max_examples=30)
@given(st.integers(min_value=0, max_value=2**32 - 1))
def test_a_failed_defender_is_drawn_last_and_only_when_asked(seed):
    never = random_scenario(np.random.default_rng(seed), ScenarioRanges())
    always = random_scenario(np.random.default_rng(seed), ScenarioRanges(defender_failure=1.0))
    assert all(d.fails_at is None for d in never.defenders)
    failing = [d.fails_at for d in always.defenders if d.fails_at is not None]
    assert len(failing) == 1 and 30.0 <= failing[0] <= 150.0
    strip = [dataclasses.replace(d, fails_at=None) for d in always.defenders]
    assert dataclasses.replace(always, defenders=tuple(strip)) == never     # nothing else changes

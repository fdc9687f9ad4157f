"""Tests of scenarios: validation (mpc_hunt/world/scenario.py) and TOML I/O (mpc_hunt/world/scenario_io.py)."""

from __future__ import annotations

import functools
import copy
import tempfile
from pathlib import Path

import pytest
import tomli_w
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt.errors import ScenarioError, UnknownNameError
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario
from mpc_hunt.world.scenario_io import (builtin_names, builtin_scenario, dumps_scenario, load_scenario,
                                  loads_scenario, resolve_scenario, save_scenario,
                                  scenario_from_dict, scenario_to_dict)

FAST = settings(deadline=None, max_examples=100)
# Finite floats without subnormals (whose products underflow and defeat relative tolerances).
floats = functools.partial(st.floats, allow_nan=False, allow_infinity=False, allow_subnormal=False)

PAPER_DEFENDERS = [(1.0, 1.0), (15.0, 15.0), (15.0, 5.0)]
PAPER_OBSTACLES = [((10.0, 7.0), 1.0), ((5.0, 5.0), 0.5), ((7.0, 12.0), 1.0)]


# --- built-in scenarios -------------------------------------------------------------------------

def test_builtin_names():
    names = builtin_names()
    assert "paper-open" in names and "paper-obstacles" in names
    assert names == sorted(names)


@pytest.mark.parametrize("name", ["paper-open", "paper-obstacles"])
def test_builtin_carries_paper_values(name):
    s = builtin_scenario(name)
    assert s.name == name
    assert s.attacker.start == (1.0, 14.0)
    assert s.attacker.nominal_velocity == (0.2, -0.2)   # as printed; capped elsewhere (E6)
    assert s.attacker.max_speed == 0.03
    assert s.attacker.perception_radius == 1.0
    assert [d.start for d in s.defenders] == PAPER_DEFENDERS
    assert all(d.max_speed == 0.08 for d in s.defenders)
    assert s.hunt.hunt_radius == 0.5
    assert s.hunt.eta == 1.0
    assert s.hunt.protective_distance == 1.0
    assert s.defender_starts.shape == (3, 2)
    assert list(s.defender_max_speeds) == [0.08] * 3


def test_paper_open_has_no_obstacles():
    s = builtin_scenario("paper-open")
    assert s.obstacles == ()
    assert s.obstacle_centres.shape == (0, 2)
    assert s.obstacle_radii.shape == (0,)


def test_paper_obstacles_has_simulation_2_obstacles():
    s = builtin_scenario("paper-obstacles")
    assert [(o.centre, o.radius) for o in s.obstacles] == PAPER_OBSTACLES
    assert s.obstacle_centres.tolist() == [[10.0, 7.0], [5.0, 5.0], [7.0, 12.0]]
    assert s.obstacle_radii.tolist() == [1.0, 0.5, 1.0]


def test_resolve_scenario_by_name_default_and_path(tmp_path):
    assert resolve_scenario("paper-open") == builtin_scenario("paper-open")
    assert resolve_scenario(None) == builtin_scenario("paper-obstacles")
    path = tmp_path / "mine.toml"
    save_scenario(builtin_scenario("paper-open"), path)
    assert resolve_scenario(path) == builtin_scenario("paper-open")
    assert resolve_scenario(str(path)) == builtin_scenario("paper-open")


def test_resolve_unknown_name_lists_builtins():
    with pytest.raises(UnknownNameError) as info:
        resolve_scenario("paper-nowhere")
    message = str(info.value)
    assert "paper-nowhere" in message
    for name in builtin_names():
        assert name in message
    assert isinstance(info.value, KeyError)


def test_builtin_scenario_unknown_name_lists_builtins():
    with pytest.raises(UnknownNameError) as info:
        builtin_scenario("nope")
    assert "paper-open" in str(info.value) and "paper-obstacles" in str(info.value)


def test_resolve_missing_toml_path_is_a_scenario_error(tmp_path):
    missing = tmp_path / "absent.toml"
    with pytest.raises(ScenarioError) as info:
        resolve_scenario(str(missing))
    assert str(missing) in str(info.value)


# --- round trips --------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["paper-open", "paper-obstacles"])
def test_builtin_round_trips_through_file_and_text(name, tmp_path):
    s = builtin_scenario(name)
    path = tmp_path / f"{name}.toml"
    save_scenario(s, path)
    assert load_scenario(path) == s
    assert load_scenario(str(path)) == s
    assert loads_scenario(dumps_scenario(s)) == s
    assert scenario_from_dict(scenario_to_dict(s)) == s


def test_round_trip_keeps_non_default_hunt_parameters(tmp_path):
    s = Scenario(name="custom", description="multi\nline \"quoted\" ü",
                 defenders=(Defender((0.1, 0.2), 0.5),),
                 attacker=Attacker((3.0, -4.0), (1e-7, -2.5e3), 0.1, 0.75),
                 obstacles=(Obstacle((10.0, 10.0), 0.3),),
                 hunt=HuntParameters(hunt_radius=0.7, k_d=2.0, omega=0.3, hold_time=0.0,
                                     min_separation=0.0, time_step=0.05))
    path = tmp_path / "custom.toml"
    save_scenario(s, path)
    back = load_scenario(path)
    assert back == s
    assert back.hunt.hold_time == 0.0 and back.hunt.omega == 0.3


pos = floats(min_value=1e-3, max_value=1e3, allow_nan=False, allow_infinity=False)
coord = floats(min_value=-100.0, max_value=100.0, allow_nan=False, allow_infinity=False)
vec = st.tuples(coord, coord)
texts = st.text(st.characters(blacklist_categories=("Cs",)), max_size=20)


@st.composite
def scenarios(draw) -> Scenario:
    a_speed = draw(floats(1e-3, 1.0))
    attacker = Attacker(draw(vec), draw(st.tuples(floats(-10, 10), floats(-10, 10))),
                        a_speed, draw(pos))
    starts = draw(st.lists(vec, min_size=1, max_size=4, unique=True)
                  .filter(lambda xs: attacker.start not in xs))
    defenders = tuple(Defender(p, a_speed * draw(floats(1.01, 100.0))) for p in starts)
    # Obstacles far from every start ([-100, 100]²), so none contains one.
    obstacles = tuple(Obstacle((draw(floats(300, 500)), draw(floats(-500, 500))),
                               draw(floats(0.01, 100.0)))
                      for _ in range(draw(st.integers(0, 3))))
    time_limit = draw(floats(1.0, 1e4))
    hunt = HuntParameters(
        hunt_radius=draw(pos), centre_tolerance=draw(pos), eta=draw(pos), k_d=draw(pos),
        k_o=draw(pos), omega=draw(floats(1e-3, 1.0)), protective_distance=draw(pos),
        safety_distance=draw(floats(0.0, 10.0)), min_separation=draw(floats(0.0, 10.0)),
        min_attacker_distance=draw(pos), time_step=draw(floats(1e-3, 1.0)),
        time_limit=time_limit, hold_time=draw(floats(0.0, 100.0)))
    name = draw(texts.filter(lambda s: s.strip()))
    return Scenario(name=name, description=draw(texts), defenders=defenders, attacker=attacker,
                    obstacles=obstacles, hunt=hunt)


@FAST
@given(s=scenarios())
def test_random_scenarios_round_trip_through_toml_text(s):
    assert loads_scenario(dumps_scenario(s)) == s


@settings(deadline=None, max_examples=20)
@given(s=scenarios())
def test_random_scenarios_round_trip_through_files(s):
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "s.toml"
        save_scenario(s, path)
        assert load_scenario(path) == s


# --- rejected input: ScenarioError naming the field ---------------------------------------------

def base() -> dict:
    return copy.deepcopy({
        "name": "t",
        "attacker": {"start": [1.0, 14.0], "nominal_velocity": [0.2, -0.2], "max_speed": 0.03,
                     "perception_radius": 1.0},
        "defenders": [{"start": [1.0, 1.0], "max_speed": 0.08},
                      {"start": [15.0, 15.0], "max_speed": 0.08}],
        "obstacles": [{"centre": [10.0, 7.0], "radius": 1.0}],
        "hunt": {"hunt_radius": 0.5},
    })


def rejects(data_or_text, field: str) -> ScenarioError:
    text = data_or_text if isinstance(data_or_text, str) else tomli_w.dumps(data_or_text)
    with pytest.raises(ScenarioError) as info:
        loads_scenario(text)
    message = str(info.value)
    assert message.startswith(field), f"{message!r} does not name {field!r}"
    return info.value


def test_base_is_valid():
    s = loads_scenario(tomli_w.dumps(base()))
    assert len(s.defenders) == 2 and len(s.obstacles) == 1


def test_scenario_error_is_a_value_error():
    assert issubclass(ScenarioError, ValueError)


@pytest.mark.parametrize("radius", [-1.0, 0.0])
def test_non_positive_obstacle_radius(radius):
    d = base()
    d["obstacles"][0]["radius"] = radius
    rejects(d, "obstacles[0].radius")


def test_negative_obstacle_radius_in_python_api():
    with pytest.raises(ScenarioError, match=r"^obstacles\[0\]\.radius"):
        Scenario(name="t", defenders=(Defender((0.0, 0.0), 0.08),),
                 attacker=Attacker((5.0, 5.0), (0.1, 0.0), 0.03, 1.0),
                 obstacles=(Obstacle((9.0, 9.0), -0.5),))


def test_defender_start_inside_obstacle():
    d = base()
    d["defenders"][1]["start"] = [10.5, 7.2]
    err = rejects(d, "defenders[1].start")
    assert "obstacles[0]" in str(err)


def test_attacker_start_inside_obstacle():
    d = base()
    d["attacker"]["start"] = [10.0, 7.0]
    rejects(d, "attacker.start")


def test_coinciding_starts():
    d = base()
    d["defenders"][1]["start"] = [1.0, 1.0]
    rejects(d, "defenders[1].start")


@pytest.mark.parametrize("table, key, literal, field", [
    ("attacker", "max_speed", "nan", "attacker.max_speed"),
    ("attacker", "perception_radius", "inf", "attacker.perception_radius"),
    ("attacker", "start", "[nan, 1.0]", "attacker.start"),
    ("attacker", "nominal_velocity", "[0.2, -inf]", "attacker.nominal_velocity"),
    ("hunt", "eta", "inf", "hunt.eta"),
    ("hunt", "time_limit", "+inf", "hunt.time_limit"),
])
def test_non_finite_numbers_in_toml(table, key, literal, field):
    text = """
name = "t"
[attacker]
start = [1.0, 14.0]
nominal_velocity = [0.2, -0.2]
max_speed = 0.03
perception_radius = 1.0
[[defenders]]
start = [1.0, 1.0]
max_speed = 0.08
[hunt]
hunt_radius = 0.5
"""
    lines = text.splitlines()
    start = lines.index(f"[{table}]")
    for i in range(start + 1, len(lines)):
        if lines[i].startswith(f"{key} ="):
            lines[i] = f"{key} = {literal}"
            break
    else:
        lines.insert(start + 1, f"{key} = {literal}")
    err = rejects("\n".join(lines), field)
    assert "finite" in str(err)


def test_non_finite_defender_value():
    text = tomli_w.dumps(base()).replace("max_speed = 0.08", "max_speed = nan", 1)
    rejects(text, "defenders[0].max_speed")


@pytest.mark.parametrize("where, field", [
    (None, "colour"),
    ("attacker", "attacker.colour"),
    ("defenders", "defenders[0].colour"),
    ("obstacles", "obstacles[0].colour"),
    ("hunt", "hunt.colour"),
])
def test_unknown_keys(where, field):
    d = base()
    if where is None:
        d["colour"] = "red"
    elif where in ("defenders", "obstacles"):
        d[where][0]["colour"] = "red"
    else:
        d[where]["colour"] = "red"
    err = rejects(d, field)
    assert "unknown key" in str(err)


@pytest.mark.parametrize("speed", [0.03, 0.01])
def test_defender_not_faster_than_attacker(speed):
    d = base()
    d["defenders"][0]["max_speed"] = speed
    rejects(d, "defenders[0].max_speed")


@pytest.mark.parametrize("value", [[1.0], [1.0, 2.0, 3.0], 5.0, "ab", ["a", 1.0], [[1.0, 2.0]], {"x": 1}])
def test_malformed_vector(value):
    d = base()
    d["attacker"]["start"] = value
    err = rejects(d, "attacker.start")
    assert "two numbers" in str(err)


@pytest.mark.parametrize("value", [[True, 1.0], ["1", "2"]])
def test_vector_of_non_numbers_is_rejected(value):
    d = base()
    d["defenders"][0]["start"] = value
    rejects(d, "defenders[0].start")


def test_numeric_string_is_rejected():
    d = base()
    d["defenders"][0]["max_speed"] = "0.08"
    rejects(d, "defenders[0].max_speed")


def test_boolean_number_is_rejected():
    d = base()
    d["attacker"]["max_speed"] = True
    rejects(d, "attacker.max_speed")


def test_missing_attacker():
    d = base()
    del d["attacker"]
    assert "missing" in str(rejects(d, "attacker"))


@pytest.mark.parametrize("table, key, field", [
    ("attacker", "max_speed", "attacker.max_speed"),
    ("defenders", "max_speed", "defenders[0].max_speed"),
    ("obstacles", "radius", "obstacles[0].radius"),
])
def test_missing_required_key(table, key, field):
    d = base()
    target = d[table][0] if isinstance(d[table], list) else d[table]
    del target[key]
    assert "missing" in str(rejects(d, field))


def test_missing_name_and_no_defenders():
    d = base()
    del d["name"]
    rejects(d, "name")
    d = base()
    d["defenders"] = []
    rejects(d, "defenders")
    d = base()
    del d["defenders"]
    rejects(d, "defenders")


@pytest.mark.parametrize("mutate, field", [
    (lambda d: d.update(name="   "), "name"),
    (lambda d: d.update(name=5), "name"),
    (lambda d: d.update(description=3), "description"),
    (lambda d: d.update(hunt=3), "hunt"),
    (lambda d: d.update(attacker=[1, 2]), "attacker"),
    (lambda d: d.update(defenders=[1, 2]), "defenders[0]"),
    (lambda d: d.update(defenders={"start": [1, 1], "max_speed": 0.08}), "defenders"),
    (lambda d: d["hunt"].update(omega=1.5), "hunt.omega"),
    (lambda d: d["hunt"].update(omega=0.0), "hunt.omega"),
    (lambda d: d["hunt"].update(time_step=700.0), "hunt.time_step"),
    (lambda d: d["hunt"].update(hold_time=-1.0), "hunt.hold_time"),
    (lambda d: d["hunt"].update(hunt_radius=0.0), "hunt.hunt_radius"),
    (lambda d: d["attacker"].update(perception_radius=-1.0), "attacker.perception_radius"),
])
def test_other_invalid_values(mutate, field):
    d = base()
    mutate(d)
    rejects(d, field)


def test_invalid_toml_text():
    with pytest.raises(ScenarioError) as info:
        loads_scenario("name = \n[attacker", source="broken.toml")
    assert str(info.value).startswith("broken.toml")
    assert "not valid TOML" in str(info.value)


def test_invalid_toml_file_names_the_path(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("[[defenders]\nstart = [1, 2]\n", encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    assert str(path) in str(info.value)
    assert "not valid TOML" in str(info.value)


def test_field_error_in_file(tmp_path):
    d = base()
    d["obstacles"][0]["radius"] = -2.0
    path = tmp_path / "neg.toml"
    path.write_text(tomli_w.dumps(d), encoding="utf-8")
    with pytest.raises(ScenarioError, match=r"^obstacles\[0\]\.radius"):
        load_scenario(path)


def test_unreadable_paths(tmp_path):
    for path in (tmp_path / "does-not-exist.toml", tmp_path):
        with pytest.raises(ScenarioError) as info:
            load_scenario(path)
        assert str(info.value).startswith(str(path))
        assert "cannot read" in str(info.value)


def test_non_utf8_file(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(b'name = "caf\xe9"\n')
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    assert str(path) in str(info.value)
    assert "UTF-8" in str(info.value)

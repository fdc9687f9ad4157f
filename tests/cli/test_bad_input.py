"""Bad scenario and state files: exit status 2 and one line on stderr naming the file, the field, the problem.

Every bad scenario file goes through the three commands that read one
(``simulate --scenario``, ``solve --scenario``, ``scenarios --write``), every
bad state file through ``solve --state``. Nothing may simulate or solve
before the input is rejected: the fixture below makes that an error.
"""

from __future__ import annotations

import dataclasses
import json
import os
import re
from pathlib import Path

import numpy as np
import pytest

from mpc_hunt.world.hunt_state import load_state, save_state
from mpc_hunt.capture.problem import MAX_HORIZON
from mpc_hunt.arguments import MAX_SEED, MAX_WORKERS_PER_CORE
from mpc_hunt.cli.common import MAX_HUNTS, MAX_PROBLEMS, MAX_RANDOM, MAX_RUN_LENGTH, MAX_STARTS
from mpc_hunt.cli.commands import main
from mpc_hunt.sweep.random_scenario import ScenarioRanges
from mpc_hunt.world.scenario import MAX_DEFENDERS, MAX_MAGNITUDE, MAX_OBSTACLES, MAX_SPEED, MAX_STEPS
from mpc_hunt.world.scenario_io import MAX_FILE_BYTES, load_scenario
from scenario_text import scenario_toml

VALID = scenario_toml("bad-input", [(5, 3), (7, 6), (3.5, 6.5)], time_limit=5.0, arena=(0, 0, 20, 20),
                      obstacles=[((10, 10), 1.0)])


def edit(old: str, new: str, text: str = VALID) -> str:
    """``text`` with the first ``old`` replaced (which must be there)."""
    assert old in text, old
    return text.replace(old, new, 1)


def defender(i: int, line: str, new: str) -> str:
    """VALID with ``line`` of the i-th [[defenders]] table replaced."""
    head, *tables = VALID.split("[[defenders]]")
    tables[i] = edit(line, new, tables[i])
    return "[[defenders]]".join([head, *tables])


MANY_DEFENDERS = VALID + "".join(f"\n[[defenders]]\nstart = [{i}.0, 15.0]\nmax_speed = 0.08\n" for i in range(18))
MANY_OBSTACLES = VALID + "".join(f"\n[[obstacles]]\ncentre = [{30 + 3 * i}.0, 30.0]\nradius = 1.0\n"
                                 for i in range(100))
HUGE_INT = "1" + "0" * 400

# (content, substrings the one line must hold besides the file's name: the field first, then the problem)
BAD_SCENARIOS = [
    pytest.param(edit("max_speed = 0.03", "max_speed = "), ("line 7", "not valid TOML"), id="syntax-no-value"),
    pytest.param(edit("[[obstacles]]", "[[obstacles]"), ("line 22", "not valid TOML"), id="syntax-unclosed-table"),
    pytest.param(edit('name = "bad-input"', 'name = "bad-input"\nname = "again"'), ("not valid TOML",),
                 id="syntax-duplicate-key"),
    pytest.param(VALID + "\x00\n", ("not valid TOML",), id="nul-byte"),
    pytest.param("", ("empty",), id="empty"),
    pytest.param("# a scenario, some day\n\n", ("empty",), id="only-comments"),
    pytest.param(bytes(range(256)) * 4, ("not a UTF-8 text file", "0x80"), id="binary-garbage"),
    pytest.param(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", ("not a UTF-8 text file", "offset 0"), id="png-file"),
    pytest.param(edit('"bad-input"', '"caf\xe9"').encode("latin-1"), ("not a UTF-8 text file",), id="latin-1"),
    pytest.param("a = " + "[" * 100_000 + "]" * 100_000 + "\n", ("nested too deeply",), id="nested-too-deep"),
    pytest.param("#" * (MAX_FILE_BYTES + 1), ("larger than the limit",), id="too-large"),
    pytest.param(edit("\nradius = 1.0", "\nradius = 1" + "0" * 5000), ("not valid TOML", "too many digits"),
                 id="integer-with-5000-digits"),
    pytest.param("colour = 'red'\n" + VALID, ("colour", "unknown key"), id="unknown-top-key"),
    pytest.param(edit("max_speed = 0.03", "max_speed = 0.03\nspeed = 0.03"), ("attacker.speed", "unknown key"),
                 id="unknown-attacker-key"),
    pytest.param(defender(0, "max_speed = 0.08", "max_sped = 0.08"), ("defenders[0].max_sped", "unknown key"),
                 id="unknown-defender-key"),
    pytest.param(edit("centre = ", "center = "), ("obstacles[0].center", "unknown key"), id="unknown-obstacle-key"),
    pytest.param(edit("[hunt]", "[hunt]\nR_hunt = 0.5"), ("hunt.R_hunt", "unknown key"), id="unknown-hunt-key"),
    pytest.param(edit('[hunt]', '[hunt]\n"a\\nb" = 1'), ("unknown key",), id="unknown-key-with-newline"),
    pytest.param(edit('name = "bad-input"\n', ""), ("name", "missing"), id="missing-name"),
    pytest.param(edit("[attacker]", "[attack]"), ("attack", "unknown key"), id="misspelt-attacker-table"),
    pytest.param(VALID.split("[attacker]")[0] + "[[defenders]]" + VALID.split("[[defenders]]", 1)[1],
                 ("attacker", "missing"), id="missing-attacker"),
    pytest.param(edit("perception_radius = 1.0\n", ""), ("attacker.perception_radius", "missing"),
                 id="missing-perception-radius"),
    pytest.param(edit("\nradius = 1.0\n", "\n"), ("obstacles[0].radius", "missing"), id="missing-obstacle-radius"),
    pytest.param(VALID.split("[[defenders]]")[0] + "[[obstacles]]" + VALID.split("[[obstacles]]")[1],
                 ("defenders", "at least one defender"), id="missing-defenders"),
    pytest.param(edit("[attacker]", "[[attacker]]"), ("attacker", "expected a table"), id="attacker-array-of-tables"),
    pytest.param(VALID.split("[[defenders]]")[0] + "[defenders]\nstart = [5.0, 3.0]\nmax_speed = 0.08\n\n"
                 "[[obstacles]]" + VALID.split("[[obstacles]]")[1],
                 ("defenders", "expected an array of tables"), id="defenders-single-table"),
    pytest.param(edit('arena = [0.0, 0.0, 20.0, 20.0]', 'arena = [0.0, 0.0, 20.0, 20.0]\nhunt = 3',
                      edit("[hunt]\ntime_limit = 5.0\n", "")),
                 ("hunt", "expected a table"), id="hunt-not-a-table"),
    pytest.param(edit('name = "bad-input"', 'name = ""'), ("name", "non-empty string"), id="empty-name"),
    pytest.param(edit('name = "bad-input"', "name = 5"), ("name", "non-empty string"), id="number-name"),
    pytest.param(edit('name = "bad-input"', 'name = "x"\ndescription = 3'), ("description", "must be a string"),
                 id="number-description"),
    pytest.param(edit("max_speed = 0.03", 'max_speed = "0.03"'), ("attacker.max_speed", "expected a number"),
                 id="string-for-number"),
    pytest.param(edit("start = [5.0, 5.0]", "start = 5.0"), ("attacker.start", "expected two numbers"),
                 id="number-for-vector"),
    pytest.param(edit("perception_radius = 1.0", "perception_radius = true"),
                 ("attacker.perception_radius", "expected a number"), id="bool-for-number"),
    pytest.param(edit("start = [5.0, 5.0]", "start = [[5.0, 5.0]]"), ("attacker.start", "expected two numbers"),
                 id="nested-vector"),
    pytest.param(defender(0, "start = [5.0, 3.0]", "start = [5.0, 3.0, 0.0]"),
                 ("defenders[0].start", "expected two numbers"), id="vector-of-three"),
    pytest.param(defender(1, "start = [7.0, 6.0]", "start = [7.0]"), ("defenders[1].start", "expected two numbers"),
                 id="vector-of-one"),
    pytest.param(defender(0, "start = [5.0, 3.0]", "start = {x = 5.0, y = 3.0}"),
                 ("defenders[0].start", "expected two numbers"), id="vector-as-table"),
    pytest.param(defender(2, "start = [3.5, 6.5]", 'start = ["3.5", "6.5"]'),
                 ("defenders[2].start", "expected two numbers"), id="vector-of-strings"),
    pytest.param(edit("time_limit = 5.0", "time_limit = 2024-01-01"), ("hunt.time_limit", "expected a number"),
                 id="date-for-number"),
    pytest.param(defender(1, "max_speed = 0.08", "max_speed = nan"), ("defenders[1].max_speed", "finite"),
                 id="nan-speed"),
    pytest.param(edit("centre = [10.0, 10.0]", "centre = [inf, 10.0]"), ("obstacles[0].centre", "finite"),
                 id="inf-in-vector"),
    pytest.param(edit("[hunt]", "[hunt]\neta = -inf"), ("hunt.eta", "finite"), id="minus-inf-gain"),
    pytest.param(defender(0, "max_speed = 0.08", "max_speed = -0.08"), ("defenders[0].max_speed", "positive"),
                 id="negative-speed"),
    pytest.param(edit("max_speed = 0.03", "max_speed = 0.0"), ("attacker.max_speed", "positive"), id="zero-speed"),
    pytest.param(edit("\nradius = 1.0", "\nradius = 0.0"), ("obstacles[0].radius", "positive"), id="zero-radius"),
    pytest.param(edit("perception_radius = 1.0", "perception_radius = -1.0"),
                 ("attacker.perception_radius", "positive"), id="negative-perception-radius"),
    pytest.param(edit("[hunt]", "[hunt]\nsafety_distance = -0.1"), ("hunt.safety_distance", "not be negative"),
                 id="negative-safety-distance"),
    pytest.param(edit("[hunt]", "[hunt]\nomega = 1.5"), ("hunt.omega", "(0, 1]"), id="omega-above-one"),
    pytest.param(edit("start = [5.0, 5.0]", "start = [2e6, 5.0]"), ("attacker.start", "limit of 1e+06 m"),
                 id="huge-coordinate"),
    pytest.param(defender(2, "max_speed = 0.08", "max_speed = 5e3"), ("defenders[2].max_speed", "limit of 1000 m/s"),
                 id="huge-speed"),
    pytest.param(edit("time_limit = 5.0", "time_limit = 1e7"), ("hunt.time_limit", "limit of 1e+06 s"),
                 id="huge-time-limit"),
    pytest.param(edit("\nradius = 1.0", f"\nradius = {HUGE_INT}"), ("obstacles[0].radius", "limit of 1e+06 m"),
                 id="huge-integer"),
    pytest.param(edit("[hunt]", "[hunt]\ntime_step = 10.0"), ("hunt.time_step", "must not exceed time_limit"),
                 id="time-step-above-time-limit"),
    pytest.param(edit("time_limit = 5.0", "time_limit = 100.0\ntime_step = 1e-6"),
                 ("hunt.time_step", "limit of 1e+07 steps"), id="too-many-steps"),
    pytest.param(MANY_DEFENDERS, ("defenders", "21 defenders is beyond the limit of 20"), id="too-many-defenders"),
    pytest.param(MANY_OBSTACLES, ("obstacles", "101 obstacles is beyond the limit of 100"), id="too-many-obstacles"),
    pytest.param(defender(1, "start = [7.0, 6.0]", "start = [5.0, 3.0]"),
                 ("defenders[1].start", "coincides with defenders[0].start"), id="defenders-on-one-spot"),
    pytest.param(defender(0, "start = [5.0, 3.0]", "start = [5.0, 5.0]"),
                 ("defenders[0].start", "coincides with attacker.start"), id="defender-on-attacker"),
    pytest.param(edit("max_speed = 0.03", "max_speed = 0.08"), ("defenders[0].max_speed", "not faster"),
                 id="attacker-as-fast"),
    pytest.param(defender(2, "max_speed = 0.08", "max_speed = 0.02"), ("defenders[2].max_speed", "not faster"),
                 id="one-defender-slower"),
    pytest.param(defender(2, "start = [3.5, 6.5]", "start = [10.5, 10.0]"),
                 ("defenders[2].start", "inside obstacles[0]"), id="defender-inside-obstacle"),
    pytest.param(edit("start = [5.0, 5.0]", "start = [11.0, 10.0]"), ("attacker.start", "inside obstacles[0]"),
                 id="attacker-on-obstacle-boundary"),
    pytest.param(edit("arena = [0.0, 0.0, 20.0, 20.0]", "arena = [0.0, 0.0, 20.0]"),
                 ("arena", "expected four numbers"), id="arena-of-three"),
    pytest.param(edit("arena = [0.0, 0.0, 20.0, 20.0]", "arena = [20.0, 0.0, 0.0, 20.0]"),
                 ("arena", "x_min < x_max"), id="arena-inverted"),
    pytest.param(edit("arena = [0.0, 0.0, 20.0, 20.0]", "arena = [0.0, 0.0, 4.0, 4.0]"),
                 ("attacker.start", "outside the arena"), id="attacker-outside-arena"),
]

STATE = {"time": 12.5, "attacker": [5.0, 5.0], "defenders": [[5.0, 4.3], [5.6, 5.35], [4.4, 5.35]]}


def state(**changes) -> str:
    """The valid state with some keys changed (a value of None drops the key)."""
    data = {**STATE, **changes}
    return json.dumps({k: v for k, v in data.items() if v is not None})


def raw_state(old: str, new: str) -> str:
    return edit(old, new, json.dumps(STATE))


BAD_STATES = [
    pytest.param(json.dumps(STATE)[:-1] + ",}", ("not valid JSON",), id="trailing-comma"),
    pytest.param(json.dumps(STATE).replace('"', "'"), ("not valid JSON",), id="single-quotes"),
    pytest.param(json.dumps(STATE)[:-1], ("not valid JSON",), id="truncated"),
    pytest.param("", ("empty",), id="empty"),
    pytest.param("  \n\t\n", ("empty",), id="whitespace-only"),
    pytest.param(bytes(range(256)), ("not a UTF-8 text file",), id="binary-garbage"),
    pytest.param(state(note="caf\xe9").encode("latin-1").replace(b"\\u00e9", b"\xe9"), ("not a UTF-8 text file",),
                 id="latin-1"),
    pytest.param("[" * 100_000 + "]" * 100_000, ("nested too deeply",), id="nested-too-deep"),
    pytest.param(" " * (MAX_FILE_BYTES + 1), ("larger than the limit",), id="too-large"),
    pytest.param(json.dumps([STATE]), ("expected a JSON object", "list"), id="top-level-list"),
    pytest.param("42", ("expected a JSON object", "int"), id="top-level-number"),
    pytest.param('"attacker"', ("expected a JSON object", "str"), id="top-level-string"),
    pytest.param(state(speed=0.03), ("speed", "unknown key"), id="unknown-key"),
    pytest.param(state(defenders=None, defender=STATE["defenders"]), ("defender", "unknown key"),
                 id="misspelt-key"),
    pytest.param(state(**{"a\nb": 1}), ("unknown key",), id="unknown-key-with-newline"),
    pytest.param(state(attacker=None), ("attacker", "missing"), id="missing-attacker"),
    pytest.param(state(defenders=None), ("defenders", "missing"), id="missing-defenders"),
    pytest.param(json.dumps(STATE)[:-1] + ', "attacker": [1.0, 1.0]}', ("attacker", "given more than once"),
                 id="repeated-key"),
    pytest.param(state(attacker=[5.0]), ("attacker", "expected two numbers"), id="attacker-of-one"),
    pytest.param(state(attacker=[5.0, 5.0, 0.0]), ("attacker", "expected two numbers"), id="attacker-of-three"),
    pytest.param(state(attacker={"x": 5.0, "y": 5.0}), ("attacker", "expected two numbers"), id="attacker-object"),
    pytest.param(state(attacker={"position": [5.0, 5.0]}), ("attacker", "expected two numbers"),
                 id="attacker-nested-junk"),
    pytest.param(state(attacker="5.0, 5.0"), ("attacker", "expected two numbers"), id="attacker-string"),
    pytest.param(state(attacker=["5.0", "5.0"]), ("attacker", "expected two numbers"), id="attacker-strings"),
    pytest.param(state(attacker=[True, False]), ("attacker", "expected two numbers"), id="attacker-bools"),
    pytest.param(raw_state('"attacker": [5.0, 5.0]', '"attacker": null'), ("attacker", "expected two numbers"),
                 id="attacker-null"),
    pytest.param(state(defenders=STATE["defenders"][:2]), ("defenders", "expected 3 positions", "got 2"),
                 id="two-defenders"),
    pytest.param(state(defenders=STATE["defenders"] + [[1.0, 1.0]]), ("defenders", "expected 3 positions"),
                 id="four-defenders"),
    pytest.param(state(defenders=[x for p in STATE["defenders"] for x in p]), ("defenders", "got 6"),
                 id="defenders-flattened"),
    pytest.param(state(defenders={"0": [5.0, 4.3]}), ("defenders", "expected 3 positions"), id="defenders-object"),
    pytest.param(state(defenders=[[5.0, 4.3], [5.6], [4.4, 5.35]]), ("defenders[1]", "expected two numbers"),
                 id="defender-of-one"),
    pytest.param(state(defenders=[[5.0, 4.3], [5.6, 5.35], [[4.4, 5.35]]]), ("defenders[2]", "expected two numbers"),
                 id="defender-nested"),
    pytest.param(raw_state('"attacker": [5.0, 5.0]', '"attacker": [NaN, 5.0]'), ("attacker", "finite"),
                 id="nan"),
    pytest.param(raw_state("[5.0, 4.3]", "[Infinity, 4.3]"), ("defenders[0]", "finite"), id="infinity"),
    pytest.param(raw_state("[5.0, 4.3]", "[1e400, 4.3]"), ("defenders[0]", "finite"), id="overflowing-float"),
    pytest.param(state(defenders=[[5.0, 4.3], [2e6, 5.35], [4.4, 5.35]]), ("defenders[1]", "limit of 1e+06 m"),
                 id="huge-coordinate"),
    pytest.param(raw_state("[5.0, 4.3]", f"[{HUGE_INT}, 4.3]"), ("defenders[0]", "limit of 1e+06 m"),
                 id="huge-integer"),
    pytest.param(raw_state("[5.0, 4.3]", "[1" + "0" * 5000 + ", 4.3]"), ("not valid JSON", "too many digits"),
                 id="integer-with-5000-digits"),
    pytest.param(state(time="12.5"), ("time", "expected a number"), id="time-string"),
    pytest.param(state(time=-1.0), ("time", "not be negative"), id="time-negative"),
    pytest.param(raw_state('"time": 12.5', '"time": NaN'), ("time", "finite"), id="time-nan"),
    pytest.param(state(time=1e7), ("time", "limit of 1e+06 s"), id="time-huge"),
    pytest.param(state(defenders=[[10.2, 10.0], [5.6, 5.35], [4.4, 5.35]]), ("defenders[0]", "inside obstacles[0]"),
                 id="defender-inside-obstacle"),
    pytest.param(state(attacker=[10.0, 10.5]), ("attacker", "inside obstacles[0]"), id="attacker-inside-obstacle"),
    pytest.param(state(defenders=[[5.0, 4.3], [5.0, 5.0], [4.4, 5.35]]), ("defenders[1]", "coincides with attacker"),
                 id="defender-on-attacker"),
    pytest.param(state(defenders=[[5.0, 4.3], [5.6, 5.35], [5.6, 5.35]]),
                 ("defenders[2]", "coincides with defenders[1]"), id="defenders-on-one-spot"),
    pytest.param(state(attacker=[25.0, 5.0]), ("attacker", "outside the arena"), id="attacker-outside-arena"),
]


@pytest.fixture(autouse=True)
def nothing_runs(monkeypatch):
    """Bad input must be rejected before any hunt is simulated or any problem solved."""
    def forbidden(*args, **kwargs):
        raise AssertionError("bad input reached the simulator or the solver")

    for target in ("mpc_hunt.sim.simulator.simulate", "mpc_hunt.solving.solver.CaptureSolver.solve",
                   "mpc_hunt.control.strategy.HuntingStrategy",
                   "mpc_hunt.capture.problem.CaptureProblem.at_state",
                   "mpc_hunt.bench.capture_state.first_formed_circle"):
        monkeypatch.setattr(target, forbidden)


def write(path, content: str | bytes):
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8")
    return path


def one_line_error(capsys, argv: list[str], path) -> str:
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2, (code, out, err)
    assert out == ""
    assert err.endswith("\n") and err.count("\n") == 1, err
    assert "Traceback" not in err
    assert err.startswith(f"mpc-hunt {argv[0]}: error: ")
    assert str(path) in err, err
    return err


def scenario_commands(path) -> list[list[str]]:
    return [["simulate", "--scenario", str(path)], ["solve", "--scenario", str(path)],
            ["scenarios", "--write", str(path)]]


@pytest.fixture
def scenario_file(tmp_path):
    return write(tmp_path / "scenario.toml", VALID)


def test_the_valid_files_are_valid(scenario_file, tmp_path):
    scenario = load_scenario(scenario_file)
    assert scenario.arena == (0.0, 0.0, 20.0, 20.0)
    loaded = load_state(write(tmp_path / "state.json", json.dumps(STATE)), scenario)
    assert loaded.time == 12.5 and loaded.defenders.shape == (3, 2)
    save_state(loaded, tmp_path / "saved.json")   # what `solve --save-state` writes loads back
    again = load_state(tmp_path / "saved.json", scenario)
    assert again.time == loaded.time
    np.testing.assert_array_equal(again.attacker, loaded.attacker)
    np.testing.assert_array_equal(again.defenders, loaded.defenders)


@pytest.mark.parametrize("content, expected", BAD_SCENARIOS)
def test_bad_scenario_file(capsys, tmp_path, content, expected):
    path = write(tmp_path / "bad.toml", content)
    for argv in scenario_commands(path):
        err = one_line_error(capsys, argv, path)
        for text in expected:
            assert text in err, (argv[0], err)


@pytest.mark.parametrize("content, expected", BAD_STATES)
def test_bad_state_file(capsys, tmp_path, scenario_file, content, expected):
    path = write(tmp_path / "state.json", content)
    err = one_line_error(capsys, ["solve", "--scenario", str(scenario_file), "--state", str(path)], path)
    for text in expected:
        assert text in err, err


@pytest.mark.parametrize("attacker", ["apf", "noisy"])
def test_an_attacker_that_takes_none_of_the_files_settings_is_one_line(capsys, tmp_path, attacker):
    """A flee attacker's sensing_radius, which --attacker apf or noisy (sensing at R_agg) cannot take."""
    path = write(tmp_path / "flee.toml", edit("perception_radius = 1.0", 'perception_radius = 1.0\nbehaviour = "flee"\n'
                                                                       "sensing_radius = 2.0"))
    err = one_line_error(capsys, ["simulate", "--scenario", str(path), "--attacker", attacker], path)
    assert f"--attacker {attacker} on {path}: attacker.sensing_radius: the {attacker} attacker senses at its " \
           "perception_radius" in err


# --- paths that are not readable files ------------------------------------------------------------

def _unreadable(tmp_path, name: str):
    path = write(tmp_path / name, "{}")
    path.chmod(0)
    if os.access(path, os.R_OK):  # root reads anything: nothing to test
        pytest.skip("running as a user who can read a file without read permission")
    return path


NOT_A_FILE = {"directory": "a directory, not a file", "missing": "No such file", "fifo": "not a regular file",
              "unreadable": "Permission denied"}


def _not_a_file(tmp_path, name: str, kind: str):
    """A path named ``name`` that is ``kind`` (a key of NOT_A_FILE), and the error it should give."""
    path = tmp_path / name
    if kind == "directory":
        path.mkdir()
    elif kind == "fifo":
        os.mkfifo(path)
    elif kind == "unreadable":
        path = _unreadable(tmp_path, name)
    return path, NOT_A_FILE[kind]


@pytest.mark.parametrize("kind", list(NOT_A_FILE))
def test_scenario_path_that_is_not_a_readable_file(capsys, tmp_path, kind):
    path, problem = _not_a_file(tmp_path, "scenario.toml", kind)
    for argv in scenario_commands(path):
        assert problem in one_line_error(capsys, argv, path)


def test_missing_scenario_without_toml_suffix(capsys, tmp_path):
    path = tmp_path / "scenario"
    for argv in scenario_commands(path):
        assert "unknown scenario" in one_line_error(capsys, argv, path)


@pytest.mark.parametrize("kind", list(NOT_A_FILE))
def test_state_path_that_is_not_a_readable_file(capsys, tmp_path, scenario_file, kind):
    path, problem = _not_a_file(tmp_path, "state.json", kind)
    err = one_line_error(capsys, ["solve", "--scenario", str(scenario_file), "--state", str(path)], path)
    assert problem in err


# --- input that looks odd but is accepted ----------------------------------------------------------

def test_overlapping_obstacles_are_allowed(tmp_path):
    path = write(tmp_path / "overlap.toml", VALID + "\n[[obstacles]]\ncentre = [10.5, 10.0]\nradius = 1.0\n")
    assert len(load_scenario(path).obstacles) == 2


def test_a_byte_order_mark_is_accepted(tmp_path):
    path = write(tmp_path / "bom.toml", "\ufeff" + VALID)
    assert load_scenario(path).name == "bad-input"


def test_defenders_closer_than_min_separation_are_allowed(tmp_path):
    # The capture stage relaxes a violated separation to its current value (docs/model.md, E9).
    path = write(tmp_path / "close.toml", defender(1, "start = [7.0, 6.0]", "start = [5.05, 3.0]"))
    assert load_scenario(path).defenders[1].start == (5.05, 3.0)


def test_defender_outside_the_arena_is_allowed(tmp_path):
    path = write(tmp_path / "outside.toml", defender(1, "start = [7.0, 6.0]", "start = [-3.0, 6.0]"))
    assert load_scenario(path).defenders[1].start == (-3.0, 6.0)


# --- docs/robustness.md states the code's numbers --------------------------------------------------

def _numbers(text: str) -> list[float]:
    return [float(x.replace(",", "")) for x in re.findall(r"\d[\d,]*(?:\.\d+)?(?:e[+-]?\d+)?", text)]


def _table(doc: str, header: str) -> list[list[str]]:
    """The rows of the Markdown table whose header line is `header`."""
    lines = doc.splitlines()
    start = lines.index(header) + 2
    rows = []
    for line in lines[start:]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.split("|")[1:-1]])
    return rows


def _row(table: list[list[str]], name: str) -> list[str]:
    rows = [cells for cells in table if f"`{name}`" in cells]
    assert len(rows) == 1, name
    return rows[0]


def test_documented_limits_and_defaults_match_the_code():
    doc = (Path(__file__).parents[2] / "docs" / "robustness.md").read_text(encoding="utf-8")
    limits = _table(doc, "| what | limit | constant |")
    counts = _table(doc, "| count | limit | constant |")
    ranges = _table(doc, "| field | default | meaning |")
    for name, value in [("MAX_MAGNITUDE", MAX_MAGNITUDE), ("MAX_SPEED", MAX_SPEED), ("MAX_STEPS", MAX_STEPS),
                        ("MAX_DEFENDERS", MAX_DEFENDERS), ("MAX_OBSTACLES", MAX_OBSTACLES),
                        ("MAX_FILE_BYTES", MAX_FILE_BYTES)]:
        assert value in _numbers(_row(limits, name)[1]), name
    for name, value in [("MAX_HORIZON", MAX_HORIZON), ("MAX_SEED", MAX_SEED), ("MAX_STARTS", MAX_STARTS),
                        ("MAX_PROBLEMS", MAX_PROBLEMS), ("MAX_RUN_LENGTH", MAX_RUN_LENGTH),
                        ("MAX_RANDOM", MAX_RANDOM), ("MAX_HUNTS", MAX_HUNTS),
                        ("MAX_WORKERS_PER_CORE", MAX_WORKERS_PER_CORE)]:
        assert float(value) in _numbers(_row(counts, name)[1]), name
    for field in dataclasses.fields(ScenarioRanges):
        default = getattr(ScenarioRanges(), field.name)
        assert _numbers(_row(ranges, field.name)[1]) == list(np.ravel(default)), field.name

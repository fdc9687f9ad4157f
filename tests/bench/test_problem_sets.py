"""Problem sets: the file round trip, seeded selection, the builders and ``mpc-hunt problems``."""

from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import small_scenario
from mpc_hunt import Attacker, Defender, HuntParameters, Scenario, ScenarioError, builtin_names, evaluate
from mpc_hunt.bench.activity import ACTIVE_TOLERANCE, ActivityProbe
from mpc_hunt.cli.commands import main
from mpc_hunt.bench.closed_loop_states import capture_stage_observations, closed_loop_entries
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.capture.evaluator import VIOLATION_NAMES
from mpc_hunt.bench.problem_set import (ProblemSet, builtin_problem_set, dumps_problem_set, load_problem_set,
                                  problem_set_from_dict, save_problem_set)
from mpc_hunt.bench.random_states import random_entries
from scenario_text import scenario_toml


def test_the_shipped_set_round_trips_through_its_file(tmp_path):
    shipped = builtin_problem_set("default")
    text = dumps_problem_set(shipped)
    again = problem_set_from_dict(json.loads(text))
    assert again.to_dict() == shipped.to_dict() and dumps_problem_set(again) == text
    path = tmp_path / "set.json"
    save_problem_set(shipped, path)
    assert load_problem_set(path).to_dict() == shipped.to_dict()
    assert text.count("\n  {\"id\"") == len(shipped.problems)          # one problem per line
    for name in builtin_names():
        assert shipped.default_state(name) is not None


def test_the_shipped_set_has_sequences_and_every_family_active():
    shipped = builtin_problem_set("default")
    runs = shipped.sequences()
    assert len(runs) >= 2 and all(len(run) >= 2 for run in runs.values())
    for name in VIOLATION_NAMES:
        assert shipped.tagged(f"active:{name}"), name


def test_a_bad_file_names_what_is_wrong(tmp_path):
    data = builtin_problem_set("default").to_dict()
    data["problems"][0]["colour"] = 1
    with pytest.raises(ScenarioError, match=r"problems\[0\]: colour: unknown key"):
        problem_set_from_dict(data)
    data = builtin_problem_set("default").to_dict()
    data["problems"][0]["sequence"] = ["a"]
    with pytest.raises(ScenarioError, match=r"problems\[0\]: sequence: expected a string or null"):
        problem_set_from_dict(data)
    data = builtin_problem_set("default").to_dict()
    data["problems"][0]["scenario"] = ["a"]  # not a name (unhashable: once a TypeError)
    with pytest.raises(ScenarioError, match=r"problems\[0\]: scenario: \['a'\] is not among the set's scenarios"):
        problem_set_from_dict(data)
    data = builtin_problem_set("default").to_dict()
    data["problems"][1]["id"] = data["problems"][0]["id"]
    with pytest.raises(ScenarioError, match="appears more than once"):
        problem_set_from_dict(data)
    with pytest.raises(MpcHuntError, match="run_length: must be from 1 to every"):
        closed_loop_entries(small_scenario(), [], every=2, run_length=3, probe=ActivityProbe())
    path = tmp_path / "bad.json"
    path.write_text("{")
    with pytest.raises(ScenarioError, match="not valid JSON"):
        load_problem_set(path)


def test_selection_by_tag_and_by_seeded_limit_keeps_sequences_whole():
    shipped = builtin_problem_set("default")
    assert {p.id for p in shipped.select(("random",)).problems} == {p.id for p in shipped.tagged("random")}
    first = shipped.select(limit=9, rng=np.random.default_rng(3))
    again = shipped.select(limit=9, rng=np.random.default_rng(3))
    assert [p.id for p in first.problems] == [p.id for p in again.problems] and len(first.problems) <= 9
    runs = shipped.sequences()
    for sequence, members in first.sequences().items():
        assert [p.id for p in members] == [p.id for p in runs[sequence]]
    order = [p.id for p in shipped.problems]
    assert [p.id for p in first.problems] == sorted((p.id for p in first.problems), key=order.index)
    with pytest.raises(ValueError, match="rng"):
        shipped.select(limit=3)


def _drifting_scenario() -> Scenario:
    """Defenders already inside R_agg: every state is a capture-stage state, for 2 simulated seconds."""
    return Scenario(name="drift", attacker=Attacker((5.0, 5.0), (0.03, 0.0), 0.03, 1.0),
                    defenders=(Defender((5.0, 4.1), 0.08), Defender((5.8, 5.4), 0.08), Defender((4.2, 5.4), 0.08)),
                    hunt=HuntParameters(time_limit=2.0))


def test_closed_loop_runs_start_every_kth_capture_stage_state():
    scenario = _drifting_scenario()
    states = capture_stage_observations(scenario)
    assert [step for step, _ in states] == list(range(20))
    entries = closed_loop_entries(scenario, states, every=7, run_length=3, probe=ActivityProbe())
    assert [e.id for e in entries] == [f"drift/step-{k}" for k in (0, 1, 2, 7, 8, 9, 14, 15, 16)]
    assert [e.sequence for e in entries[:4]] == ["drift/run-0"] * 3 + ["drift/run-7"]
    assert all("closed-loop" in e.tags for e in entries)


def test_random_states_are_seeded_feasible_and_make_their_family_active():
    template = small_scenario(obstacles=())
    scenarios, entries = random_entries(template, 1, np.random.default_rng(5))
    again = random_entries(template, 1, np.random.default_rng(5))[1]
    assert [e.state.to_dict() for e in entries] == [e.state.to_dict() for e in again]
    problems = ProblemSet(scenarios, tuple(entries))
    probe = ActivityProbe()
    for entry, case in zip(entries, VIOLATION_NAMES):
        assert f"case:{case}" in entry.tags and f"active:{case}" in entry.tags
        problem = problems.problem(entry)
        held = evaluate(problem, problem.held_plan())   # every inequality holds where the defenders stand
        assert all(held.violation[name] == 0.0 for name in VIOLATION_NAMES if name != "equal_distance")
        assert evaluate(problem, probe.optimum(problem)).max_violation <= ACTIVE_TOLERANCE


TINY = scenario_toml("tiny", [(5, 4.1), (5.8, 5.4), (4.2, 5.4)], time_limit=2.0)


def test_the_problems_command_lists_describes_and_builds(capsys, tmp_path):
    assert main(["problems"]) == 0
    assert capsys.readouterr().out.startswith("default: ")
    assert main(["problems", "default"]) == 0
    out = capsys.readouterr().out
    assert "paper-obstacles/default: scenario paper-obstacles" in out and "tag closed-loop:" in out
    scenario = tmp_path / "tiny.toml"
    scenario.write_text(TINY)
    target = tmp_path / "built.json"
    assert main(["problems", "--build", str(target), "--scenario", str(scenario), "--every", "10",
                 "--run-length", "2", "--random", "0"]) == 0
    built = load_problem_set(target)
    assert [p.id for p in built.problems] == ["tiny/default", "tiny/step-0", "tiny/step-1", "tiny/step-10",
                                              "tiny/step-11"]
    assert main(["problems", "nowhere.json"]) == 2
    assert "problems: error: " in capsys.readouterr().err

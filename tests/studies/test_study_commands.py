"""The studies are commands like ``mpc-hunt``: --help, a bad argument or output path in one line with exit status 2
before any work, counts that cannot run refused up front, a study that ran nothing not successful, and training
keeping its finished generations through Ctrl-C.

Only the argument paths run here (milliseconds each); the studies' runs are their --check's business
(tests/test_committed_results.py).
"""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

def _source(name: str) -> str:
    return (ROOT / "studies" / f"{name}.py").read_text(encoding="utf-8")


STUDIES = sorted(p.stem for p in (ROOT / "studies").glob("*.py") if '\nif __name__ == "__main__":\n' in _source(p.stem))
WRITING = [n for n in STUDIES if 'add_argument("--output"' in _source(n) or "add_study_options(parser" in _source(n)]


def study(name: str):
    return importlib.import_module(f"studies.{name}")


def usage_error(capsys, name: str, argv: list[str]) -> str:
    """``main(argv)`` of the study must stop with exit status 2 and one line on stderr, before any work."""
    with pytest.raises(SystemExit) as exc:
        study(name).main(argv)
    err = capsys.readouterr().err
    assert exc.value.code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


@pytest.mark.parametrize("name", STUDIES)
def test_help(name, capsys):
    with pytest.raises(SystemExit) as exc:
        study(name).main(["--help"])
    assert exc.value.code == 0 and "usage:" in capsys.readouterr().out


@pytest.mark.parametrize("name", STUDIES)
def test_a_bad_argument_is_one_line_from_the_script(name):
    run = subprocess.run([sys.executable, str(ROOT / "studies" / f"{name}.py"), "--no-such-option"],
                         capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert run.returncode == 2 and run.stdout == ""
    assert run.stderr == f"{name}.py: error: unrecognized arguments: --no-such-option (see --help)\n"


def _bad_outputs(tmp_path: Path) -> dict[str, str]:
    a_file = tmp_path / "a-file"
    a_file.write_text("x")
    read_only = tmp_path / "read-only"
    read_only.mkdir()
    read_only.chmod(0o500)
    cases = {"a file": str(a_file), "missing parent": str(tmp_path / "nowhere" / "out"), "empty": ""}
    if not os.access(read_only, os.W_OK):          # root writes anywhere
        cases["read-only parent"] = str(read_only / "out")
    if Path("/proc/self").is_dir():                 # nobody, root included, creates a file there
        cases["unwritable parent"] = "/proc/mpc-hunt-out"
    return cases


@pytest.mark.parametrize("name", WRITING)
def test_a_bad_output_folder_is_refused_before_any_work(name, capsys, tmp_path, monkeypatch):
    module = study(name)
    for attribute in ("run", "train", "train_side", "study", "run_sweep", "hunt_indices", "timed_sizes",
                      "hunt_states"):
        if hasattr(module, attribute):       # any work at all fails the test
            monkeypatch.setattr(module, attribute, lambda *a, **k: pytest.fail("work started"))
    for why, path in _bad_outputs(tmp_path).items():
        err = usage_error(capsys, name, ["--output", path])
        assert "argument --output" in err, (why, err)
    assert not (tmp_path / "nowhere").exists()


def test_train_attacker_refuses_a_weights_file_it_cannot_write(capsys, tmp_path):
    for path in (tmp_path, tmp_path / "nowhere" / "w.json", ""):
        assert "argument --weights" in usage_error(capsys, "train_attacker", ["--weights", str(path)])


@pytest.mark.parametrize("name,argv,message", [
    ("team_size", ["--states", "1"], "--states: at least 2"),
    ("step_latency", ["--states", "1"], "--states: at least 2"),
    ("train_attacker", ["--population", "3"], "--population: at least 4"),
])
def test_counts_that_cannot_run_are_refused_up_front(name, argv, message, capsys, tmp_path, monkeypatch):
    module = study(name)
    for attribute in ("run", "train", "timed_sizes", "hunt_states"):
        if hasattr(module, attribute):
            monkeypatch.setattr(module, attribute, lambda *a, **k: pytest.fail("work started"))
    err = usage_error(capsys, name, argv + (["--output", str(tmp_path / "out")] if name in WRITING else []))
    assert message in err
    assert not (tmp_path / "out").exists()


def test_the_attackers_study_takes_the_first_reachable_draws_and_refuses_a_seed_with_none(capsys, tmp_path,
                                                                                         monkeypatch):
    attackers = study("attackers")
    from mpc_hunt.sweep.random_scenario import ScenarioRanges, sweep_scenario
    from mpc_hunt.sweep.reachability import reachable
    first = [i for i in range(12) if reachable(sweep_scenario(1, i, ScenarioRanges()))][:3]
    assert len(first) == 3 and attackers.hunt_indices(3, 1) == first
    monkeypatch.setattr(attackers, "reachable", lambda scenario: False)
    monkeypatch.setattr(attackers, "run", lambda *a, **k: pytest.fail("work started"))
    err = usage_error(capsys, "attackers", ["--hunts", "2", "--output", str(tmp_path / "out")])
    assert "none of the first 40 draws of --seed 1 is reachable" in err
    assert not (tmp_path / "out").exists()


def test_a_sweep_study_that_ran_nothing_does_not_succeed(tmp_path, capsys, monkeypatch):
    sweep_study = study("sweep_study")
    assert sweep_study.run_file(tmp_path / "empty.db", {"strategies": ["apf"]}, []) == sweep_study.NOTHING_RAN
    attackers = study("attackers")
    monkeypatch.setattr(attackers, "hunt_indices", lambda hunts, seed: [0])
    monkeypatch.setattr(attackers, "todo", lambda indices, seed: [])        # as if every draw ran nothing
    monkeypatch.setattr(attackers, "write", lambda *a, **k: pytest.fail("tables written from no hunt"))
    assert attackers.main(["--hunts", "1", "--output", str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err.endswith(f"error: {sweep_study.NOTHING_RAN}\n")


hunts = None        # the last training's FakeHunts

# Training, with the hunts replaced by a quick fitness of the weights: what is kept through Ctrl-C, and resumed.
class FakeHunts:
    """``run_local`` for train_attacker: a candidate's fitness is a fixed function of its weights; Ctrl-C at the
    start of generation ``stop`` (counted from 0; None: never)."""

    def __init__(self, stop: int | None):
        self.stop, self.generation = stop, 0

    def __call__(self, tasks, work, workers):
        if self.generation == self.stop:
            self.stop = None
            raise KeyboardInterrupt
        self.generation += 1
        for t in tasks:
            w = np.array(t.weights)
            yield {"candidate": t.candidate, "episode": t.index, "fitness": float(np.tanh(w.sum() + 0.1 * t.index))}


def _train(module, monkeypatch, folder: Path, stop: int | None, *extra: str) -> int:
    global hunts
    hunts = FakeHunts(stop)
    monkeypatch.setattr(module, "training_hunt", lambda generation, index: None)
    monkeypatch.setattr(module, "run_local", hunts)
    monkeypatch.setattr(module, "describe_machine", lambda: {"cpu": "test"})
    monkeypatch.setattr(module, "machine_lines", lambda machine: [])
    return module.main(["--generations", "4", "--population", "4", "--episodes", "2", "--output", str(folder),
                        "--weights", str(folder.parent / f"{folder.name}.json"), *extra])


def test_training_keeps_its_finished_generations_through_ctrl_c_and_resumes(monkeypatch, tmp_path, capsys):
    module = study("train_attacker")
    whole, stopped = tmp_path / "whole", tmp_path / "stopped"
    assert _train(module, monkeypatch, whole, None) == 0
    assert not (whole / module.PROGRESS).exists()               # a finished training leaves no progress file
    capsys.readouterr()
    assert _train(module, monkeypatch, stopped, 2) == 130
    assert "2 finished generations kept" in capsys.readouterr().err
    kept = module.read_progress(stopped / module.PROGRESS, None)
    assert [g["curve"]["generation"] for g in kept] == [0, 1] and not (tmp_path / "stopped.json").exists()
    with pytest.raises(SystemExit) as exc:                       # without --resume, the kept work is not overwritten
        _train(module, monkeypatch, stopped, None)
    assert exc.value.code == 2 and "--resume" in capsys.readouterr().err
    assert _train(module, monkeypatch, stopped, None, "--resume") == 0
    assert hunts.generation == 2                                 # the two kept generations are not run again
    resumed = json.loads((tmp_path / "stopped.json").read_text())["weights"]
    assert resumed == json.loads((tmp_path / "whole.json").read_text())["weights"]     # as if never stopped
    curve = json.loads((stopped / "results.json").read_text())["curve"]
    assert [c["generation"] for c in curve] == [0, 1, 2, 3]


def test_a_resumed_training_needs_the_same_settings(monkeypatch, tmp_path, capsys):
    module = study("train_attacker")
    assert _train(module, monkeypatch, tmp_path / "out", 1) == 130
    capsys.readouterr()
    err = usage_error(capsys, "train_attacker", ["--population", "5", "--output", str(tmp_path / "out"), "--resume"])
    assert "other settings" in err


@pytest.mark.parametrize("failure,code,message", [
    (lambda: (_ for _ in ()).throw(__import__("mpc_hunt.errors").errors.MpcHuntError("bad\ninput")), 2,
     "error: bad input"),
    (lambda: open("/nonexistent/results.json", "w"), 2, "error: /nonexistent/results.json: No such file"),
    (lambda: (_ for _ in ()).throw(KeyboardInterrupt), 130, "interrupted"),
])
def test_a_study_that_fails_at_run_time_says_so_in_one_line(failure, code, message, capsys):
    assert study("study_check").run_study(failure) == code
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


@pytest.mark.parametrize("content", ["", "{not json", '{"elapsed_s": "soon"}', "[]"])
def test_train_ppo_refuses_a_damaged_checkpoint_in_one_line(content, tmp_path):
    pytest.importorskip("stable_baselines3", reason="Stable-Baselines3 is the optional extra learn")
    folder = tmp_path / "out" / "checkpoint" / "team"
    folder.mkdir(parents=True)
    (folder / "progress.json").write_text(content)
    run = subprocess.run([sys.executable, str(ROOT / "studies" / "train_ppo.py"), "--side", "team", "--resume",
                          "--output", str(tmp_path / "out")], capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert run.returncode == 2 and run.stderr.count("\n") == 1 and "Traceback" not in run.stderr
    assert "progress.json: not a training's progress" in run.stderr


def test_the_realtime_study_resumes_from_whole_lines_only(tmp_path, monkeypatch, capsys):
    module = study("realtime")
    progress = tmp_path / "hunts.jsonl"
    hunt = {"formulation": "qp", "backend": "osqp", "horizon": 5, "scenario": "paper-open",
            "past_limit_on_cpu": 0, "past_limit_stolen": 0}
    older = {k: v for k, v in hunt.items() if k != "past_limit_stolen"} | {"horizon": 1}
    lines = [json.dumps(hunt), json.dumps(older), "[1, 2]", json.dumps(hunt | {"horizon": 10})[:25]]
    progress.write_text("\n".join(lines), encoding="utf-8")
    monkeypatch.setattr(module, "PROGRESS", progress)
    assert list(module.finished()) == ["qp:osqp N=5 paper-open"]    # an older version's, another's, a cut line: rerun
    usage_error(capsys, "realtime", ["--workers", "3"])
    assert "not allowed with" in usage_error(capsys, "realtime", ["--check", "--fresh"])   # a check forgets nothing


def test_the_realtime_study_rewritten_without_a_hunt_keeps_the_machine_its_hunts_ran_on(tmp_path, monkeypatch):
    module = study("realtime")
    monkeypatch.setattr(module, "OUT", tmp_path)
    now = {"cpu": "this one"}
    assert module.run_machine(now) is now                             # nothing committed
    ran = {"cpu": "the run's", "load_average": [3.0, 2.0, 1.0]}
    (tmp_path / "results.json").write_text(json.dumps({"settings": module.settings(), "machine": ran}))
    assert module.run_machine(now) == ran
    other = module.settings() | {"budget_s": 0.05}
    (tmp_path / "results.json").write_text(json.dumps({"settings": other, "machine": ran}))
    assert module.run_machine(now) is now                             # another run's
    (tmp_path / "results.json").write_text("{cut")
    assert module.run_machine(now) is now


@pytest.mark.parametrize("folder,content,message", [
    ("missing", None, "states.json: no such file"),
    ("empty", None, "states.json: no such file"),
    ("damaged", "{not json", "states.json: not valid JSON"),
    ("damaged", "[1, 2]", "states.json: expected a JSON object of team sizes"),
    ("damaged", '{"3": [{"attacker": [1, 2]}, {"attacker": [1, 2]}]}', "team size 3, state 0: defenders: missing"),
])
def test_team_size_refuses_states_it_cannot_reuse_in_one_line(folder, content, message, tmp_path, monkeypatch,
                                                               capsys):
    module = study("team_size")
    monkeypatch.setattr(module, "timed_sizes", lambda *a, **k: pytest.fail("work started"))
    out = tmp_path / folder
    if folder != "missing":
        out.mkdir()
    if content is not None:
        (out / "states.json").write_text(content)
    assert module.main(["--reuse-states", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "without --reuse-states" in err, err


def test_team_size_check_of_a_missing_folder_is_one_line(tmp_path, capsys):
    out = tmp_path / "missing"
    assert study("team_size").main(["--check", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == f"error: {out / 'results.json'}: no such file; run python studies/team_size.py --output {out} to " \
                  "make the results to check\n"


@pytest.mark.parametrize("content,message", [
    ("{}", "rounds: expected a list of objects"),
    ("[]", "expected a JSON object with 'rounds' and 'growth'"),
    ('{"rounds": [{"size": 3}], "growth": []}', "rounds[0]: no 'scheme'"),
    ('{"rounds": [], "growth": [{"size": "3", "robot_plan_difference_m": 0}]}', "growth[0]: size"),
])
def test_team_size_check_of_results_of_another_shape_is_one_line(content, message, tmp_path, capsys):
    out = tmp_path / "wrong"
    out.mkdir()
    (out / "results.json").write_text(content)
    assert study("team_size").main(["--check", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "to make the results to check" in err, err


def test_the_sweep_study_refuses_a_strategy_that_cannot_be_built_before_its_results_file(monkeypatch, tmp_path):
    from dataclasses import replace

    from mpc_hunt.control import ppo_team
    from mpc_hunt.errors import SettingError

    module = study("sweep")
    bad = tmp_path / "team.npz"
    bad.write_bytes(b"not a network\n")
    monkeypatch.setattr(ppo_team, "TEAM_POLICY", replace(ppo_team.TEAM_POLICY, name=str(bad)))
    monkeypatch.setattr(module, "arguments", lambda: {"strategies": ["ppo"]})
    monkeypatch.setattr(module, "SweepStore", lambda *a, **k: pytest.fail("the sweep's file was opened"))
    with pytest.raises(SettingError, match="ppo cannot be built"):
        module.run_sweep()


SWEEPING = [n for n in STUDIES if "add_study_options(parser" in _source(n)]


@pytest.mark.parametrize("name", SWEEPING)
@pytest.mark.parametrize("workers", ["0", "-1", "2.5", "1000000"])
def test_a_sweep_study_refuses_a_workers_count_it_cannot_run_in_one_line(name, workers, capsys):
    assert "--workers" in usage_error(capsys, name, ["--workers", workers])


@pytest.mark.parametrize("name", SWEEPING)
def test_a_sweep_study_hands_its_workers_to_the_sweep(name, monkeypatch, tmp_path):
    module, seen = study(name), []
    monkeypatch.setattr(module, "run_file", lambda db, arguments, hunts, workers=None: seen.append(workers) or "stop")
    module.main(["--hunts", "1", "--workers", "1", "--output", str(tmp_path / "out")])
    assert seen and set(seen) == {1}

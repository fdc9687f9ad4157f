"""The command line: every command's --help, its output, and one-line errors."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import numpy as np

from mpc_hunt.cli.commands import main
from mpc_hunt.bench.problem_set import builtin_problem_set
from mpc_hunt.control.spec import make_controller
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.world.behaviours import with_behaviour
from mpc_hunt.world.belief import parse_belief
from mpc_hunt.world.scenario_io import builtin_scenario, load_scenario
from scenario_text import scenario_toml

TINY = scenario_toml("tiny", [(5, 3), (7, 6), (3.5, 6.5)], time_limit=5.0)


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("command", [[], ["simulate"], ["solve"], ["scenarios"], ["backends"], ["compare"],
                                     ["problems"], ["sweep"], ["sweep-report"]])
def test_help(command):
    with pytest.raises(SystemExit) as exc:
        main(command + ["--help"])
    assert exc.value.code == 0


def test_scenarios_list_and_write(capsys, tmp_path):
    code, out, _ = run(capsys, "scenarios")
    assert code == 0 and "paper-open" in out and "paper-obstacles (default)" in out
    target = tmp_path / "open.toml"
    code, out, _ = run(capsys, "scenarios", "--write", "paper-open", "--output", str(target))
    assert code == 0 and load_scenario(target) == builtin_scenario("paper-open")
    code, out, _ = run(capsys, "scenarios", "--write", "paper-obstacles")
    assert code == 0 and 'name = "paper-obstacles"' in out


def test_simulate_json_on_a_scenario_file(capsys, tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    code, out, err = run(capsys, "simulate", "--scenario", str(path), "--json")
    assert code == 0, err
    report = json.loads(out)
    for key in ("captured", "capture_time_s", "path_lengths_m", "final_hunting_radius_m",
                "min_obstacle_clearance_m", "min_defender_separation_m", "steps", "solve_time",
                "failed_solves", "fallbacks"):
        assert key in report
    assert report["captured"] is False and report["capture_time_s"] is None
    assert report["min_obstacle_clearance_m"] is None and report["steps"] == 50
    assert len(report["path_lengths_m"]) == 3


@pytest.mark.parametrize("controller, attacker, belief, seed, other", [
    ("apf", "gap", "exact", None, []),                                        # other: the scenario's own attacker
    ("enclose", "noisy", "intent_heading=60,eta=2x", 3, ["--seed", "4"]),     # other: another seed
])
def test_simulate_runs_the_attacker_and_belief_it_is_given(capsys, tmp_path, controller, attacker, belief, seed,
                                                           other):
    """As the Python API with the world's generator default_rng(seed), the belief's child 0 of SeedSequence(seed)."""
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    base = ["simulate", "--scenario", str(path), "--json", "--controller", controller]
    flags = ["--attacker", attacker, "--belief", belief] + ([] if seed is None else ["--seed", str(seed)])
    code, out, err = run(capsys, *base, *flags)
    assert code == 0, err
    scenario = with_behaviour(load_scenario(path), attacker)
    seed = seed or 0
    solver = {} if controller == "apf" else {"formulation": "rti", "backend": "hpipm", "horizon": 10}
    controller = make_controller(controller, scenario, belief=parse_belief(belief),
                                 rng=np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0]), **solver)
    expected = json.loads(json.dumps(simulate(scenario, controller, rng=np.random.default_rng(seed)).to_dict()))
    assert json.loads(out) | {"solve_time": None} == expected | {"solve_time": None}
    _, out, _ = run(capsys, *base, *(flags[:4] + other if other else []))
    assert json.loads(out)["path_lengths_m"] != expected["path_lengths_m"]


def test_simulate_scores_the_control_loops_plans_only_when_asked(capsys, tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    reports = []
    for flags in ((), ("--score",)):
        code, out, err = run(capsys, "simulate", "--scenario", str(path), "--json", *flags)
        assert code == 0, err
        reports.append(json.loads(out) | {"solve_time": None})
    assert reports[0] == reports[1]                 # no failed step: the evaluator changes no decision
    code, _, err = run(capsys, "simulate", "--controller", "voronoi", "--score")
    assert code == 2 and "--score: controller 'voronoi' solves no capture problem" in err


def test_simulate_summary_with_qp_and_plot(capsys, tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    figure = tmp_path / "hunt.png"
    code, out, err = run(capsys, "simulate", "--scenario", str(path), "--formulation", "qp",
                         "--backend", "clarabel", "--horizon", "3", "--no-prediction", "--plot", str(figure))
    assert code == 0, err
    assert "qp on clarabel, horizon 3" in out and "prediction off" in out
    assert figure.stat().st_size > 0


def test_solve_at_a_state_file(capsys, tmp_path):
    state = tmp_path / "state.json"
    state.write_text(json.dumps({"attacker": [4.0, 11.0],
                                 "defenders": [[4.0, 10.3], [4.6, 11.35], [3.4, 11.35]]}))
    for formulation, backend in (("nlp", "ipopt"), ("qp", "osqp"), ("qp", "clarabel")):
        code, out, err = run(capsys, "solve", "--scenario", "paper-open", "--state", str(state),
                             "--formulation", formulation, "--backend", backend, "--json")
        assert code == 0, err
        report = json.loads(out)
        assert report["status"] == "optimal"
        assert (report["formulation"], report["backend"]) == (formulation, backend)
        assert set(report["violation"]) >= {"motion_limit", "equal_distance", "obstacle_safety", "separation"}
        assert report["objective"] > 0 and report["solve_time_s"] > 0 and report["iterations"] > 0
        assert len(report["plan"]) == 1 and len(report["plan"][0]) == 3


@pytest.mark.parametrize("argv,message", [
    (["simulate", "--scenario", "nowhere"], "unknown scenario 'nowhere'"),
    (["simulate", "--horizon", "0"], "--horizon: must be at least 1"),
    (["simulate", "--formulation", "lp"], "invalid choice: 'lp'"),
    (["solve", "--formulation", "qp", "--backend", "ipopt"], "does not solve formulation 'qp'"),
    (["solve", "--time-limit", "nan"], "--time-limit: must be a positive finite number"),
    (["scenarios", "--output", "x.toml"], "--output needs --write"),
    (["simulate", "--controller", "enclose", "--formulation", "distributed", "--time-limit", "0.05"],
     "--time-limit: backend daqp-condensed takes none (its step is one call that nothing can stop); bound it with "
     "--max-iter, drop --time-limit or pick another backend"),
    (["compare", "--objective", "enclose", "--pair", "distributed:daqp-condensed", "--time-limit", "0.1"],
     "--time-limit: backend daqp-condensed takes none; leave it out of the pairs, or drop --time-limit"),
    (["compare", "--pair", "distributed"], "--pair: distributed: formulation distributed poses the enclose "
                                           "objective, not the paper objective (pick another formulation, or "
                                           "another --objective)"),
    (["problems", "--build", "x.json", "--scenario", "two-defenders"],
     "--random: random states need at least 3 defenders; the first scenario, two-defenders, has 2: give 0, or put "
     "another scenario first"),
    (["compare", "--seed", "-1"], "--seed: must not be negative"),
    (["problems", "--build", "x.json", "--seed", "-1"], "--seed: must not be negative"),
    (["simulate", "--attacker", "nobody"], "invalid choice: 'nobody' (choose from 'apf', 'flee', 'gap', 'voronoi', "
                                           "'noisy', 'learned', 'minimax', 'ppo')"),
    (["sweep", "--attacker", "apf", "--attacker", "gapp"], "invalid choice: 'gapp' (choose from 'apf', 'flee', "),
    (["simulate", "--belief", "colour=2x"], "--belief: belief 'colour=2x': expected NAME=VALUE with NAME one of eta, "
                                            "intent_heading, perception_radius"),
    (["sweep", "--belief", "exact", "--belief", "eta=fast"], "--belief: belief 'eta=fast': eta's value 'fast' is "
                                                              "not a number"),
    (["sweep", "--belief", "eta=0x"], "--belief: belief.eta: must be positive"),
    (["simulate", "--belief", "intent_heading=200"], "--belief: belief.intent_heading"),
    (["simulate", "--seed", "-1"], "--seed: must not be negative"),
    (["simulate", "--seed", str(2**63)], "--seed: at most 9223372036854775807"),
])
def test_bad_arguments_are_one_line(capsys, argv, message):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own errors exit
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2
    assert message in err and err.count("\n") == 1 and "Traceback" not in err


@pytest.mark.parametrize("content,message", [
    ("name = 'x'\n[attacker]\nstart = [1, 2]\n", "attacker.max_speed: missing"),
    ("this is not toml", "not valid TOML"),
    (TINY.replace("max_speed = 0.08", "max_speed = 0.01", 1), "defenders[0].max_speed"),
    (TINY + "\n[[obstacles]]\ncentre = [5.0, 3.0]\nradius = 0.5\n", "defenders[0].start"),
    (TINY.replace("[hunt]", "[hunt]\ncolour = 1"), "hunt.colour: unknown key"),
])
def test_bad_scenario_files_are_one_line(capsys, tmp_path, content, message):
    path = tmp_path / "bad.toml"
    path.write_text(content)
    code, out, err = run(capsys, "simulate", "--scenario", str(path))
    assert code == 2 and out == ""
    assert message in err and err.count("\n") == 1


def test_bad_state_file_is_one_line(capsys, tmp_path):
    state = tmp_path / "state.json"
    state.write_text(json.dumps({"attacker": [4.0, 11.0], "defenders": [[4.0, 10.3]]}))
    code, _, err = run(capsys, "solve", "--scenario", "paper-open", "--state", str(state))
    assert code == 2 and "defenders: expected 3 positions" in err and err.count("\n") == 1


def test_console_script_runs_without_traceback():
    result = subprocess.run([sys.executable, "-m", "mpc_hunt.cli", "simulate", "--scenario", "missing.toml"],
                            capture_output=True, text=True)
    assert result.returncode == 2 and "Traceback" not in result.stderr


@pytest.mark.parametrize("option,name,message", [
    ("--plot", "missing-folder/hunt.png", "does not exist"),
    ("--plot", "hunt.xyz", "extension '.xyz' (use .png, .pdf, .svg)"),
    ("--plot", "hunt", "no extension"),
    ("--plot", ".", "is a directory"),
    ("--animate", "hunt.png", "(use .gif)"),
])
def test_a_bad_output_path_is_refused_before_the_hunt(capsys, tmp_path, option, name, message):
    target = tmp_path / name if name != "." else tmp_path.parent / (tmp_path.name + ".png")
    if name == ".":
        target.mkdir()
    code, out, err = run(capsys, "simulate", option, str(target))
    assert code == 2 and out == "" and err.count("\n") == 1
    assert message in err and option in err


def test_version_and_backends(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.startswith("mpc-hunt ")
    code, out, _ = run(capsys, "backends")
    assert code == 0 and "backend daqp (accepts qp): installed" in out
    assert "formulation socp (emits socp; default backend clarabel): clarabel, cvxpy" in out


def test_the_apf_baseline_runs_without_optimisation(capsys):
    code, out, err = run(capsys, "simulate", "--scenario", "paper-open", "--controller", "apf", "--json")
    assert code == 0, err
    report = json.loads(out)
    assert report["controller"] == "apf" and report["solve_time"]["count"] == 0
    code, _, err = run(capsys, "simulate", "--controller", "apf", "--horizon", "3")
    assert code == 2 and "--horizon: controller 'apf' solves no capture problem" in err


def test_solve_defaults_use_the_shipped_state(capsys):
    code, out, err = run(capsys, "solve", "--formulation", "qp", "--backend", "daqp", "--json")
    assert code == 0, err
    report = json.loads(out)
    assert report["status"] == "optimal" and report["scenario"] == "paper-obstacles"
    shipped = builtin_problem_set("default").default_state("paper-obstacles")
    assert report["state"] == shipped.to_dict()
    code, out, _ = run(capsys, "solve", "--formulation", "qp", "--backend", "clarabel", "--json")
    # Measured: 3.9e-8; Eq. 14's penalty (w_eq / R_hunt² = 4e3) magnifies the backends' ~1e-11 m differences.
    assert json.loads(out)["objective"] == pytest.approx(report["objective"], rel=1e-6)


@pytest.mark.parametrize("flags, expected", [
    ([], ("trap", "rti", "hpipm", 10)),                                    # the recommended controller
    (["--controller", "paper"], ("paper", "rti", "hpipm", 10)),           # the paper's strategy, one flag away
    (["--controller", "paper", "--formulation", "nlp"], ("paper", "nlp", "ipopt", 1)),   # as published
    (["--formulation", "qp", "--backend", "daqp"], ("trap", "qp", "daqp", 1)),
    (["--horizon", "2"], ("trap", "rti", "hpipm", 2)),
])
def test_simulate_runs_the_recommended_controller_unless_told(capsys, tmp_path, flags, expected):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY.replace("time_limit = 5.0", "time_limit = 0.2"), encoding="utf-8")
    code, out, _ = run(capsys, "simulate", "--scenario", str(path), "--json", *flags)
    report = json.loads(out)
    assert code == 0 and (report["controller"], report["formulation"], report["backend"],
                          report["horizon"]) == expected


def test_solve_runs_the_papers_problem_by_default(capsys):
    code, out, _ = run(capsys, "solve", "--scenario", "paper-open", "--json")
    report = json.loads(out)
    assert (report["formulation"], report["backend"], report["horizon"]) == ("nlp", "ipopt", 1)


def test_solve_holds_a_failed_defender_where_it_stands(capsys, tmp_path):
    """After its fails_at, a defender inside R_agg is not planned to move (failed-defender: defender 2 at 100 s)."""
    state = tmp_path / "state.json"
    state.write_text(json.dumps({"time": 150.0, "attacker": [10.0, 10.0],
                                 "defenders": [[10.0, 9.3], [10.6, 10.35], [9.4, 10.35]]}))
    code, out, err = run(capsys, "solve", "--scenario", "failed-defender", "--state", str(state), "--json")
    assert code == 0, err
    plan = json.loads(out)["plan"]
    assert plan[0][2] == [9.4, 10.35] and plan[0][0] != [10.0, 9.3]


def test_simulate_reports_its_budget_hits_deadline_misses_and_certificates(capsys, tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    code, out, err = run(capsys, "simulate", "--scenario", str(path), "--json", "--max-iter", "1",
                         "--deadline", "1e-9")
    assert code == 0, err
    report = json.loads(out)
    count = report["solve_time"]["count"]
    assert count > 0 and report["budget_hits"] == report["failed_solves"] == count   # HPIPM stops after 1 iteration
    assert report["solve_time"]["deadline_misses"]["over_deadline"] == count         # nothing meets a nanosecond
    assert report["solve_time"]["deadline_misses"]["deadline_s"] == 1e-9
    assert set(report["certificate_max"]) == {"primal_residual", "dual_residual", "duality_gap"}
    code, out, _ = run(capsys, "simulate", "--scenario", str(path))
    assert code == 0 and "than the deadline" not in out and "budget hits 0" in out

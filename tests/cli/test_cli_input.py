"""Input the command line and the sweep take: a belief's names, a seed's bound, solver chatter, a strategy's
defaults, the sweep's size, and the shipped data files (learned weights, problem sets) checked when loaded."""

from __future__ import annotations

import json
import tracemalloc
from pathlib import Path

import pytest

from mpc_hunt.arguments import MAX_SEED
from mpc_hunt.bench.problem_set import builtin_problem_set, load_problem_set
from mpc_hunt.cli import commands
from mpc_hunt.cli.commands import build_parser, main
from mpc_hunt.cli.common import messages
from mpc_hunt.control.controllers import SOLVING
from mpc_hunt.control.recommended import RECOMMENDED
from mpc_hunt.errors import DataFileError, MpcHuntError
from mpc_hunt.sweep.random_scenario import ScenarioRanges
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.sweep.runner import MAX_TASKS, run_local, tasks
from mpc_hunt.world.behaviours import DEFAULT_BEHAVIOUR, learned
from mpc_hunt.world.belief import parse_belief
from scenario_text import scenario_toml

TINY = scenario_toml("tiny", [(5, 3), (7, 6), (3.5, 6.5)], time_limit=5.0)


def one_line_error(capsys, argv) -> str:
    """Run the command line; it must fail with exit status 2 and one line on stderr, which is returned."""
    try:
        code = main(argv)
    except SystemExit as exc:      # argparse's own errors exit
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


@pytest.mark.parametrize("spec", ["eta=3x,eta=5x", "perception_radius=1.3x,eta=2x, perception_radius=1.5x"])
def test_a_belief_naming_a_parameter_twice_is_refused(capsys, spec):
    with pytest.raises(MpcHuntError, match="given twice"):
        parse_belief(spec)
    for command in ("simulate", "sweep"):
        assert "given twice" in one_line_error(capsys, [command, "--belief", spec])


@pytest.mark.parametrize("digits", [20, 5000])
@pytest.mark.parametrize("sign", ["", "-"])
def test_a_seed_of_many_digits_is_told_the_bound(capsys, digits, sign):
    err = one_line_error(capsys, ["simulate", "--seed", sign + "9" * digits])
    rule = "must not be negative" if sign else f"at most {MAX_SEED}"
    assert rule in err and f"{digits} digits" in err and len(err) < 300


def _chatty(args) -> int:
    """A command whose solver warns as CasADi does (on the Python stderr of the moment), then says something of its
    own."""
    import casadi

    x = casadi.MX.sym("x")
    solver = casadi.nlpsol("chatty", "ipopt", {"x": x, "f": casadi.sqrt(x - 1)},
                           {"ipopt.print_level": 0, "print_time": 0, "ipopt.sb": "yes"})
    solver(x0=0)                          # NaN in the gradient: CasADi warns on stderr
    print("the command's own message", file=messages())
    return 0


def test_solver_chatter_reaches_stderr_only_with_verbose(capsys, monkeypatch):
    monkeypatch.setattr(commands, "_backends", _chatty)
    assert main(["backends"]) == 0
    err = capsys.readouterr().err
    assert err == "the command's own message\n"
    assert main(["backends", "--verbose"]) == 0
    err = capsys.readouterr().err
    assert "CasADi" in err and "NaN detected" in err and err.endswith("the command's own message\n")


def _simulate_settings(*flags: str) -> dict:
    args = build_parser().parse_args(["simulate", *flags])
    spec = commands._controller_spec(args)
    return {"formulation": spec.formulation, "backend": spec.backend, "horizon": spec.horizon}


@pytest.mark.parametrize("controller", SOLVING)
@pytest.mark.parametrize("fields,flags", [
    ("", []), (":qp", ["--formulation", "qp"]), (":rti", ["--formulation", "rti"]),
    (":::3", ["--horizon", "3"]), (":qp:daqp", ["--formulation", "qp", "--backend", "daqp"]),
])
def test_a_sweep_strategy_runs_what_simulate_runs_for_the_same_controller(controller, fields, flags):
    strategy = ControllerSpec.parse(controller + fields)
    settings = _simulate_settings("--controller", controller, *flags)
    assert {"formulation": strategy.formulation, "backend": strategy.backend, "horizon": strategy.horizon} == settings
    if not fields:
        assert settings == RECOMMENDED


def test_a_sweep_strategy_horizon_has_the_command_lines_bounds(capsys):
    for bad in ("0", "201", "x", "9" * 5000):
        with pytest.raises(MpcHuntError) as exc:
            ControllerSpec.parse(f"enclose:rti:hpipm:{bad}")
        simulate = one_line_error(capsys, ["simulate", "--horizon", bad])
        assert str(exc.value).split("horizon: ", 1)[1] in simulate and len(str(exc.value)) < 300


def test_the_sweeps_total_is_bounded_before_any_file(capsys, tmp_path, monkeypatch):
    output = tmp_path / "big.db"
    for where in ("mpc_hunt.sweep.store.SweepStore", "mpc_hunt.sweep.stored_run.run_into"):   # no file, no hunt
        monkeypatch.setattr(where, lambda *a, **k: pytest.fail("the sweep started"))
    argv = ["sweep", "--hunts", "1000000", "--strategy", "apf", "--strategy", "voronoi", "--attacker", "apf",
            "--attacker", "flee", "--attacker", "gap", "--belief", "exact", "--belief", "eta=2x",
            "--output", str(output)]
    err = one_line_error(capsys, argv)
    assert f"= 12000000 hunts: at most {MAX_TASKS}" in err
    assert not output.exists()


def test_the_sweeps_tasks_are_made_as_they_are_run():
    tracemalloc.start()
    todo = tasks(["apf", "voronoi"], 200_000, 1, ScenarioRanges(), {("apf", DEFAULT_BEHAVIOUR, "exact", 1, 0)})
    first = next(iter(todo))
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 2_000_000                  # 400,000 hunts listed would take about 100 MB
    assert (first.strategy, first.index) == ("voronoi", 0) and len(todo) == 399_999


def _row(task: int) -> dict:
    return {"task": task}


def test_local_workers_read_the_tasks_as_they_run():
    read = []

    def todo():
        for i in range(10_000):
            read.append(i)
            yield i

    rows = run_local(todo(), workers=1, work=_row)
    assert next(rows) in ({"task": 0}, {"task": 1})
    rows.close()
    assert len(read) <= 4


# The shipped data files, damaged.
def _weights_text() -> str:
    return Path(str(learned.weights_file())).read_text(encoding="utf-8")


def _damaged_weights() -> dict:
    good = _weights_text()
    data = json.loads(good)
    first = repr(data["weights"][0][0])
    return {
        "truncated": good[:len(good) // 2],
        "empty": "",
        "wrong-keys": json.dumps({"weight": data["weights"]}),
        "not-an-object": json.dumps(data["weights"]),
        "short-rows": json.dumps({"weights": [row[:-1] for row in data["weights"]]}),
        "flat": json.dumps({"weights": data["weights"][0] + data["weights"][1]}),
        "three-rows": json.dumps({"weights": data["weights"] + [data["weights"][0]]}),
        "NaN": good.replace(first, "NaN", 1),
        "infinite": good.replace(first, "1e999", 1),
        "text": json.dumps({"weights": [["1"] * 10] * 2}),
    }


@pytest.mark.parametrize("damage", list(_damaged_weights()))
def test_damaged_learned_weights_are_one_line_naming_the_file(capsys, monkeypatch, tmp_path, damage):
    path = tmp_path / "learned.json"
    path.write_text(_damaged_weights()[damage], encoding="utf-8")
    with pytest.raises(DataFileError) as exc:
        learned.load_weights(path)
    assert str(exc.value).startswith(f"{path}: ") and "\n" not in str(exc.value)
    monkeypatch.setattr(learned, "weights_file", lambda: path)          # as if the shipped file were damaged
    scenario = tmp_path / "tiny.toml"
    scenario.write_text(TINY)
    err = one_line_error(capsys, ["simulate", "--scenario", str(scenario), "--attacker", "learned",
                                  "--controller", "apf", "--json"])
    assert str(path) in err


def test_the_shipped_weights_load():
    assert learned.shipped_weights().shape == (2, learned.FEATURES)


def _damaged_problem_sets() -> dict:
    good = Path(__file__).parents[2].joinpath("mpc_hunt", "bench", "problems", "default.json").read_text("utf-8")
    data = json.loads(good)
    first = data["problems"][0]
    return {
        "truncated": good[:len(good) // 3],
        "empty": "",
        "wrong-format": json.dumps(data | {"format": "something else"}),
        "no-problems": json.dumps({k: v for k, v in data.items() if k != "problems"}),
        "short-position": json.dumps(data | {"problems": [first | {"attacker": [1.0]}]}),
        "NaN": json.dumps(data | {"problems": [first | {"attacker": [float("nan"), 1.0]}]}),
        "defenders-missing": json.dumps(data | {"problems": [first | {"defenders": first["defenders"][:1]}]}),
    }


@pytest.mark.parametrize("damage", list(_damaged_problem_sets()))
def test_damaged_problem_sets_are_one_line_naming_the_file(capsys, monkeypatch, tmp_path, damage):
    shipped = tmp_path / "problems"
    shipped.mkdir()
    path = shipped / "default.json"
    path.write_text(_damaged_problem_sets()[damage], encoding="utf-8")
    with pytest.raises(MpcHuntError) as exc:
        load_problem_set(path)
    assert str(exc.value).startswith(str(path)) and "\n" not in str(exc.value)
    monkeypatch.setattr("mpc_hunt.bench.problem_set.resources.files", lambda package: shipped)
    with pytest.raises(MpcHuntError, match=str(path)):
        builtin_problem_set("default")
    assert str(path) in one_line_error(capsys, ["problems", "default"])

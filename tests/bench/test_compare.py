"""``mpc-hunt compare`` end to end on a tiny selection: rows, modes, seeded selection, outputs, Ctrl-C."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import mpc_hunt.bench.compare as compare
from mpc_hunt.solving.accuracy import accuracy_table
from mpc_hunt.cli.commands import main
from mpc_hunt.plots.compare_report import write_report
from mpc_hunt.bench.compare import check_pairs, run_compare
from mpc_hunt.bench.compare_rows import rows
from mpc_hunt.capture.evaluator import ENCLOSE_OBJECTIVE, OBJECTIVE
from mpc_hunt.errors import BenchmarkError
from mpc_hunt.bench.problem_set import builtin_problem_set

ROOT = Path(__file__).resolve().parents[2]
PAIRS = ["nlp:ipopt", "qp:daqp", "sqp:daqp"]
REQUIRED = ("formulation", "backend", "mode", "horizon", "success_rate", "solve_time_median_s", "solve_time_p95_s",
            "solve_time_shifted_geomean_s", "optimality_gap_median", "max_violation", "iterations_median")


def _tiny():
    """The default state of paper-open, one random state and one closed-loop sequence (4 states)."""
    shipped = builtin_problem_set("default")
    keep = {"paper-open/default", "random-4/obstacle_safety"} | {p.id for p in shipped.problems
                                                                 if p.sequence == "paper-open/run-1781"}
    return shipped.select(), [p for p in shipped.problems if p.id in keep]


@pytest.mark.slow
def test_a_small_run_scores_every_pair_in_both_modes(tmp_path):
    shipped, keep = _tiny()
    problem_set = type(shipped)(shipped.scenarios, tuple(keep), "tiny")
    run = run_compare(problem_set, check_pairs(PAIRS), [1], ["cold", "replayed"], np.random.default_rng(0),
                      starts=2)
    assert not run.interrupted and len(run.records) == 3 * (6 + 4)
    table = rows(run)
    assert [(r["formulation"], r["mode"]) for r in table] == [("nlp", "cold"), ("qp", "cold"), ("sqp", "cold"),
                                                              ("nlp", "replayed"), ("qp", "replayed"),
                                                              ("sqp", "replayed")]
    for r in table:
        assert set(REQUIRED) <= set(r) and r["solves"] == (6 if r["mode"] == "cold" else 4)
        assert r["solve_time_median_s"] > 0 and r["solve_time_p95_s"] >= r["solve_time_median_s"]
    by = {(r["formulation"], r["mode"]): r for r in table}
    # The exact formulations reach the reference; warm starts happen only in the closed loop (3 of 4 states).
    assert by[("nlp", "cold")]["success_rate"] == 1.0 and abs(by[("nlp", "cold")]["optimality_gap_median"]) < 1e-6
    assert by[("sqp", "replayed")]["warm_started"] == 3 and by[("sqp", "cold")]["warm_started"] == 0
    # The same-state speed-up: the replayed states are problems of the set too, so cold times exist for each.
    assert by[("sqp", "replayed")]["warm_speedup_states"] == 4 and by[("sqp", "replayed")]["warm_speedup"] > 0
    assert by[("sqp", "cold")]["warm_speedup"] is None
    assert by[("nlp", "cold")]["max_dual_residual"] is not None                 # every row carries certificates
    # The QP linearises Eq. 14 and the attacker's path: above the best known, never below by more than noise.
    assert by[("qp", "cold")]["optimality_gap_median"] > 1e-4
    assert by[("qp", "cold")]["max_violation_equal_distance"] > 0
    files = write_report(run, {"cpu": "test", "cores": 1, "usable_cores": 1, "system": "s", "python": "3",
                               "packages": {}}, tmp_path / "report", "mpc-hunt compare (test)", {})
    assert all(f.stat().st_size > 0 for f in files)
    text = (tmp_path / "report" / "README.md").read_text()
    assert "mpc-hunt compare (test)" in text and "![performance_profile.png]" in text and OBJECTIVE in text
    saved = json.loads((tmp_path / "report" / "results.json").read_text())
    assert len(saved["solves"]) == len(run.records) and saved["rows"][0]["formulation"] == "nlp"


def _compare_json(capsys, *extra):
    code = main(["compare", "--json", "--limit", "2", "--seed", "4", "--pair", "qp:daqp", "--pair", "nlp:ipopt",
                 "--starts", "1", *extra])
    out, err = capsys.readouterr()
    return code, (json.loads(out) if out else None), err


def test_the_command_prints_rows_and_the_same_seed_picks_the_same_problems(capsys):
    code, first, err = _compare_json(capsys)
    assert code == 0, err
    assert err == ""                                     # no progress bar with --json
    assert set(first) == {"machine", "settings", "interrupted", "rows"}
    assert {"cpu", "cores", "python", "packages"} <= set(first["machine"])
    assert all(set(REQUIRED) <= set(r) for r in first["rows"])
    assert {(r["formulation"], r["backend"]) for r in first["rows"]} == {("qp", "daqp"), ("nlp", "ipopt")}
    code, again, _ = _compare_json(capsys)
    assert again["settings"]["problems"] == first["settings"]["problems"] and len(first["settings"]["problems"]) <= 2
    code, other, _ = _compare_json(capsys, "--seed", "5")
    assert other["settings"]["problems"] != first["settings"]["problems"]


def test_horizon_ten_and_the_outputs(capsys, tmp_path):
    code, doc, err = _compare_json(capsys, "--horizon", "10", "--mode", "cold", "--csv", str(tmp_path / "rows.csv"),
                                   "--plot", str(tmp_path / "figures"))
    assert code == 0, err
    assert {r["horizon"] for r in doc["rows"]} == {10} and {r["mode"] for r in doc["rows"]} == {"cold"}
    assert (tmp_path / "rows.csv").read_text().startswith("formulation,backend,mode,horizon,")
    assert len(list((tmp_path / "figures").glob("*.png"))) == 3


def test_ctrl_c_keeps_the_finished_solves(capsys, monkeypatch):
    calls = 0
    solve = compare._solve

    def interrupted(*args):
        nonlocal calls
        calls += 1
        if calls == 3:
            raise KeyboardInterrupt
        return solve(*args)

    monkeypatch.setattr(compare, "_solve", interrupted)
    code, doc, err = _compare_json(capsys)
    assert code == 2 and doc["interrupted"] is True
    assert sum(r["solves"] for r in doc["rows"]) == 2
    assert err.count("\n") == 1 and "interrupted: kept" in err and "Traceback" not in err


@pytest.mark.parametrize("argv,message", [
    (["compare", "--pair", "qp:ipopt"], "does not solve formulation 'qp'"),
    (["compare", "--pair", "lp"], "unknown formulation 'lp'"),
    (["compare", "--tag", "nothing-has-this"], "--tag nothing-has-this: no problem"),
    (["compare", "--csv", "rows.txt"], "--csv rows.txt: extension '.txt'"),
    (["compare", "--report", "missing-folder/report"], "folder missing-folder does not exist"),
    (["compare", "--problems", "nowhere"], "unknown problem set 'nowhere'"),
    (["compare", "--horizon", "0"], "--horizon: must be at least 1"),
])
def test_bad_arguments_are_one_line(capsys, argv, message):
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count("\n") == 1


def test_the_score_and_the_accuracy_table_are_documented_as_the_code_has_them():
    formulations = (ROOT / "docs" / "formulations.md").read_text(encoding="utf-8")
    benchmarks = (ROOT / "docs" / "benchmarks.md").read_text(encoding="utf-8")
    assert OBJECTIVE in formulations
    assert accuracy_table() in benchmarks


def test_compare_poses_and_scores_the_enclose_objective_when_asked(tmp_path, capsys):
    """Same states, other objective: the plans are scored on the objective they were planned for, and the
    exact formulation still reaches the multi-start reference on it."""
    shipped, keep = _tiny()
    problem_set = type(shipped)(shipped.scenarios, tuple(keep[:2]), "tiny")
    runs = {o: run_compare(problem_set, check_pairs(["ms-nlp:ipopt"]), [3], ["cold"], np.random.default_rng(0),
                           starts=2, objective=o) for o in ("paper", "enclose")}
    for entry in keep[:2]:
        assert problem_set.problem(entry, 3, "enclose").objective == "enclose"
    paper, enclose = ([r.objective for r in runs[o].records] for o in ("paper", "enclose"))
    assert all(abs(a - b) > 1e-6 for a, b in zip(paper, enclose))
    (row,) = rows(runs["enclose"])
    assert row["success_rate"] == 1.0 and abs(row["optimality_gap_median"]) < 1e-6
    write_report(runs["enclose"], {"cpu": "test", "cores": 1, "usable_cores": 1, "system": "s", "python": "3",
                                   "packages": {}}, tmp_path / "report", "mpc-hunt compare (test)", {})
    text = (tmp_path / "report" / "README.md").read_text()
    assert "(`enclose`)" in text and ENCLOSE_OBJECTIVE in text and OBJECTIVE not in text
    with pytest.raises(BenchmarkError, match="objective: unknown 'capture'"):
        run_compare(problem_set, check_pairs(["sqp:daqp"]), [3], ["cold"], np.random.default_rng(0),
                    objective="capture")
    assert main(["compare", "--objective", "enclose", "--limit", "1", "--pair", "sqp:daqp", "--horizon", "2",
                 "--starts", "1", "--mode", "cold", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["settings"]["objective"] == "enclose"


def test_every_pair_is_told_apart_at_a_glance():
    """Scatter points by marker alone, lines by colour and line style: distinct for far more pairs than exist."""
    from mpc_hunt.plots.compare import pair_style
    from mpc_hunt.solving import registry
    styles = [pair_style(k) for k in range(max(20, len(registry.pairs(installed_only=False))))]
    assert len({s["marker"] for s in styles}) == len(styles)
    assert len({(s["color"], s["linestyle"]) for s in styles}) == len(styles)

"""Sweeps: the summary's statistics, the failure taxonomy, local and Dask runs, and resuming."""

from __future__ import annotations

import contextlib
import dataclasses
import io
import json
import multiprocessing
import os
import shutil
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from conftest import small_scenario
from mpc_hunt import Attacker, Command, Defender, HuntParameters, Obstacle, Scenario, Solution, Status, simulate
from mpc_hunt.cli.commands import main
from mpc_hunt.cli.common import flag
from mpc_hunt.control.encircling import EncirclingController
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.errors import MpcHuntError, OptionError, SettingError
from mpc_hunt.sweep.random_scenario import ScenarioRanges, ranges_to_dict
from mpc_hunt.sweep.runner import Hunt, connect_dask, run_dask, run_hunt, run_local, tasks
from mpc_hunt.sweep.outcome import FAILURE_STREAK, failure_cause, safety_breaches
from mpc_hunt.sweep.random_scenario import sweep_scenario
from mpc_hunt.sweep.reachability import comfortable
from mpc_hunt.sweep.store import COLUMNS, LEGACY_COLUMNS, SweepStore
from mpc_hunt.sweep.summary import summarise, table, wilson

ROOT = Path(__file__).resolve().parents[2]
TIMING = {"wall_time_s", "solve_time_p50_s", "solve_time_p95_s", "solve_time_max_s", "solves_over_time_step"}
QUICK = ScenarioRanges(time_limit=30.0)


def _outcomes(rows):
    return sorted(tuple((k, v) for k, v in r.items() if k not in TIMING) for r in rows)


def test_wilson_interval_on_known_values():
    assert wilson(0, 0) == (0.0, 1.0)
    lo, hi = wilson(5, 10)
    assert lo == pytest.approx(0.2366, abs=1e-4) and hi == pytest.approx(0.7634, abs=1e-4)
    lo, hi = wilson(10, 10)
    assert hi == pytest.approx(1.0, abs=1e-12) and lo == pytest.approx(0.7225, abs=1e-4)


def test_summary_of_hand_made_rows():
    base = {"strategy": "s", "capture_time_s": None, "path_length_m": None, "cause": None, "reachable": True,
            "comfortable": True, "n_defenders": 3}
    rows = [base | {"outcome": "captured", "capture_time_s": 100.0, "path_length_m": 30.0,
                    "safety_breach_approach": 1, "min_arena_margin_m": 0.5, "n_defenders": 2},
            base | {"outcome": "captured", "capture_time_s": 200.0, "path_length_m": 50.0, "comfortable": False,
                    "safety_breach_approach": 1, "safety_breach_capture": 1, "min_arena_margin_m": 0.25},
            base | {"outcome": "failed", "cause": "time_limit", "safety_breach_approach": 0},
            base | {"outcome": "failed", "cause": "defender_contact", "comfortable": False},
            base | {"outcome": "failed", "cause": "attacker_escaped", "reachable": False, "comfortable": False},
            base | {"outcome": "uncapturable", "cause": "time_limit", "reachable": False, "comfortable": False,
                    "safety_breach_capture": 1}]
    (s,) = summarise(rows)
    assert s["hunts"] == 6 and s["uncapturable_by_definition"] == 1 and s["success_rate"] == 0.4
    assert s["unreachable"] == 1 and s["success_rate_reachable"] == 0.5
    assert s["success_rate_reachable_ci95"] == list(wilson(2, 4))
    assert s["comfortable"] == 2 and s["success_rate_comfortable"] == 0.5       # the first and third rows
    assert s["success_rate_comfortable_ci95"] == list(wilson(1, 2))
    assert s["safety_breaches_approach"] == 2 and s["safety_breaches_capture"] == 2   # every hunt, uncapturable too
    assert s["min_arena_margin_m"] == 0.25
    assert s["failures"]["time_limit"] == 1 and s["failures"]["defender_contact"] == 1 and s["collisions"] == 1
    assert s["capture_time_median_s"] == 150.0 and s["capture_time_iqr_s"] == 50.0
    assert s["reachable_by_defenders"] == {
        "2": {"hunts": 1, "captured": 1, "success_rate": 1.0, "success_rate_ci95": list(wilson(1, 1))},
        "3": {"hunts": 3, "captured": 1, "success_rate": 1 / 3, "success_rate_ci95": list(wilson(1, 3))}}
    assert (s["strategy"], s["attacker"], s["belief"]) == ("s", "apf", "exact")    # rows without them: the defaults
    header, rule, line, _, note, _, groups, _, by_defenders = table([s]).splitlines()
    cells = dict(zip(header.strip("|").split(" | "), line.strip("|").split(" | ")))
    assert note.startswith("Of the reachable hunts, by number of defenders")
    assert by_defenders.split(" | ")[1:3] == ["apf", "exact"]
    assert by_defenders.split(" | ")[3:] == [f"1 / 1, 100.0 % ({100 * wilson(1, 1)[0]:.1f} %–100.0 %)",
                                             f"1 / 3, 33.3 % ({100 * wilson(1, 3)[0]:.1f} %–"
                                             f"{100 * wilson(1, 3)[1]:.1f} %) |"]
    assert len(rule.split("|")) == len(header.split("|")) == len(line.split("|"))
    assert line.startswith("| s | apf | exact | 6 (") and header.startswith("| strategy | attacker | belief | hunts |")
    assert cells["hunts"] == "6 (1 uncapturable, 1 unreachable, 2 comfortable)"
    assert cells["of comfortable hunts"] == f"50.0 % ({100 * wilson(1, 2)[0]:.1f} %–{100 * wilson(1, 2)[1]:.1f} %)"
    assert cells["inside R_safe approaching / capturing"] == "2 / 2 hunts"


def test_each_failure_cause():
    scenario = small_scenario(obstacles=((6.0, 11.8, 0.3),))
    scenario = dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, time_limit=0.5))
    result = simulate(scenario, EncirclingController(scenario))
    assert failure_cause(result, scenario) == "time_limit"
    cases = {"obstacle_collision": dict(min_obstacle_clearance=-0.01),
             "defender_contact": dict(min_defender_separation=0.1),
             "outside_arena": dict(min_arena_margin=-0.01, termination="attacker_escaped"),
             "attacker_escaped": dict(termination="attacker_escaped"),
             "solver_failure_streak": dict(longest_failure_streak=50),
             "non_finite_state": dict(termination="non_finite_state")}
    for cause, change in cases.items():
        assert failure_cause(dataclasses.replace(result, **change), scenario) == cause
    assert failure_cause(dataclasses.replace(result, captured=True, termination="captured"), scenario) is None
    assert failure_cause(dataclasses.replace(result, captured=True, min_defender_separation=0.1),
                         scenario) == "defender_contact"      # safety comes before capture
    assert failure_cause(dataclasses.replace(result, captured=True, min_arena_margin=-0.01),
                         scenario) == "outside_arena"         # so does the arena
    assert failure_cause(dataclasses.replace(result, min_arena_margin=-1e-7, min_defender_separation=0.1),
                         scenario) == "defender_contact"
    assert failure_cause(dataclasses.replace(result, captured=True, min_arena_margin=-1e-7), scenario) is None
    assert failure_cause(dataclasses.replace(result, captured=True, min_arena_margin=None), scenario) is None


class Scripted:
    """Fixed velocities every step and, if given, the same capture-stage solution (say, a failed one); every
    defender in the approaching stage, or the capture stage if ``capture``."""

    def __init__(self, velocities, solution=None, capture=False):
        self.velocities, self.solution, self.capture = np.array(velocities, dtype=float), solution, capture

    def describe(self):
        return {"controller": "scripted"}

    def command(self, obs):
        n = len(obs.defenders)
        return Command(self.velocities, np.full(n, self.capture), np.full((n, 2), np.nan), self.solution,
                       self.solution is not None)


def _hunt(defenders, obstacles=(), time_limit=15.0, arena=None, omega=0.5):
    """Defenders (x, y) far from an attacker at (10, 10) who stands still: nothing is captured."""
    return Scenario(name="scripted", defenders=tuple(Defender(p, 0.08) for p in defenders),
                    attacker=Attacker((10.0, 10.0), (0.0, 0.0), 0.03, 1.0),
                    obstacles=tuple(Obstacle(c, r) for c, r in obstacles), arena=arena,
                    hunt=HuntParameters(time_limit=time_limit, omega=omega))


@pytest.mark.parametrize("cause, scenario, controller", [
    ("time_limit", _hunt([(0, 0), (0, 2), (0, 4)]), Scripted(np.zeros((3, 2)))),
    ("obstacle_collision", _hunt([(0, 0), (0, 2), (0, 4)], obstacles=[((1.0, 0.0), 0.3)]),
     Scripted([(0.08, 0), (0, 0), (0, 0)])),                                         # into the obstacle at t = 8.75 s
    ("defender_contact", _hunt([(0, 0), (2, 0), (0, 4)]), Scripted([(0.08, 0), (-0.08, 0), (0, 0)])),  # t = 11.25 s
    ("outside_arena", _hunt([(0, 0), (0, 2), (0, 4)], arena=(-1.0, -1.0, 20.0, 20.0)),
     Scripted([(-0.08, 0), (0, 0), (0, 0)])),                                        # out of the arena at t = 12.5 s
    ("non_finite_state", _hunt([(0, 0), (0, 2), (0, 4)]), Scripted([(np.nan, 0), (0, 0), (0, 0)])),
    ("solver_failure_streak", _hunt([(0, 0), (0, 2), (0, 4)], time_limit=FAILURE_STREAK * 0.1),
     Scripted(np.zeros((3, 2)), Solution(status=Status.ERROR))),
    ("time_limit", _hunt([(0, 0), (0, 2), (0, 4)], time_limit=(FAILURE_STREAK - 1) * 0.1),
     Scripted(np.zeros((3, 2)), Solution(status=Status.ERROR))),                             # one failed solve short
])
def test_hand_built_hunts_end_with_each_cause(cause, scenario, controller):
    result = simulate(scenario, controller)
    assert failure_cause(result, scenario) == cause
    # A collision, a contact or a streak is recorded, and the hunt goes on to its time limit.
    expected = "non_finite_state" if cause == "non_finite_state" else "time_limit"
    assert result.termination == expected


def test_a_defender_beyond_an_edge_is_recorded_by_how_far():
    scenario = _hunt([(0, 0), (0, 2), (0, 4)], arena=(-1.0, -1.0, 20.0, 20.0), time_limit=10.0)
    inside = simulate(scenario, Scripted([(-0.08, 0), (0, 0), (0, 0)]))       # to x = -0.8 m: 0.2 m inside
    assert inside.min_arena_margin == pytest.approx(0.2) and failure_cause(inside, scenario) == "time_limit"
    beyond = simulate(dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, time_limit=15.0)),
                      Scripted([(-0.08, 0), (0, 0), (0, 0)]))                 # to x = -1.2 m: 0.2 m beyond
    assert beyond.min_arena_margin == pytest.approx(-0.2)
    assert simulate(dataclasses.replace(scenario, arena=None), Scripted(np.zeros((3, 2)))).min_arena_margin is None


@pytest.mark.parametrize("capture, breaches", [(False, (True, False)), (True, (False, True))])
def test_a_safety_distance_breach_is_recorded_in_its_stage(capture, breaches):
    """Defender 0 runs to 0.06 m of an obstacle's surface (inside R_safe = 0.1 m, not touching it)."""
    scenario = _hunt([(0, 0), (0, 2), (0, 4)], obstacles=[((1.0, 0.0), 0.3)], time_limit=8.0)
    result = simulate(scenario, Scripted([(0.08, 0), (0, 0), (0, 0)], capture=capture))
    assert failure_cause(result, scenario) == "time_limit"
    assert safety_breaches(result, scenario) == breaches
    short = dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, time_limit=7.5))   # to 0.1 m
    assert safety_breaches(simulate(short, Scripted([(0.08, 0), (0, 0), (0, 0)], capture=capture)), short) \
        == (False, False)


class _EquationSixAlone:
    """Every defender by Eq. 6 towards the attacker, the approaching stage without its R_safe filter."""

    def __init__(self, scenario):
        self.scenario = scenario

    def describe(self):
        return {"controller": "eq6"}

    def command(self, obs):
        from mpc_hunt.control.controller import Command
        from mpc_hunt.world.approach import approach_velocity

        s, P = self.scenario, obs.defenders
        velocities = np.array([approach_velocity(s, P[i], obs.attacker, s.defender_max_speeds[i], np.delete(P, i, 0))
                               for i in range(len(P))])
        return Command(velocities, np.zeros(len(P), dtype=bool), np.full_like(P, np.nan))


def test_the_approaching_stage_keeps_r_safe_where_eq_6_alone_would_not():
    """With ω = 1, Eq. 6 is pure pursuit: defender 0 heads through the obstacle between it and the attacker."""
    scenario = _hunt([(0, 0), (2, 8), (8, 2)], obstacles=[((4.0, 4.1), 0.5)], time_limit=90.0, omega=1.0)
    result = simulate(scenario, EncirclingController(scenario))
    assert result.approach_min_obstacle_clearance >= scenario.hunt.safety_distance - 1e-9
    assert safety_breaches(result, scenario)[0] is False
    unfiltered = simulate(scenario, _EquationSixAlone(scenario))
    assert failure_cause(unfiltered, scenario) == "obstacle_collision"


def test_an_exception_inside_a_hunt_is_a_row_with_its_message(monkeypatch):
    def broken(*args, **kwargs):
        raise ZeroDivisionError("no")

    monkeypatch.setattr("mpc_hunt.sweep.runner.simulate_batch", broken)
    row = run_hunt(Hunt("apf", 1, 0, next(iter(tasks(["apf"], 1, 1, QUICK, set()))).ranges))
    assert (row["outcome"], row["cause"], row["message"]) == ("failed", "error", "ZeroDivisionError: no")
    assert set(row) <= set(COLUMNS) and row["scenario_toml"]


def test_the_results_file_keeps_every_column_whatever_row_comes_first(tmp_path):
    task = list(tasks(["apf"], 2, 1, ScenarioRanges(time_limit=2.0), set()))
    good = run_hunt(task[1])
    assert list(good) == list(COLUMNS)                        # the documented schema, in order
    assert list(COLUMNS).index("comfortable") == list(COLUMNS).index("reachable") + 1
    error = {k: v for k, v in good.items() if k in ("strategy", "attacker", "belief", "name", "seed", "index")}
    error |= {"index": 0, "outcome": "failed", "cause": "error", "message": "boom"}
    store = SweepStore(tmp_path / "s.db", {"sweep": 1})
    store.add(error)                                          # an error row first, with few columns
    store.add(good)
    store.add(good | {"outcome": "captured"})                 # a key already present is left as it is
    rows = store.rows()
    assert len(rows) == 2 and rows[0]["termination"] is None
    assert rows[1] == good | {"capturable_by_definition": int(good["capturable_by_definition"])}
    assert rows[1]["comfortable"] == comfortable(sweep_scenario(1, 1, ScenarioRanges(time_limit=2.0)))
    assert {rows[1][k] for k in ("safety_breach_approach", "safety_breach_capture")} <= {0, 1}
    with pytest.raises(MpcHuntError, match="columns the results file does not"):
        store.add(good | {"surprise": 1})
    store.close()


def test_a_hunt_ends_when_the_attacker_leaves_the_arena():
    scenario = small_scenario(obstacles=())
    scenario = dataclasses.replace(scenario, arena=(9.0, 9.0, 11.0, 11.0))      # attacker starts at (10, 10)
    result = simulate(scenario, EncirclingController(scenario))
    assert result.termination == "attacker_escaped"
    assert failure_cause(result, scenario) == "outside_arena"          # the defenders start beyond its edges
    assert failure_cause(dataclasses.replace(result, min_arena_margin=0.0), scenario) == "attacker_escaped"


def test_a_strategy_is_a_controller_spec_named_by_its_label(capsys, tmp_path):
    assert ControllerSpec.parse("paper:qp:daqp:5").label == "paper:qp:daqp:5"
    assert ControllerSpec.parse("paper").label == "paper:rti:hpipm:10" and ControllerSpec.parse("apf").label == "apf"
    for bad in ("paper:qp:ipopt", "apf:qp", "paper:qp:daqp:0", "nobody", "a:b:c:d:e"):
        with pytest.raises(OptionError):
            ControllerSpec.parse(bad)
        assert main(["sweep", "--strategy", bad, "--output", str(tmp_path / "s.db")]) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"mpc-hunt sweep: error: --strategy {bad!r}: ") and err.count("\n") == 1


SMALL = ["--hunts", "3", "--seed", "1", "--strategy", "apf", "--strategy", "paper:qp:daqp:1", "--set", "time_limit=30"]


@pytest.fixture(scope="module")
def small_sweep(tmp_path_factory):
    """The CLI's tiny sweep on 2 local processes: its JSON summary and its stored rows."""
    path = tmp_path_factory.mktemp("sweep") / "s.db"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["sweep", *SMALL, "--workers", "2", "--output", str(path), "--json"]) == 0
    return json.loads(out.getvalue()), SweepStore(path).rows()


def test_sweep_end_to_end_on_local_processes(small_sweep):
    summary, rows = small_sweep
    for s in summary["strategies"]:
        for key in ("success_rate", "success_rate_ci95", "success_rate_comfortable", "success_rate_comfortable_ci95",
                    "failures", "collisions", "capture_time_median_s", "safety_breaches_approach",
                    "safety_breaches_capture", "min_arena_margin_m"):
            assert key in s
        assert s["hunts"] == 3 and set(s["failures"]) >= {"time_limit", "obstacle_collision", "defender_contact",
                                                          "outside_arena", "attacker_escaped",
                                                          "solver_failure_streak", "non_finite_state"}
    assert len(rows) == 6 and all(r["wall_time_s"] > 0 for r in rows)


def test_the_same_rows_on_a_dask_cluster(small_sweep):
    from distributed import LocalCluster
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        todo = tasks(["apf", "paper:qp:daqp:1"], 3, 1, QUICK, set())
        remote = list(run_dask(todo, connect_dask(cluster.scheduler_address)))
    assert _outcomes(remote) == _outcomes(small_sweep[1])


def test_a_killed_local_worker_loses_no_hunt(small_sweep):
    rows = []
    for row in run_local(tasks(["apf", "paper:qp:daqp:1"], 3, 1, QUICK, set()), workers=2):
        if not rows:        # the pool breaks; the hunts it was running go to a new one
            os.kill(multiprocessing.active_children()[0].pid, signal.SIGKILL)
        rows.append(row)
    assert _outcomes(rows) == _outcomes(small_sweep[1])


def test_an_interrupted_sweep_resumes_to_the_same_rows(tmp_path):
    # apf's hunts run 32 a batch, a batch in about 0.1 s: 1500 hunts leave seconds between the first rows and the
    # last, so the kill lands mid-sweep even when polling lags (70 hunts once ended before the kill came)
    argv = ["sweep", "--hunts", "1500", "--seed", "2", "--strategy", "apf", "--set", "time_limit=20",
            "--workers", "1", "--json"]
    killed = tmp_path / "killed.db"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    process = subprocess.Popen([sys.executable, "-m", "mpc_hunt.cli", *argv, "--output", str(killed)], cwd=ROOT,
                               env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _wait_for_rows(killed, 2)
    process.send_signal(signal.SIGKILL)
    process.wait()
    if Path("/proc").is_dir():      # its workers die with it
        deadline = time.monotonic() + 5
        while _processes_naming(killed) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not _processes_naming(killed)
    partial = len(SweepStore(killed).rows())
    assert 2 <= partial < 1500
    assert main([*argv, "--output", str(killed), "--resume"]) == 0
    whole = tmp_path / "whole.db"
    assert main([*argv, "--output", str(whole)]) == 0
    assert _outcomes(SweepStore(killed).rows()) == _outcomes(SweepStore(whole).rows())


def _processes_naming(path: Path) -> list[int]:
    """Live processes whose command line names ``path`` (Linux)."""
    found = []
    for cmdline in Path("/proc").glob("[0-9]*/cmdline"):
        try:
            text = cmdline.read_bytes()
            state = (cmdline.parent / "stat").read_text().split(") ")[-1][:1]
        except OSError:
            continue
        if str(path).encode() in text and state != "Z":
            found.append(int(cmdline.parent.name))
    return found


def _wait_for_rows(path: Path, count: int, seconds: float = 120) -> None:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        time.sleep(0.1)
        if not path.exists():      # connecting would create it
            continue
        try:
            with sqlite3.connect(path) as db:
                if db.execute("select count(*) from hunts").fetchone()[0] >= count:
                    return
        except sqlite3.OperationalError:      # the table does not exist yet
            continue


def test_ctrl_c_stops_a_sweep_at_once_even_inside_ipopt(tmp_path):
    """IPOPT takes a KeyboardInterrupt as a request to end one solve; the hunt must not run on to its end."""
    path = tmp_path / "s.db"
    process = subprocess.Popen([sys.executable, "-m", "mpc_hunt.cli", "sweep", "--hunts", "3", "--seed", "1",
                                "--strategy", "paper:ms-nlp:ipopt:1", "--workers", "1", "--output", str(path)],
                               cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)}, start_new_session=True,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    _wait_for_rows(path, 1)
    time.sleep(1.0)                          # the second hunt is running (for seconds more)
    os.killpg(process.pid, signal.SIGINT)    # what Ctrl-C in a terminal does: the whole process group
    start = time.monotonic()
    _, err = process.communicate(timeout=120)
    assert time.monotonic() - start < 5.0
    assert process.returncode == 2 and "interrupted; finished hunts are in" in err.decode()
    assert len(SweepStore(path).rows()) == 1


def test_resume_with_other_arguments_or_numpy_is_refused(capsys, tmp_path):
    path = tmp_path / "s.db"
    base = ["sweep", "--hunts", "1", "--strategy", "apf", "--set", "time_limit=5", "--output", str(path), "--json"]
    assert main(base) == 0
    assert main(base) == 2 and f"--output: {path} exists (use --resume to continue it, or another --output)" in \
        capsys.readouterr().err
    assert main([*base[:2], "2", *base[3:], "--resume"]) == 2
    assert "--resume: other arguments than the sweep in" in capsys.readouterr().err
    with sqlite3.connect(path) as db:
        db.execute("update sweep set numpy = '0.1'")
    assert main([*base, "--resume"]) == 2 and "drawn with numpy 0.1" in capsys.readouterr().err


def test_a_file_that_is_not_a_sweep_is_one_line(capsys, tmp_path):
    other = tmp_path / "other.db"
    with sqlite3.connect(other) as db:
        db.execute("create table t (x)")
    text = tmp_path / "text.db"
    text.write_text("hello\n")
    for path in (other, text, tmp_path / "missing.db"):
        assert main(["sweep-report", str(path)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and str(path) in err
    with sqlite3.connect(other) as db:            # read, never changed
        assert [r[0] for r in db.execute("select name from sqlite_master")] == ["t"]


def test_a_forgotten_strategy_is_run_again_on_resume_and_the_others_kept(small_sweep, tmp_path):
    path = tmp_path / "s.db"
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["sweep", *SMALL, "--workers", "1", "--output", str(path), "--json"]) == 0
    store = SweepStore(path, SweepStore(path).arguments, resume=True)
    assert store.forget("apf") == 3
    with pytest.raises(MpcHuntError, match="not one of this sweep's"):
        store.forget("voronoi")
    kept = [r for r in store.rows() if r["strategy"] != "apf"]
    store.close()
    assert len(kept) == 3
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["sweep", *SMALL, "--workers", "1", "--output", str(path), "--json", "--resume"]) == 0
    rows = SweepStore(path).rows()
    assert _outcomes(rows) == _outcomes(small_sweep[1])
    assert [r for r in rows if r["strategy"] != "apf"] == kept


# --- attackers and beliefs ------------------------------------------------------------------------------------

TWO_BY_TWO = ["sweep", "--hunts", "2", "--seed", "4", "--strategy", "apf", "--strategy", "voronoi",
              "--attacker", "apf", "--attacker", "noisy", "--belief", "exact", "--belief", "eta=3,intent_heading=60",
              "--set", "time_limit=20", "--set", "arena=[0, 0, 6, 6]", "--set", "n_obstacles=0", "--json"]
BELIEFS = ["exact", "eta=3x,intent_heading=60"]     # as stored: the labels


def _sweep(argv: list[str]) -> dict:
    """``mpc-hunt argv``'s JSON summary."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(argv) == 0
    return json.loads(out.getvalue())


@pytest.fixture(scope="module")
def two_by_two(tmp_path_factory):
    """Two strategies against two attackers with two beliefs, on 2 hunts of 20 s: the file and its summary."""
    path = tmp_path_factory.mktemp("sweep") / "s.db"
    return path, _sweep([*TWO_BY_TWO, "--workers", "2", "--output", str(path)])


def test_every_strategy_meets_every_attacker_and_belief_on_the_same_hunts(two_by_two, tmp_path):
    path, summary = two_by_two
    store = SweepStore(path)
    rows, arguments = store.rows(), store.arguments
    store.close()
    assert arguments["attackers"] == ["apf", "noisy"] and arguments["beliefs"] == BELIEFS
    keys = [(r["strategy"], r["attacker"], r["belief"], r["index"]) for r in rows]
    assert sorted(keys) == sorted((s, a, b, i) for s in ("apf", "voronoi") for a in ("apf", "noisy")
                                  for b in BELIEFS for i in (0, 1))
    assert [(s["strategy"], s["attacker"], s["belief"]) for s in summary["strategies"]] == \
        list(dict.fromkeys(k[:3] for k in keys)) and all(s["hunts"] == 2 for s in summary["strategies"])
    for a in ("apf", "noisy"):         # every strategy and belief meets one scenario, its behaviour replaced
        for i in (0, 1):
            scenarios = {r["scenario_toml"] for r in rows if (r["attacker"], r["index"]) == (a, i)}
            assert len(scenarios) == 1 and f'behaviour = "{a}"' in scenarios.pop()
    by_key = {k: r for k, r in zip(keys, rows)}
    assert all(by_key[("apf", "apf", "exact", i)]["min_attacker_distance_m"] !=
               by_key[("apf", "noisy", "exact", i)]["min_attacker_distance_m"] for i in (0, 1))   # pushed at random
    again = tmp_path / "again.db"      # the same rows from a second run, on one worker
    _sweep([*TWO_BY_TWO, "--workers", "1", "--output", str(again)])
    assert _outcomes(SweepStore(again).rows()) == _outcomes(rows)


def test_a_resume_runs_only_the_combinations_missing(two_by_two, tmp_path):
    path = tmp_path / "partial.db"
    shutil.copy(two_by_two[0], path)
    with sqlite3.connect(path) as db:
        assert db.execute("delete from hunts where attacker = 'noisy' and belief != 'exact'").rowcount == 4
    kept = SweepStore(path).rows()
    _sweep([*TWO_BY_TWO, "--workers", "1", "--output", str(path), "--resume"])
    rows = SweepStore(path).rows()
    assert [r for r in rows if r in kept] == kept and len(rows) == 16       # kept to the wall time: not rerun
    assert _outcomes(rows) == _outcomes(SweepStore(two_by_two[0]).rows())


def test_each_hunt_gets_its_attacker_belief_and_generators_whatever_the_strategy(monkeypatch):
    from mpc_hunt.control.spec import ControllerSpec
    from mpc_hunt.sweep import runner
    from mpc_hunt.world.belief import parse_belief

    seen = []
    build, run = ControllerSpec.build, runner.simulate_batch

    def spy_build(spec, scenario, *, belief, rng):
        seen.append(("controller", scenario.attacker.behaviour, belief, rng.bit_generator.state))
        return build(spec, scenario, belief=belief, rng=rng)

    def spy_simulate(scenarios, controllers, rngs):
        seen.extend(("world", s.attacker.behaviour, rng.bit_generator.state) for s, rng in zip(scenarios, rngs))
        return run(scenarios, controllers, rngs)

    monkeypatch.setattr(ControllerSpec, "build", spy_build)
    monkeypatch.setattr(runner, "simulate_batch", spy_simulate)
    ranges = next(iter(tasks(["apf"], 1, 4, ScenarioRanges(time_limit=1.0), set()))).ranges
    for strategy in ("apf", "voronoi"):
        run_hunt(Hunt(strategy, 4, 1, ranges, attacker="noisy", belief="intent_heading=60"))
    world, belief = runner.hunt_rngs(4, 1)
    assert seen[:2] == seen[2:] == [("controller", "noisy", parse_belief("intent_heading=60"),
                                     belief.bit_generator.state),
                                    ("world", "noisy", world.bit_generator.state)]


def test_the_hunts_generators_are_spawned_apart_from_every_other_stream():
    from mpc_hunt.sweep.random_scenario import sweep_rng
    from mpc_hunt.sweep.runner import hunt_rngs

    world, belief = hunt_rngs(7, 3, 2)
    chain = np.random.SeedSequence(7).spawn(4)[3].spawn(3)[2].spawn(2)
    assert world.random() == np.random.default_rng(chain[0]).random()
    assert belief.random() == np.random.default_rng(chain[1]).random()
    firsts = {g.random() for g in (*hunt_rngs(7, 3, 2), *hunt_rngs(7, 3), *hunt_rngs(7, 4, 2), sweep_rng(7, 3),
                                   np.random.default_rng([7, 3, 2]))}     # the last: member 2's nanometre moves
    assert len(firsts) == 8
    assert [g.random() for g in hunt_rngs(7, 3, 2)] == [g.random() for g in hunt_rngs(7, 3, 2)]


def _legacy_file(path: Path, hunts: int, ranges: ScenarioRanges) -> None:
    """A results file as the previous version wrote it (no attacker and belief columns, arguments without
    attackers and beliefs), holding hunt 0 of a sweep of ``hunts`` with strategy apf and seed 1."""
    arguments = {"strategies": ["apf"], "hunts": hunts, "seed": 1, "ranges": ranges_to_dict(ranges)}
    row = run_hunt(Hunt("apf", 1, 0, arguments["ranges"]))
    columns = ", ".join(f'"{c}" {COLUMNS[c]}' for c in LEGACY_COLUMNS)
    with sqlite3.connect(path) as db:
        db.execute("create table sweep (arguments text not null, numpy text not null)")
        db.execute(f'create table hunts ({columns}, primary key ("strategy", "seed", "index"))')
        db.execute("insert into sweep values (?, ?)", (json.dumps(arguments, sort_keys=True), np.__version__))
        db.execute(f"insert into hunts values ({', '.join('?' for _ in LEGACY_COLUMNS)})",
                   [row[c] for c in LEGACY_COLUMNS])


def test_a_results_file_of_the_previous_version_is_read_and_resumed_as_the_papers_attacker(capsys, tmp_path):
    ranges = ScenarioRanges(time_limit=10.0)
    path = tmp_path / "old.db"
    _legacy_file(path, 2, ranges)
    store = SweepStore(path)
    assert store.legacy and store.arguments["attackers"] == ["apf"] and store.arguments["beliefs"] == ["exact"]
    (row,) = store.rows()
    store.close()
    assert list(row) == list(COLUMNS) and (row["attacker"], row["belief"]) == ("apf", "exact")
    assert main(["sweep-report", str(path), "--json"]) == 0
    (summary,) = json.loads(capsys.readouterr().out)["strategies"]
    assert (summary["strategy"], summary["attacker"], summary["belief"], summary["hunts"]) == \
        ("apf", "apf", "exact", 1)
    argv = ["sweep", "--hunts", "2", "--seed", "1", "--strategy", "apf", "--set", "time_limit=10", "--workers", "1",
            "--json", "--output", str(path), "--resume"]
    assert main([*argv, "--attacker", "gap"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--attacker, --belief: " in err and "written by an earlier mpc-hunt" in err and \
        "only the attacker apf with the belief exact" in err and "another --output" in err
    assert main(argv) == 0                     # the same sweep: continued in the old columns
    capsys.readouterr()
    store = SweepStore(path)
    assert store.legacy and len(store.rows()) == 2
    new = tmp_path / "new.db"
    assert main([*argv[:-2], str(new)]) == 0       # --output new.db, not resumed
    fresh = SweepStore(new).rows()
    assert {r["edge_race_lost"] for r in store.rows()} == {None}     # a label the earlier version did not write
    assert _outcomes(store.rows()) == _outcomes([r | {"edge_race_lost": None} for r in fresh])


def test_the_committed_results_file_of_the_previous_version_reads(tmp_path):
    path = tmp_path / "sweep.db"
    shutil.copy(ROOT / "studies" / "sweep" / "sweep.db", path)
    store = SweepStore(path)
    rows = store.rows()
    assert store.legacy and len(rows) == len(store.arguments["strategies"]) * store.arguments["hunts"]
    assert {(r["attacker"], r["belief"]) for r in rows} == {("apf", "exact")}
    assert [s["strategy"] for s in summarise(rows)] == sorted(store.arguments["strategies"])


def test_a_sweep_meets_the_learned_attacker(tmp_path):
    """The trained attacker is a behaviour like the others: ``--attacker learned`` runs and is stored as such."""
    path = tmp_path / "learned.db"
    summary = _sweep(["sweep", "--hunts", "1", "--seed", "4", "--strategy", "voronoi", "--attacker", "learned",
                      "--set", "time_limit=20", "--set", "arena=[0, 0, 6, 6]", "--set", "n_obstacles=0", "--json",
                      "--workers", "1", "--output", str(path)])
    assert [(s["strategy"], s["attacker"], s["hunts"]) for s in summary["strategies"]] == [("voronoi", "learned", 1)]
    rows = SweepStore(path).rows()
    assert len(rows) == 1 and 'behaviour = "learned"' in rows[0]["scenario_toml"]


def test_a_resumed_sweep_may_add_an_attacker_and_keeps_what_it_ran(two_by_two, tmp_path):
    """More strategies, attackers or beliefs extend a results file (its rows stay valid); other changes do not."""
    path = tmp_path / "extended.db"
    shutil.copy(two_by_two[0], path)
    kept = SweepStore(path).rows()
    more = [*TWO_BY_TWO[:13], "--attacker", "flee", *TWO_BY_TWO[13:]]
    _sweep([*more, "--workers", "1", "--output", str(path), "--resume"])
    store = SweepStore(path)
    rows, arguments = store.rows(), store.arguments
    store.close()
    assert arguments["attackers"] == ["apf", "noisy", "flee"] and len(rows) == 24
    assert [r for r in rows if r in kept] == kept
    with pytest.raises(SettingError, match="^resume: .*only more strategies, attackers, beliefs may be added") as exc:
        SweepStore(path, {**arguments, "seed": 5}, resume=True)
    assert exc.value.named(flag).endswith("only more --strategy, --attacker, --belief may be added")


def test_hunts_run_as_one_batch_give_each_hunt_its_row_alone_and_a_broken_one_disturbs_none(monkeypatch):
    from mpc_hunt.sweep import runner

    work = list(tasks(["voronoi", "paper:rti:hpipm:1"], 3, 5, ScenarioRanges(time_limit=20.0), set(),
                      attackers=["gap", "noisy"]))
    work.insert(2, Hunt("voronoi:none", 5, 0, work[0].ranges))    # a strategy that cannot be built
    assert [len(b) for b in runner.batches(work, size=2)] == [2, 1, 1, 1, 2, 1, 1, 2, 1, 1]

    def alone(row):
        return {k: v for k, v in row.items() if k != "wall_time_s"}

    singly = [alone(run_hunt(t)) for t in work]
    together = runner.run_hunts(work)
    assert [alone(r) for r in together] == singly
    assert together[2]["cause"] == "error" and sum(r["cause"] == "error" for r in together) == 1
    real = runner.simulate_batch

    def crashing(scenarios, controllers, rngs):        # one hunt's controller crashes the batch it is in
        if len(scenarios) > 1:
            raise ZeroDivisionError("one hunt")
        return real(scenarios, controllers, rngs)

    monkeypatch.setattr(runner, "simulate_batch", crashing)
    assert [alone(r) for r in runner.run_hunts(work)] == singly

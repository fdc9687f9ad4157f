"""compare's own-loop mode: each pair in its own loop, hunt by hunt, its rows counting what the loop met."""

from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import capture_stage_scenario
from mpc_hunt.bench.own_loop import OwnLoopRun, hunt_summary, rows, run_own_loop, table
from mpc_hunt.cli import main
from mpc_hunt.errors import BenchmarkError
from mpc_hunt.sim import batch


def test_each_pair_runs_its_own_hunt_and_its_row_counts_what_its_loop_met():
    scenario = capture_stage_scenario(3.0)
    run = run_own_loop(OwnLoopRun([scenario], [("qp", "daqp"), ("rti", "hpipm")], [3], deadline=1e-9))
    assert [(h.formulation, h.backend) for h in run.hunts] == [("qp", "daqp"), ("rti", "hpipm")]
    assert not np.array_equal(run.hunts[0].result.defenders, run.hunts[1].result.defenders)   # its own states
    by = {r["backend"]: r for r in rows(run)}
    for backend, row in by.items():
        result = next(h.result for h in run.hunts if h.backend == backend)
        assert row["solves"] == len(result.solve_times) > 0 and row["setups"] >= 1     # the first structure
        assert row["deadline_misses"] == row["solves"]               # nothing meets a nanosecond
        assert row["deadline_misses_T"] == int(np.sum(result.solve_times > 0.1))
        assert row["step_time_max_s"] == pytest.approx(result.solve_times.max())
        assert row["setup_max_s"] == pytest.approx(result.setup_times.max()) and row["setup_max_s"] > 0
        assert row["applied_plans_scored"] == row["solves"] - row["fallbacks"]
        assert row["max_dual_residual"] is not None and row["max_dual_residual"] < 1e-3
    assert "qp/daqp" in table(rows(run)) and "rti/hpipm" in table(rows(run))


def test_a_budget_hit_is_counted_and_the_fallback_applied():
    run = run_own_loop(OwnLoopRun([capture_stage_scenario(3.0)], [("qp", "osqp")], [5], max_iter=2))
    row = rows(run)[0]
    assert row["budget_hits"] == row["solves"] == row["fallbacks"] == row["failed_solves"] > 0
    assert row["longest_failure_streak"] == row["solves"] and row["applied_plans_scored"] == 0


def test_bad_settings_are_refused_before_any_hunt():
    with pytest.raises(BenchmarkError, match="scenarios"):
        run_own_loop(OwnLoopRun([], [("qp", "osqp")], [1]))
    with pytest.raises(BenchmarkError, match="deadline"):
        run_own_loop(OwnLoopRun([capture_stage_scenario(3.0)], [("qp", "osqp")], [1], deadline=-1.0))


def test_the_command_runs_own_loop_alone(capsys):
    assert main(["compare", "--mode", "own-loop", "cold"]) == 2
    assert "give it alone" in capsys.readouterr().err
    assert main(["compare", "--mode", "own-loop", "--pair", "qp:osqp", "--hunts", "0", "--horizon", "1",
                 "--max-iter", "1", "--window", "5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["settings"]["scenarios"] == ["paper-open", "paper-obstacles"] and out["settings"]["max_iter"] == 1
    assert out["rows"][0]["budget_hits"] == out["rows"][0]["solves"] > 0


@pytest.mark.slow
def test_ctrl_c_keeps_the_rows_of_the_hunts_finished(tmp_path):
    """Ctrl-C during an own-loop run prints the rows of every hunt finished, then exits 130, within a few seconds."""
    import os
    import re
    import signal
    import subprocess
    import sys
    import time

    command = [sys.executable, "-m", "mpc_hunt.cli", "compare", "--mode", "own-loop", "--pair", "qp:daqp",
               "--pair", "rti:hpipm", "--hunts", "0", "--horizon", "1", "5", "10"]
    env = {**os.environ, "COLUMNS": "200"}
    with subprocess.Popen(command, stdout=subprocess.PIPE, stderr=open(tmp_path / "err", "w"), text=True,
                          env=env) as run:
        deadline = time.monotonic() + 120
        while not any(int(n) >= 1 for n in re.findall(r"(\d+)/12 hunts", (tmp_path / "err").read_text())):
            assert time.monotonic() < deadline and run.poll() is None, (tmp_path / "err").read_text()
            time.sleep(0.2)
        stopped = time.monotonic()
        run.send_signal(signal.SIGINT)
        out, _ = run.communicate(timeout=30)
    assert run.returncode == 130 and time.monotonic() - stopped < 5
    assert "qp/daqp" in out and "interrupted: kept what was finished" in (tmp_path / "err").read_text()


def test_a_hunt_whose_capture_stage_keeps_failing_is_abandoned_at_its_time():
    """Every solve capped at 2 iterations fails: after ``abandon_after`` s of them in a row the hunt stops."""
    run = run_own_loop(OwnLoopRun([capture_stage_scenario(3.0)], [("qp", "osqp")], [5], max_iter=2, abandon_after=0.5))
    result = run.hunts[0].result
    assert result.termination == "abandoned" and not result.captured
    assert len(result.solve_times) == result.steps == 5         # 0.5 s of T = 0.1 s steps, the last one applied
    row = rows(run)[0]
    assert row["abandoned"] == 1 and row["captured"] == 0 and row["longest_failure_streak"] == 5
    with pytest.raises(BenchmarkError, match="abandon_after"):
        run_own_loop(OwnLoopRun([capture_stage_scenario(3.0)], [("qp", "osqp")], [1], abandon_after=0.0))


def test_hunts_on_two_worker_processes_are_the_hunts_of_one():
    """The same tasks on two processes: the same hunts (no time limit, so nothing depends on the clock)."""
    scenario = capture_stage_scenario(2.0)
    pairs = [("qp", "daqp"), ("rti", "hpipm")]
    one = run_own_loop(OwnLoopRun([scenario], pairs, [1, 3]))
    two = run_own_loop(OwnLoopRun([scenario], pairs, [1, 3]), workers=2)
    key = lambda h: (h.formulation, h.backend, h.horizon)      # noqa: E731
    assert sorted(map(key, two.hunts)) == sorted(map(key, one.hunts)) and len(one.hunts) == 4
    by = {key(h): h.result for h in one.hunts}
    for hunt in two.hunts:
        np.testing.assert_array_equal(hunt.result.defenders, by[key(hunt)].defenders)
        assert hunt.result.termination == by[key(hunt)].termination


def test_own_loop_settings_are_refused_in_the_other_modes(capsys):
    for flag, value in (("--workers", "1"), ("--abandon-after", "5"), ("--deadline", "0.02")):
        assert main(["compare", "--mode", "cold", flag, value]) == 2
        assert f"{flag}: own-loop only" in capsys.readouterr().err


def test_a_step_past_its_limit_beyond_its_own_overhead_is_counted():
    """Under a time limit, each step's own overhead is recorded, and a step counts as past "the limit plus the
    measured overhead" exactly when its time less its overhead exceeds the limit."""
    run = run_own_loop(OwnLoopRun([capture_stage_scenario(3.0)], [("sqp", "osqp")], [3], time_limit=1e-4))
    hunt = run.hunts[0]
    r = hunt.result
    assert hunt.time_limit == 1e-4 and len(r.overhead_times) == len(r.solve_times) > 0
    assert np.all((r.overhead_times > 0) & (r.overhead_times <= r.solve_times))
    over = r.solve_times - r.overhead_times - 1e-4
    row = rows(run)[0]
    assert row["past_limit_and_overhead"] == int(np.sum(over > 0))
    assert row["largest_overrun_s"] == pytest.approx(over.max())
    assert row["overhead_max_s"] == pytest.approx(r.overhead_times.max())
    assert len(r.off_cpu_times) == len(r.solve_times) and np.all(r.off_cpu_times >= 0)
    assert len(r.stolen_times) == len(r.solve_times) and np.all(r.stolen_times == 0)   # read with a deadline only
    on_cpu = over - r.off_cpu_times
    assert row["past_limit_on_cpu"] == int(np.sum(on_cpu > 0)) <= row["past_limit_and_overhead"]
    assert row["largest_overrun_on_cpu_s"] == pytest.approx(on_cpu.max())
    unlimited = rows(run_own_loop(OwnLoopRun([capture_stage_scenario(3.0)], [("qp", "osqp")], [1])))[0]
    assert unlimited["past_limit_and_overhead"] is None and unlimited["largest_overrun_s"] is None
    assert unlimited["past_limit_on_cpu"] is None and unlimited["largest_overrun_on_cpu_s"] is None


def test_a_step_the_hypervisor_took_time_from_is_the_machines(monkeypatch):
    """Under a deadline, the machine's steal is read around each step; a step past its limit during which the
    hypervisor took the time it overran by is not counted as the step's own on the CPU."""
    ticks = iter(np.arange(0.0, 1e4, 0.5))  # every reading half a second on: each step saw 0.5 s stolen
    monkeypatch.setattr(batch, "stolen", lambda: float(next(ticks)))
    run = run_own_loop(OwnLoopRun([capture_stage_scenario(3.0)], [("sqp", "osqp")], [3], time_limit=1e-4,
                                  deadline=0.02))
    r = run.hunts[0].result
    assert len(r.stolen_times) == len(r.solve_times) > 0 and np.all(r.stolen_times == 0.5)
    summary = hunt_summary(run.hunts[0])
    assert summary["past_limit_and_overhead"] > 0 and summary["past_limit_on_cpu"] == 0
    assert summary["past_limit_stolen"] == summary["past_limit_and_overhead"]

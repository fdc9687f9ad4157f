"""The command line's limits: every count bounded, every output path checked before any work, foreign results
files and scheduler addresses refused in one line, and Ctrl-C stopping a command at once, even inside IPOPT."""

from __future__ import annotations

import os
import select
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from mpc_hunt.cli.commands import main
from mpc_hunt.sweep.store import SweepStore
from scenario_text import scenario_toml

ROOT = Path(__file__).resolve().parents[2]
PROC = Path("/proc")     # a folder no process can create a file or folder in, root included
UNWRITABLE = PROC / "mpc-hunt-test"


def _status(argv: list[str]) -> int:
    """The exit status of ``mpc-hunt argv`` (argparse's refusals exit by SystemExit)."""
    try:
        return main(argv)
    except SystemExit as exc:
        return exc.code


@pytest.mark.parametrize("argv", [
    ["simulate", "--horizon", "201"], ["solve", "--horizon", "10000"], ["compare", "--horizon", "1", "999"],
    ["compare", "--starts", "101"], ["compare", "--limit", "100001"], ["compare", "--seed", str(2**63)],
    ["problems", "--build", "x.json", "--every", "100001"], ["problems", "--build", "x.json", "--run-length", "1001"],
    ["problems", "--build", "x.json", "--random", "1001"], ["problems", "--build", "x.json", "--seed", str(2**64)],
    ["sweep", "--hunts", "1000001"], ["sweep", "--seed", str(2**63)], ["sweep", "--workers", "100000"],
    ["sweep", "--strategy", "paper:qp:daqp:201"],
])
def test_every_count_has_an_upper_bound(argv, capsys):
    assert _status(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and ("at most" in err or "from 1 to 200" in err), err


@pytest.fixture
def no_work(monkeypatch):
    """Any simulation, problem-set build or benchmark is an error: the command must refuse first."""
    def refuse(*args, **kwargs):
        raise AssertionError("work started before the output path was checked")
    for target in ("mpc_hunt.sim.simulator.simulate", "mpc_hunt.bench.build_problems.build_problem_set",
                   "mpc_hunt.bench.compare.run_compare", "mpc_hunt.sweep.runner.run_local"):
        monkeypatch.setattr(target, refuse)


@pytest.mark.parametrize("argv", [
    ["simulate", "--plot", str(PROC / "hunt.png")], ["simulate", "--animate", str(PROC / "hunt.gif")],
    ["compare", "--plot", str(UNWRITABLE)], ["compare", "--report", str(UNWRITABLE)],
    ["compare", "--csv", str(PROC / "rows.csv")], ["problems", "--build", str(PROC / "set.json")],
    ["solve", "--save-state", str(PROC / "state.json")], ["sweep", "--hunts", "1", "--output",
                                                                 str(PROC / "sweep.db")],
])
def test_every_output_path_is_checked_before_any_work(argv, no_work, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "cannot write in /proc" in err, err


@pytest.mark.parametrize("address", ["foo", "tcp://", "tcp://127.0.0.1:notaport", "::::"])
def test_a_malformed_scheduler_address_is_one_line_and_writes_nothing(address, tmp_path, capsys):
    out = tmp_path / "s.db"
    assert main(["sweep", "--hunts", "1", "--dask-scheduler", address, "--output", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"--dask-scheduler: cannot connect to {address}" in err and not out.exists()


def test_a_sweep_on_dask_without_dask_says_how_to_install_it(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)        # its import fails
    assert main(["sweep", "--hunts", "1", "--dask-scheduler", "tcp://127.0.0.1:8786", "--output",
                 str(tmp_path / "s.db")]) == 2
    assert capsys.readouterr().err == 'mpc-hunt sweep: error: --dask-scheduler: needs Dask: pip install ' \
                                      '"mpc-hunt[dask]"\n'


@pytest.mark.parametrize("arguments, numpy_version", [
    ("{not json", "2"), ("[1, 2]", "2"), ('{"strategies": "apf", "hunts": 1, "seed": 0, "ranges": {}}', "2"),
    ('{"strategies": ["apf"], "hunts": true, "seed": 0, "ranges": {}}', "2"), (None, "2"),
    ('{"strategies": ["apf"], "hunts": 1, "seed": 0, "ranges": {}}', 3),
])
def test_a_results_file_with_foreign_metadata_is_one_line_naming_it(arguments, numpy_version, tmp_path, capsys):
    path = tmp_path / "foreign.db"
    SweepStore(path, {"strategies": ["apf"], "hunts": 1, "seed": 0, "ranges": {}}).close()
    with sqlite3.connect(path) as db:
        db.execute("drop table sweep")
        db.execute("create table sweep (arguments, numpy)")
        db.execute("insert into sweep values (?, ?)", (arguments, numpy_version))
    for argv in (["sweep-report", str(path)], ["sweep", "--resume", "--hunts", "1", "--strategy", "apf",
                                                "--output", str(path)]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and str(path) in err and "stored arguments" in err, err


def _in_capture_stage(tmp_path: Path) -> Path:
    """Three defenders inside the attacker's perception radius, all on one side: IPOPT solves from step 0, and the
    hunt runs for minutes."""
    path = tmp_path / "close.toml"
    path.write_text(scenario_toml("close", [(4.2, 5.0), (4.3, 5.5), (4.3, 4.5)], time_limit=600.0))
    return path


@pytest.mark.parametrize("command", [["simulate", "--controller", "paper", "--formulation", "nlp", "--json"],
                                     ["problems", "--random", "0", "--build"]])
def test_ctrl_c_stops_a_command_inside_ipopt_at_once_with_nothing_written(command, tmp_path):
    out = tmp_path / "set.json"
    argv = [*command, *([str(out)] if command[-1] == "--build" else []), "--scenario",
            str(_in_capture_stage(tmp_path))]
    process = subprocess.Popen([sys.executable, "-m", "mpc_hunt.cli", *argv], cwd=tmp_path,
                               env={**os.environ, "PYTHONPATH": str(ROOT)}, start_new_session=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    time.sleep(4.0)                          # imports done, the hunt's capture stage solving with IPOPT
    assert process.poll() is None, process.communicate()
    start = time.monotonic()
    os.killpg(process.pid, signal.SIGINT)    # what Ctrl-C in a terminal does: the whole process group
    stdout, stderr = process.communicate(timeout=30)
    assert time.monotonic() - start < 5.0
    assert process.returncode in (130, 2), stderr
    assert "interrupted" in stderr.decode() and stdout == b""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["close.toml"]


def test_ctrl_c_clears_simulates_progress_bar_before_its_line(tmp_path):
    process = subprocess.Popen([sys.executable, "-m", "mpc_hunt.cli", "simulate", "--controller", "paper",
                                "--formulation", "nlp", "--scenario", str(_in_capture_stage(tmp_path))],
                               cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(ROOT)}, start_new_session=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    shown, deadline = b"", time.monotonic() + 60
    try:
        while b"hunt:" not in shown:             # the bar, shown after 2 s of the hunt
            assert select.select([process.stderr], [], [], max(0.0, deadline - time.monotonic()))[0], shown
            chunk = os.read(process.stderr.fileno(), 4096)
            assert chunk, process.communicate()
            shown += chunk
        os.killpg(process.pid, signal.SIGINT)
        stdout, rest = process.communicate(timeout=30)
    finally:
        if process.poll() is None:              # a failed test leaves no ten-minute hunt behind
            os.killpg(process.pid, signal.SIGKILL)
    assert process.returncode == 130 and stdout == b""
    text = (shown + rest).decode()
    assert text.rsplit("\r", 1)[-1] == "mpc-hunt simulate: interrupted: nothing written\n", text[-300:]
    assert text.rsplit("\r", 2)[-2].strip() == "", text[-300:]     # the bar blanked, the line from its start


def test_a_ctrl_c_no_command_catches_itself_is_one_line_and_status_130(monkeypatch, capsys):
    """Outside the sections a command stops itself in (a solve, a sweep's hunts), Ctrl-C is still one line and
    128 + SIGINT, as the commands that stop at once end."""
    from mpc_hunt.cli import commands

    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(commands, "_backends", interrupted)
    assert commands.main(["backends"]) == 130
    assert capsys.readouterr().err == "mpc-hunt backends: interrupted\n"

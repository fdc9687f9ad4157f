"""``mpc-hunt export``: the stage-form steps as C, built with the Makefile they come with, give Python's plan."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

from mpc_hunt.cli.commands import main


@pytest.mark.skipif(shutil.which("make") is None or shutil.which("gcc") is None, reason="needs make and gcc")
@pytest.mark.parametrize("formulation, objective", [("rti", "paper"), ("stage-sqp", "paper"), ("rti", "enclose")])
def test_the_exported_program_prints_pythons_plan(tmp_path, capsys, formulation, objective):
    """Each stage form, and the default controller's step (enclose: no Eq. 14 in its stages)."""
    folder = tmp_path / "board"
    assert main(["export", "--scenario", "paper-obstacles", "--horizon", "2", "--formulation", formulation,
                 "--objective", objective, "--output", str(folder)]) == 0
    assert "capture_step" in capsys.readouterr().out
    subprocess.run(["make", "-s", "-C", str(folder), "CFLAGS=-O1"], check=True, capture_output=True, timeout=300)
    with open(folder / "input.txt") as stdin:
        run = subprocess.run([str(folder / "capture_step")], stdin=stdin, capture_output=True, text=True,
                             timeout=60)
    assert run.returncode == 0, run.stderr
    plan, expected = np.array(run.stdout.split(), dtype=float), np.loadtxt(folder / "expected.txt")
    assert plan.shape == expected.shape and plan.size > 0
    np.testing.assert_allclose(plan, expected, rtol=0, atol=1e-9)
    # states one after another, each timed on request
    twice = (folder / "input.txt").read_text() * 2
    run = subprocess.run([str(folder / "capture_step"), "--time"], input=twice, capture_output=True, text=True,
                         timeout=60)
    assert run.returncode == 0 and run.stderr.count("time_us") == 2
    np.testing.assert_array_equal(np.array(run.stdout.split(), dtype=float), np.tile(plan, 2))
    # a state with a number missing is a one-line error, not a plan
    short = " ".join((folder / "input.txt").read_text().split()[:-1])
    run = subprocess.run([str(folder / "capture_step")], input=short, capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and "missing" in run.stderr


@pytest.mark.skipif(shutil.which("make") is None or shutil.which("gcc") is None, reason="needs make and gcc")
def test_the_balance_mode_and_a_blasfeo_of_ones_own(tmp_path, capsys):
    plans = {}
    for mode in ("robust", "balance"):
        folder = tmp_path / mode
        assert main(["export", "--scenario", "paper-obstacles", "--horizon", "2", "--hpipm-mode", mode,
                     "--output", str(folder)]) == 0
        plans[mode] = np.loadtxt(folder / "expected.txt")
    assert "(enum hpipm_mode) 2" in (folder / "capture_step.c").read_text()      # balance, in the C step too
    assert 0 < np.max(np.abs(plans["balance"] - plans["robust"])) < 1e-5
    own = tmp_path / "blasfeo"                    # a BLASFEO of one's own: here the wheel's, through a link
    own.mkdir()
    deps = next(line.split("?=")[1].strip() for line in (folder / "Makefile").read_text().splitlines()
                if line.startswith("DEPS ?="))
    for name in ("libblasfeo.so", "libblasfeo.so.0"):
        (own / name).symlink_to(f"{deps}/{name}")
    subprocess.run(["make", "-s", "-C", str(folder), "CFLAGS=-O1", f"BLASFEO={own}"], check=True, capture_output=True,
                   timeout=300)
    loaded = subprocess.run(["ldd", str(folder / "capture_step")], capture_output=True, text=True).stdout
    assert f"{own}/libblasfeo.so.0" in loaded                   # HPIPM runs on it, not on the wheel's
    with open(folder / "input.txt") as stdin:
        run = subprocess.run([str(folder / "capture_step")], stdin=stdin, capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    np.testing.assert_allclose(np.array(run.stdout.split(), dtype=float), plans["balance"], rtol=0, atol=1e-9)


def test_a_formulation_that_is_not_a_stage_step_is_one_line(tmp_path, capsys):
    assert main(["export", "--formulation", "nlp", "--output", str(tmp_path / "board")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "formulation: only the stage-form steps" in err and "stage-sqp" in err


def test_an_output_that_is_a_file_is_one_line(tmp_path, capsys):
    (tmp_path / "taken").write_text("")
    assert main(["export", "--output", str(tmp_path / "taken")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "not a folder" in err


@pytest.mark.skipif(shutil.which("make") is None or shutil.which("gcc") is None, reason="needs make and gcc")
def test_one_robots_distributed_step_prints_pythons_plan(tmp_path, capsys):
    """--robot picks whose step; its C prints the plan Python's robot loop gave from the same inputs."""
    folders = {}
    for robot in ("1", "3"):
        folders[robot] = tmp_path / f"robot{robot}"
        assert main(["export", "--scenario", "paper-obstacles", "--horizon", "3", "--formulation", "distributed",
                     "--objective", "enclose", "--robot", robot, "--output", str(folders[robot])]) == 0
        assert f"robot {robot} of " in capsys.readouterr().out
    inputs = {r: np.loadtxt(f / "input.txt") for r, f in folders.items()}
    assert inputs["1"].shape == inputs["3"].shape and not np.array_equal(inputs["1"], inputs["3"])
    folder = folders["3"]
    subprocess.run(["make", "-s", "-C", str(folder), "CFLAGS=-O1"], check=True, capture_output=True, timeout=300)
    with open(folder / "input.txt") as stdin:
        run = subprocess.run([str(folder / "capture_step")], stdin=stdin, capture_output=True, text=True,
                             timeout=60)
    assert run.returncode == 0, run.stderr
    np.testing.assert_allclose(np.array(run.stdout.split(), dtype=float), np.loadtxt(folder / "expected.txt"),
                               rtol=0, atol=1e-9)


@pytest.mark.parametrize("arguments, message", [
    (["--robot", "4"], "--robot 4: 3 defenders are planned at this state (1 to 3)"),
    (["--objective", "paper"], "formulation distributed poses the enclose objective, not 'paper'")])
def test_a_robot_that_is_not_there_or_the_papers_objective_is_one_line(tmp_path, capsys, arguments, message):
    command = ["export", "--formulation", "distributed", "--objective", "enclose", "--output", str(tmp_path / "x")]
    assert main(command + arguments) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and not (tmp_path / "x").exists()

"""``mpc-hunt export``: the stage-form steps as C, built with the Makefile they come with, give Python's plan."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

from mpc_hunt.capture.iteration import ONE_QP, QPIteration
from mpc_hunt.cli.commands import main
from mpc_hunt.errors import MpcHuntError, SettingError
from mpc_hunt.solving.export import check_export


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


def test_the_solvers_export_of_a_formulation_that_is_not_a_stage_step_is_refused(tmp_path):
    from mpc_hunt.solving.solver import CaptureSolver

    with pytest.raises(MpcHuntError, match="formulation: only the stage-form steps"):  # not an AttributeError
        CaptureSolver("nlp", "ipopt").export(tmp_path / "board", None)


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
    (["--objective", "paper"], "formulation distributed poses the enclose objective, not the paper objective")])
def test_a_robot_that_is_not_there_or_the_papers_objective_is_one_line(tmp_path, capsys, arguments, message):
    command = ["export", "--formulation", "distributed", "--objective", "enclose", "--output", str(tmp_path / "x")]
    assert main(command + arguments) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and not (tmp_path / "x").exists()


# --- options an export cannot use, and its targets ------------------------------------------------------------------

@pytest.mark.parametrize("arguments, message", [
    (["--formulation", "rti", "--robot", "3"], "--robot: only a formulation that plans robot by robot"),
    (["--formulation", "distributed", "--objective", "enclose", "--hpipm-mode", "balance"],
     "--hpipm-mode: the step is solved by daqp-condensed"),
    (["--target", "aarch64-linux"], "--target aarch64-linux: HPIPM and BLASFEO come built for this machine only"),
    (["--formulation", "stage-sqp", "--objective", "enclose", "--backend", "daqp-condensed"],
     "its export writes one QP a step")])
def test_an_option_the_export_cannot_use_is_refused(tmp_path, capsys, arguments, message):
    assert main(["export", "--output", str(tmp_path / "x")] + arguments) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err


def test_the_exported_backends_are_those_that_declare_a_step_to_export():
    """The command line's --backend choices come from the backends' ``exports`` (none for a solver of other QPs)."""
    from mpc_hunt.cli.commands import EXPORT_BACKENDS
    from mpc_hunt.solving import registry

    exports = {name: registry.backend_class(name).exports for name in registry.BACKENDS}
    assert {"hpipm": "hpipm", "hpipm-codegen": "hpipm", "daqp-condensed": "condensed"}.items() <= exports.items()
    assert set(EXPORT_BACKENDS) == {name for name, step in exports.items() if step}
    assert exports["osqp"] is None and exports["daqp"] is None


@pytest.mark.parametrize("target, exports, iteration, field", [
    ("sparc", "condensed", ONE_QP, "target"), ("aarch64-linux", "hpipm", ONE_QP, "target"),
    ("host", "condensed", QPIteration(30, 1e-4), "backend")])
def test_the_exports_refusals_name_its_fields_not_the_command_lines_flags(target, exports, iteration, field):
    with pytest.raises(SettingError) as refused:
        check_export(target, exports, iteration)
    assert refused.value.fields == (field,) and "--" not in str(refused.value)


@pytest.mark.parametrize("output", ["", "."])
def test_the_current_folder_is_not_an_output(tmp_path, monkeypatch, capsys, output):
    monkeypatch.chdir(tmp_path)
    assert main(["export", "--output", output]) == 2
    err = capsys.readouterr().err
    assert "that is the current folder" in err and err.count("\n") == 1 and not list(tmp_path.iterdir())


def test_an_unknown_target_or_a_missing_cross_compiler_is_one_line(tmp_path, monkeypatch, capsys):
    command = ["export", "--formulation", "distributed", "--objective", "enclose", "--output", str(tmp_path / "x")]
    with pytest.raises(SystemExit) as exit_:
        main(command + ["--target", "sparc"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "--target" in err and "sparc" in err and err.count("\n") == 1
    which = shutil.which
    monkeypatch.setattr(shutil, "which", lambda name, *a, **k: None if "aarch64" in name else which(name, *a, **k))
    assert main(command + ["--target", "aarch64-linux"]) == 2
    err = capsys.readouterr().err
    assert "the cross compiler aarch64-linux-gnu-gcc is not installed (apt-get install gcc-aarch64-linux-gnu)" in err
    assert err.count("\n") == 1 and not (tmp_path / "x").exists()


@pytest.mark.skipif(shutil.which("make") is None or shutil.which("gcc") is None, reason="needs make and gcc")
@pytest.mark.parametrize("backend", ["daqp-condensed", "hpipm"])
def test_the_exported_program_refuses_malformed_input(tmp_path, backend):
    """A token that is not a number, a non-finite number, trailing numbers that make no state: one line on stderr,
    exit 2, and no plan for that state (the states before it are printed)."""
    folder = tmp_path / "board"
    assert main(["export", "--scenario", "paper-obstacles", "--horizon", "2", "--formulation", "distributed",
                 "--objective", "enclose", "--backend", backend, "--output", str(folder)]) == 0
    subprocess.run(["make", "-s", "-C", str(folder), "CFLAGS=-O1"], check=True, capture_output=True, timeout=600)
    state = (folder / "input.txt").read_text()
    plan = len((folder / "expected.txt").read_text().split())
    numbers = state.split()

    def changed(i: int, token: str) -> str:
        return " ".join(numbers[:i] + [token] + numbers[i + 1:]) + "\n"

    cases = {state + "garbage\n": "state 1: theta[0]: 'garbage' is not a number",
             state + " ".join(numbers[:3]): "state 1: theta[3] missing",
             state + changed(5, "nan"): "state 1: theta[5]: 'nan' is not finite",
             changed(len(numbers) - 1, "1e999"): f"state 0: reference[{plan - 1}]: '1e999' is not finite",
             changed(0, "0.5x"): "state 0: theta[0]: '0.5x' is not a number",
             changed(2, "-inf"): "state 0: theta[2]: '-inf' is not finite"}
    for text, message in cases.items():
        run = subprocess.run([str(folder / "capture_step")], input=text, capture_output=True, text=True, timeout=60)
        assert run.returncode == 2 and run.stderr.startswith(f"input: {message}"), run.stderr
        assert run.stderr.count("\n") == 1
        printed = len(run.stdout.split())
        assert printed == (plan if message.startswith("state 1") else 0)


def _robot_inputs(size: int, states: int) -> tuple:
    """Every robot's step inputs along the committed team_size states of ``size`` robots (the default backend's
    closed loop), the first problem, and Python's plans."""
    from pathlib import Path

    from mpc_hunt import CaptureMPC
    from studies.team_size import load_states, problems_of

    committed = load_states(Path(__file__).resolve().parents[2] / "studies" / "team_size" / "states.json")
    problems = problems_of(size, committed[size][:states])
    mpc = CaptureMPC("distributed", score=False)
    team = mpc.solver.step_for(problems[0])
    inputs, plans = [], []
    for problem in problems:
        assert mpc.loop_step(problem).usable
        for robot in team.robots:
            inputs.append(np.concatenate([robot.theta, robot.reference.reshape(-1)]))
            plans.append(robot.plan.reshape(-1).copy())
    return problems[0], inputs, plans


@pytest.mark.skipif(shutil.which("make") is None or shutil.which("aarch64-linux-gnu-gcc") is None
                    or shutil.which("qemu-aarch64") is None,
                    reason="needs make, aarch64-linux-gnu-gcc and qemu-aarch64 (Debian: gcc-aarch64-linux-gnu, "
                           "qemu-user)")
def test_a_robots_step_cross_compiled_for_aarch64_gives_the_hosts_plans(tmp_path):
    """Robot 1's step exported by the CLI for aarch64 Linux, run under qemu-aarch64 on every robot's inputs of
    the committed states of 6 robots: the host's plans (Python's, which the host's C gives to the bit) within
    1e-9 m (measured: 0)."""
    from mpc_hunt import CaptureSolver

    problem, inputs, plans = _robot_inputs(6, 5)
    folder = tmp_path / "arm"
    CaptureSolver("distributed").export(folder, problem, robot=0, target="aarch64-linux")
    assert "CC = aarch64-linux-gnu-gcc" in (folder / "Makefile").read_text()
    subprocess.run(["make", "-s", "-C", str(folder), "CFLAGS=-O2"], check=True, capture_output=True, timeout=900)
    assert (folder / "capture_step").read_bytes()[18] == 183          # the ELF header's machine: EM_AARCH64
    text = "\n".join(" ".join(f"{v:.17g}" for v in x) for x in inputs) + "\n"
    run = subprocess.run(["qemu-aarch64", "-L", "/usr/aarch64-linux-gnu", str(folder / "capture_step")], input=text,
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    out = np.array(run.stdout.split(), dtype=float)
    assert out.shape == (len(inputs) * plans[0].size,)
    np.testing.assert_allclose(out, np.concatenate(plans), rtol=0, atol=1e-9)


@pytest.mark.skipif(shutil.which("make") is None or shutil.which("arm-none-eabi-gcc") is None
                    or shutil.which("qemu-system-arm") is None,
                    reason="needs make, arm-none-eabi-gcc with newlib and qemu-system-arm (Debian: gcc-arm-none-eabi, "
                           "libnewlib-arm-none-eabi, qemu-system-arm)")
def test_a_robots_step_on_a_bare_metal_cortex_m7_gives_the_hosts_plans(tmp_path):
    """Robot 1's step built for a Cortex-M7 without an operating system, on qemu's mps2-an500 board, the inputs of
    the committed states compiled in: the host's plans within 1e-9 m (measured: 4e-16), each step's SysTick
    count at 40 instructions a tick (the calibration loop's 2,000,000 instructions), heap and stack reported."""
    from mpc_hunt import CaptureSolver

    problem, inputs, plans = _robot_inputs(6, 2)
    folder = tmp_path / "m7"
    CaptureSolver("distributed").export(folder, problem, robot=0, target="cortex-m7")
    (folder / "input.txt").write_text("\n".join(" ".join(f"{v:.17g}" for v in x) for x in inputs) + "\n")
    subprocess.run(["make", "-s", "-C", str(folder)], check=True, capture_output=True, timeout=900)
    run = subprocess.run(["make", "-s", "-C", str(folder), "run"], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    out = np.array(run.stdout.split(), dtype=float)
    assert out.shape == (len(inputs) * plans[0].size,)
    np.testing.assert_allclose(out, np.concatenate(plans), rtol=0, atol=1e-9)
    report = dict(line.split(maxsplit=1) for line in run.stderr.splitlines() if not line.startswith("ticks"))
    assert report["calibration"] == "2000000 50000"
    ticks = [int(line.split()[1]) for line in run.stderr.splitlines() if line.startswith("ticks")]
    assert len(ticks) == len(inputs) and min(ticks) > 0
    assert 0 < int(report["heap"]) < 256 * 1024 and 0 < int(report["stack"]) < 64 * 1024

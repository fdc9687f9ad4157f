"""The scripts in examples/: each runs to its end at its small default size, imports only the public API, and is
shown on the documentation site."""

from __future__ import annotations

import ast
import importlib
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
# The public API: the package and its public subpackages, each with its __all__ (docs/reference/).
PUBLIC_MODULES = ("mpc_hunt", "mpc_hunt.bench", "mpc_hunt.capture", "mpc_hunt.cli", "mpc_hunt.control",
                  "mpc_hunt.envs", "mpc_hunt.plots", "mpc_hunt.sim", "mpc_hunt.solving", "mpc_hunt.sweep",
                  "mpc_hunt.world")
# Each script, the arguments CI runs it with, and what its output must say when it ran to its end.
RUNS = {
    "first_hunt.py": ([], "termination: captured"),
    "solve_one_problem.py": ([], "next state, warm: qp on daqp: optimal"),
    "compare_pairs.py": ([], "own loop, enclose on paper-open"),
    "embed_step.py": ([], "captured at t = "),
    "sweep_hunts.py": ([], "hunts"),
    "attackers_and_agents.py": ([], "DefenderEnv against gap"),
    "export_to_board.py": (["--cflags=-O1"], "wrote "),
}
TIMEOUT = 300  # s: a hung example fails; each takes a minute or less on two idle cores


def scripts() -> list[Path]:
    return sorted(EXAMPLES.glob("*.py"))


def test_every_example_is_run_here():
    assert {p.name for p in scripts()} == set(RUNS)


@pytest.mark.slow
@pytest.mark.examples
@pytest.mark.parametrize("name", sorted(RUNS))
def test_the_example_runs_to_its_end(name, tmp_path):
    arguments, said = RUNS[name]
    env = os.environ | {"MPC_HUNT_CACHE": str(tmp_path / "cache"), "MPLBACKEND": "Agg"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    started = time.perf_counter()
    run = subprocess.run([sys.executable, str(EXAMPLES / name), *arguments], cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=TIMEOUT)
    assert run.returncode == 0, run.stderr[-2000:]
    assert said in run.stdout, run.stdout[-2000:]
    if name == "export_to_board.py" and shutil.which("make") and shutil.which("cc"):
        assert "built and run: " in run.stdout, run.stdout  # the C program's plan beside Python's
    print(f"{name}: {time.perf_counter() - started:.1f} s")


def imports(path: Path) -> list[tuple[str, str | None]]:
    """(module, name) for every import of the script: name None for ``import module``."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found += [(alias.name, None) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            assert node.level == 0, f"{path.name}: a relative import"
            found += [(node.module, alias.name) for alias in node.names]
    return found


def private_imports(path: Path) -> list[str]:
    """What the script imports of mpc_hunt beyond the public API."""
    wrong = []
    for module, name in imports(path):
        if module.split(".")[0] != "mpc_hunt":
            continue
        if module not in PUBLIC_MODULES or any(part.startswith("_") for part in module.split(".")):
            wrong.append(module if name is None else f"{module}.{name}")
        elif name is not None and (name.startswith("_") or name not in importlib.import_module(module).__all__):
            wrong.append(f"{module}.{name}")
    return wrong


@pytest.mark.parametrize("name", sorted(RUNS))
def test_the_example_imports_only_the_public_api(name):
    assert private_imports(EXAMPLES / name) == []


def test_the_import_check_refuses_what_is_private(tmp_path):
    script = tmp_path / "private.py"
    script.write_text("from mpc_hunt.world.hunting_circle import success_test\nfrom mpc_hunt import _x, simulate\n"
                      "import mpc_hunt.solving.step\nfrom mpc_hunt.sweep import tasks\n"
                      "from mpc_hunt.sim import simulate\n")
    assert private_imports(script) == ["mpc_hunt.world.hunting_circle.success_test", "mpc_hunt._x",
                                       "mpc_hunt.solving.step", "mpc_hunt.sweep.tasks"]


def test_every_example_is_shown_on_the_site_and_the_readme_points_to_the_embedded_step():
    pages = "\n".join(p.read_text(encoding="utf-8") for p in (ROOT / "docs").rglob("*.md"))
    for name in RUNS:
        assert f'--8<-- "examples/{name}"' in pages, name
    assert "examples/embed_step.py" in (ROOT / "README.md").read_text(encoding="utf-8")

"""The spine's promises: one-way imports, solvers on first use, compatibility derived from the registry."""

from __future__ import annotations

import ast
import pkgutil
import subprocess
import sys
from pathlib import Path

import pytest

import formulations
import mpc_hunt
from mpc_hunt import CaptureSolver, SolverNotFoundError, solve
from mpc_hunt.solving import registry
from mpc_hunt.solving.backends.daqp import DaqpBackend
from conftest import problem_at

ROOT = Path(__file__).resolve().parents[1]
TOP = ("mpc_hunt", "formulations")


def _modules() -> list[str]:
    names = []
    for package in (mpc_hunt, formulations):
        names.append(package.__name__)
        names += [m.name for m in pkgutil.walk_packages(package.__path__, package.__name__ + ".")
                  if not m.name.endswith(".__main__")]      # importing it runs the command line
    return names


def test_every_module_imports_alone_in_a_fresh_interpreter():
    modules = _modules()
    assert {"formulations.nlp", "mpc_hunt.solving.backends.daqp", "mpc_hunt.cli.commands"} <= set(modules)
    running = {m: subprocess.Popen([sys.executable, "-c", f"import {m}"], cwd=ROOT, stderr=subprocess.PIPE,
                                   text=True) for m in modules}
    failed = {m: p.communicate()[1].strip().splitlines()[-1:] for m, p in running.items()}
    assert {m: err for m, err in failed.items() if running[m].returncode} == {}


def test_the_import_contracts_hold():
    """The layer order, the formulations' place, solver packages and acyclicity: pyproject.toml's contracts."""
    run = subprocess.run([str(Path(sys.executable).with_name("lint-imports")), "--no-cache"], cwd=ROOT,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-1000:]
    assert "5 kept, 0 broken" in run.stdout


def _private_imports(path: Path) -> list[str]:
    """``from mpc_hunt.X… import _name`` (or formulations.…) in ``path`` reaching into another subpackage."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    here = ".".join(path.relative_to(ROOT).with_suffix("").parts[:2])
    return [f"{path.relative_to(ROOT)}: {node.module}.{alias.name}" for node in ast.walk(tree)
            if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] in TOP
            and ".".join(node.module.split(".")[:2]) != here
            for alias in node.names if alias.name.startswith("_") and not alias.name.startswith("__")]


def test_no_module_imports_a_private_name_of_another_package():
    files = [f for top in ("mpc_hunt", "formulations", "studies") for f in (ROOT / top).rglob("*.py")]
    assert [hit for f in files for hit in _private_imports(f)] == []


def test_import_mpc_hunt_loads_no_solver():
    code = ("import sys, mpc_hunt; print(sorted(m for m in ('cvxpy', 'casadi', 'osqp', 'clarabel', 'daqp') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


class SecondDaqp(DaqpBackend):
    """A new backend written against the contract: one class, one registry line."""

    name = "daqp2"


class MissingSolver(DaqpBackend):
    name = "missing"
    package = "no_such_solver_package"
    install = "no-such-solver"


@pytest.fixture
def extra_backends(monkeypatch):
    monkeypatch.setitem(registry.BACKENDS, "daqp2", "test_layers:SecondDaqp")
    monkeypatch.setitem(registry.BACKENDS, "missing", "test_layers:MissingSolver")
    registry.backend_class.cache_clear()
    yield
    registry.backend_class.cache_clear()


def test_a_registered_backend_works_with_every_formulation_of_its_kind(extra_backends, scenario):
    assert ("qp", "daqp2") in registry.pairs() and ("sqp", "daqp2") in registry.pairs()
    assert ("nlp", "daqp2") not in registry.pairs() and ("socp", "daqp2") not in registry.pairs()
    problem = problem_at(scenario, 2)
    assert solve(problem, "qp", "daqp2").objective == pytest.approx(solve(problem, "qp", "daqp").objective,
                                                                      rel=1e-12)


def test_a_missing_solver_is_listed_with_its_install_hint(extra_backends):
    assert ("qp", "missing") not in registry.pairs()
    assert ("qp", "missing") in registry.pairs(installed_only=False)
    with pytest.raises(SolverNotFoundError, match="pip install no-such-solver"):
        CaptureSolver("qp", "missing")

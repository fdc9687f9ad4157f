"""The spine's promises: one-way imports, solvers on first use, compatibility derived from the registry."""

from __future__ import annotations

import pkgutil
import subprocess
import sys
from pathlib import Path

import pytest

import formulations
import mpc_hunt
from mpc_hunt import CaptureSolver, SolverNotFoundError, solve
from mpc_hunt.capture import registry
from mpc_hunt.capture.backends.daqp import DaqpBackend
from conftest import problem_at

ROOT = Path(__file__).resolve().parents[1]


def _modules() -> list[str]:
    names = []
    for package in (mpc_hunt, formulations):
        names.append(package.__name__)
        names += [m.name for m in pkgutil.walk_packages(package.__path__, package.__name__ + ".")
                  if not m.name.endswith(".__main__")]      # importing it runs the command line
    return names


def test_every_module_imports_alone_in_a_fresh_interpreter():
    modules = _modules()
    assert "formulations.nlp" in modules and "mpc_hunt.capture.backends.daqp" in modules and "mpc_hunt.cli.commands" in modules
    running = {m: subprocess.Popen([sys.executable, "-c", f"import {m}"], cwd=ROOT, stderr=subprocess.PIPE,
                                   text=True) for m in modules}
    failed = {m: p.communicate()[1].strip().splitlines()[-1:] for m, p in running.items()}
    assert {m: err for m, err in failed.items() if running[m].returncode} == {}


def test_the_import_contracts_hold():
    """The layer order, the formulations' place, solver packages and acyclicity: pyproject.toml's contracts."""
    run = subprocess.run([str(Path(sys.executable).with_name("lint-imports")), "--no-cache"], cwd=ROOT,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-1000:]
    assert "4 kept, 0 broken" in run.stdout


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

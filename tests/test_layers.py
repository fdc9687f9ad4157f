"""The spine's promises: one-way imports, solvers on first use, compatibility derived from the registry."""

from __future__ import annotations

import ast
import importlib.util
import os
import pkgutil
import subprocess
import sys
from pathlib import Path

import pytest

import mpc_hunt
from mpc_hunt import CaptureSolver, SolverNotFoundError, solve
from mpc_hunt.solving import registry
from mpc_hunt.solving.backends.daqp import DaqpBackend
from conftest import problem_at

ROOT = Path(__file__).resolve().parents[1]
TOP = ("mpc_hunt",)


def _modules() -> list[str]:
    names = []
    for package in (mpc_hunt,):
        names.append(package.__name__)
        names += [m.name for m in pkgutil.walk_packages(package.__path__, package.__name__ + ".")
                  if not m.name.endswith(".__main__")]      # importing it runs the command line
    return names


def _third_party(modules: list[str]) -> list[str]:
    """What our modules import from outside our package (``a.b.c`` for ``from a.b import c``)."""
    names = set()
    for module in modules:
        spec = importlib.util.find_spec(module)
        names |= set(_imported(Path(spec.origin).read_text(encoding="utf-8")))
    return sorted(n for n in names if n.split(".")[0] != "mpc_hunt")


@pytest.mark.skipif(not hasattr(os, "fork"), reason="forks a process per module")
def test_every_module_imports_alone():
    """Each module imported first, alone: no import cycle or missing import hidden by another module's being
    imported before it (tests/import_alone.py: a process per module, forked after the third-party packages)."""
    modules = _modules()
    assert {"mpc_hunt.formulations.nlp", "mpc_hunt.solving.backends.daqp", "mpc_hunt.cli.commands"} <= set(modules)
    run = subprocess.run([sys.executable, str(ROOT / "tests" / "import_alone.py"), *_third_party(modules)],
                         input="\n".join(modules), cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr[-2000:]


def test_a_module_that_cannot_import_alone_is_named(tmp_path):
    """The check above fails when a module's import fails."""
    (tmp_path / "broken_alone.py").write_text("import mpc_hunt.no_such_module\n", encoding="utf-8")
    run = subprocess.run([sys.executable, str(ROOT / "tests" / "import_alone.py"), "numpy"],
                         input="json\nbroken_alone", cwd=tmp_path, capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": str(tmp_path)})
    assert run.returncode == 1 and run.stdout.startswith("broken_alone: ModuleNotFoundError"), run.stdout


def test_the_import_contracts_hold():
    """The layer order, the formulations' place, solver packages and acyclicity: pyproject.toml's contracts."""
    run = subprocess.run([str(Path(sys.executable).with_name("lint-imports")), "--no-cache"], cwd=ROOT,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-1000:]
    assert "8 kept, 0 broken" in run.stdout


STUDIES = {f.stem for f in (ROOT / "studies").glob("*.py")}


def _imported(source: str) -> list[str]:
    """Every name an import in ``source`` binds, in full: ``a.b.c`` for ``from a.b import c`` and ``import a.b.c``."""
    return [f"{node.module}.{alias.name}" if isinstance(node, ast.ImportFrom) else alias.name
            for node in ast.walk(ast.parse(source)) if isinstance(node, (ast.Import, ast.ImportFrom))
            and not (isinstance(node, ast.ImportFrom) and (node.level or not node.module)) for alias in node.names]


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def _forbidden_imports(source: str, path: str) -> list[str]:
    """Imports in ``source`` (of the file ``path``, from the root) of a private name or module (``_name``) of
    another subpackage of mpc_hunt; in a study, also of the command line (``mpc_hunt.cli``) and
    of another study by its bare name: the studies use the package's public API, and one another as
    ``studies.…``."""
    here = ".".join(Path(path).with_suffix("").parts[:2])
    names = _imported(source)
    hits = [n for n in names if n.split(".")[0] in TOP and ".".join(n.split(".")[:2]) != here
            and any(_private(part) for part in n.split(".")[1:])]
    if Path(path).parent == Path("studies"):
        hits += [n for n in names if n.split(".")[:2] == ["mpc_hunt", "cli"] or n.split(".")[0] in STUDIES]
    return [f"{path}: {n}" for n in hits]


def test_no_module_imports_a_private_name_of_another_package_nor_a_study_the_command_line():
    files = [f for top in ("mpc_hunt", "studies") for f in (ROOT / top).rglob("*.py")]
    assert [hit for f in files for hit in _forbidden_imports(f.read_text(encoding="utf-8"),
                                                             f.relative_to(ROOT).as_posix())] == []


def test_the_import_check_finds_a_study_reaching_past_the_public_api():
    source = ("from mpc_hunt.cli.common import count\nimport mpc_hunt.cli.commands\nfrom mpc_hunt import cli\n"
              "from mpc_hunt.sweep.runner import _drawn\nfrom mpc_hunt.solving._hidden import x\n"
              "from study_check import check_result\nimport docs_block\n"
              "from studies.study_check import check_result\nfrom mpc_hunt.interrupt import stop_at_once\n")
    assert [hit.split(": ")[1] for hit in _forbidden_imports(source, "studies/x.py")] == [
        "mpc_hunt.sweep.runner._drawn", "mpc_hunt.solving._hidden.x", "mpc_hunt.cli.common.count",
        "mpc_hunt.cli.commands", "mpc_hunt.cli", "study_check.check_result", "docs_block"]
    assert _forbidden_imports(source, "mpc_hunt/cli/x.py") == ["mpc_hunt/cli/x.py: mpc_hunt.sweep.runner._drawn",
                                                              "mpc_hunt/cli/x.py: mpc_hunt.solving._hidden.x"]


def test_import_mpc_hunt_loads_no_qp_solver_and_no_environment_package():
    code = ("import sys, mpc_hunt; print(sorted(m for m in ('cvxpy', 'osqp', 'clarabel', 'daqp', "
            "'gymnasium', 'pettingzoo') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


class SecondDaqp(DaqpBackend):
    """A new backend written against the contract: one class, one registry line."""

    name = "daqp2"


class MissingSolver(DaqpBackend):
    name = "missing"
    package = "no_such_solver"


@pytest.fixture
def extra_backends(monkeypatch):
    monkeypatch.setitem(registry.BACKENDS, "daqp2", SecondDaqp)
    monkeypatch.setitem(registry.BACKENDS, "missing", MissingSolver)


def test_a_registered_backend_works_with_every_formulation_of_its_kind(extra_backends, scenario):
    assert ("qp", "daqp2") in registry.pairs() and ("sqp", "daqp2") in registry.pairs()
    assert ("nlp", "daqp2") not in registry.pairs() and ("socp", "daqp2") not in registry.pairs()
    problem = problem_at(scenario, 2)
    assert solve(problem, "qp", "daqp2").objective == pytest.approx(solve(problem, "qp", "daqp").objective,
                                                                      rel=1e-12)


def test_a_missing_solver_is_listed_with_its_install_hint(extra_backends):
    assert ("qp", "missing") not in registry.pairs()
    assert ("qp", "missing") in registry.pairs(installed_only=False)
    with pytest.raises(SolverNotFoundError, match="pip install no_such_solver"):
        CaptureSolver("qp", "missing")


def test_the_formulations_folder_documents_every_registered_formulation_and_installs_none():
    table = (ROOT / "formulations" / "README.md").read_text(encoding="utf-8")
    rows = {line.split("|")[1].strip().strip("`") for line in table.splitlines() if line.startswith("| `")}
    assert rows == set(registry.FORMULATIONS)
    assert not list((ROOT / "formulations").glob("*.py"))      # the code is mpc_hunt.formulations


def test_the_package_installs_no_top_level_name_but_its_own():
    import tomllib

    from setuptools import find_packages

    found = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]["packages"]["find"]
    packages = find_packages(str(ROOT), include=found["include"])
    assert "mpc_hunt.formulations" in packages
    assert {p.split(".")[0] for p in packages} == {"mpc_hunt"}

"""The package root is lazy: ``import mpc_hunt`` loads none of its subpackages, each public name is imported from
its subpackage on first use, and a Ctrl-C while the command line is still importing is one line, status 130."""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
from pathlib import Path

import pytest

import mpc_hunt
import mpc_hunt.arguments
import mpc_hunt.cli

ROOT = Path(__file__).resolve().parents[1]
NAMES = [name for name in mpc_hunt.__all__ if name != "__version__"]


def _python(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)


def test_import_mpc_hunt_imports_no_subpackage_and_no_solver():
    """Nor the package metadata (``__version__``'s, which imports email, zipfile, sockets …) until it is read."""
    run = _python("import sys, mpc_hunt\n"
                  "print(sorted(m for m in sys.modules if m.split('.')[0] in ('casadi', 'cvxpy') "
                  "or m.startswith('mpc_hunt.') or m == 'importlib.metadata'))")
    assert run.returncode == 0 and run.stdout.strip() == "[]", run.stdout + run.stderr


def stub_imports() -> dict[str, list[str]]:
    """The stub's imports: each name the root lists, by the subpackage it is imported from."""
    tree = ast.parse((ROOT / "mpc_hunt" / "__init__.pyi").read_text(encoding="utf-8"))
    homes: dict[str, list[str]] = {}
    for node in tree.body:
        if isinstance(node, ast.ImportFrom):
            assert node.level == 1 and all(a.asname == a.name for a in node.names)  # re-exported, relative
            homes.setdefault(f"mpc_hunt.{node.module}", []).extend(a.name for a in node.names)
    return homes


def test_every_public_name_is_its_subpackages_and_listed():
    homes = {name: module for module, names in stub_imports().items() for name in names}
    assert sorted(homes) == sorted(NAMES)
    for name in NAMES:
        assert getattr(mpc_hunt, name) is getattr(importlib.import_module(homes[name]), name), name
    assert set(mpc_hunt.__all__) <= set(dir(mpc_hunt))
    assert isinstance(mpc_hunt.__version__, str) and mpc_hunt.__version__


def test_every_public_name_resolves_in_a_fresh_process():
    """From nothing imported: ``from mpc_hunt import *`` binds every name of ``__all__``, none of them None."""
    run = _python("import mpc_hunt\nnames = {}\nexec('from mpc_hunt import *', names)\n"
                  "print([n for n in mpc_hunt.__all__ if names.get(n) is None])")
    assert run.returncode == 0 and run.stdout.strip() == "[]", run.stdout + run.stderr


def test_each_public_name_is_the_one_its_subpackage_exports():
    """The stub the root's names are read from lists each under the subpackage whose ``__all__`` has it."""
    for module, names in stub_imports().items():
        exported = getattr(importlib.import_module(module), "__all__", None)
        assert exported is None or set(names) <= set(exported), module


def test_a_subpackage_is_an_attribute_and_an_unknown_name_is_not():
    run = _python("import mpc_hunt\nprint(mpc_hunt.sim.simulate is mpc_hunt.simulate)")  # nothing imported it yet
    assert run.returncode == 0 and run.stdout.strip() == "True", run.stdout + run.stderr
    with pytest.raises(AttributeError, match="no attribute 'no_such_name'"):
        mpc_hunt.no_such_name  # noqa: B018
    assert not hasattr(mpc_hunt, "_private")


CUT = """
import sys

class Cut:
    def find_spec(self, name, path=None, target=None):
        if name == {module!r}:
            raise KeyboardInterrupt   # Ctrl-C while the command line imports it
        return None

sys.meta_path.insert(0, Cut())
sys.argv = ["mpc-hunt", "backends"]
{start}
"""
STARTS = {
    "mpc-hunt": "from mpc_hunt.cli import main\nsys.exit(main())",  # what the console script runs
    "python -m mpc_hunt.cli": "import runpy\nrunpy.run_module('mpc_hunt.cli', run_name='__main__')",
}


@pytest.mark.parametrize("module", ["mpc_hunt.cli.commands", "mpc_hunt.solving"])
@pytest.mark.parametrize("start", sorted(STARTS))
def test_ctrl_c_while_the_command_line_imports_is_one_line_and_status_130(start, module):
    run = _python(CUT.format(module=module, start=STARTS[start]))
    assert (run.returncode, run.stdout, run.stderr) == (130, "", "mpc-hunt: interrupted\n"), run.stderr
    assert mpc_hunt.cli.EXIT_INTERRUPTED == mpc_hunt.arguments.EXIT_INTERRUPTED

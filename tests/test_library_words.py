"""The library raises in its own words: no error outside ``mpc_hunt/cli/`` names a command-line flag; it names the
function's argument (``mpc_hunt.errors.field_name``, ``SettingError``) and the command line names the flag."""

from __future__ import annotations

import ast
import pickle
import re
from pathlib import Path

from mpc_hunt.cli.common import flag
from mpc_hunt.errors import BenchmarkError, SettingError, field_name

ROOT = Path(__file__).resolve().parents[1]
FLAG = re.compile(r"--[a-z]")
EXCLUDED = ("mpc_hunt/cli/",)     # the command line: the one place that knows flags
FUNCTION = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)


def _flags_raised(source: str, path: str) -> list[str]:
    """``path:line: text`` of each string a ``raise`` in ``source`` builds its error from that names a flag: in its
    own expression, in what the names it uses were assigned (in its function, its outer ones, the module), and in
    what the module's functions it calls return."""
    tree = ast.parse(source)
    outer: dict[ast.AST, ast.AST | None] = {tree: None}     # each function's enclosing one (the module's: None)
    scope: dict[ast.AST, ast.AST] = {}                         # each node's innermost function, or the module
    _scopes(tree, tree, outer, scope)
    functions: dict[str, list[ast.AST]] = {}
    for node in outer:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            functions.setdefault(node.name, []).append(node)
    hits, seen = set(), set()
    work = [(n.exc, scope[n]) for n in ast.walk(tree) if isinstance(n, ast.Raise) and n.exc is not None]
    while work:
        expression, where = work.pop()
        for node in ast.walk(expression):
            if node in seen:
                continue
            seen.add(node)
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and FLAG.search(node.value):
                hits.add(f"{path}:{node.lineno}: {node.value}")
            elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load):
                chain = where
                while chain is not None:
                    work += [(value, chain) for value in _assigned(chain, node.id, scope)]
                    chain = outer[chain]
            elif isinstance(node, ast.Call):
                name = node.func.id if isinstance(node.func, ast.Name) else getattr(node.func, "attr", None)
                work += [(r.value, function) for function in functions.get(name, []) for r in ast.walk(function)
                         if isinstance(r, ast.Return) and r.value is not None and scope[r] is function]
    return sorted(hits)


def _scopes(node: ast.AST, here: ast.AST, outer: dict, scope: dict) -> None:
    """Fill ``scope`` (each node below ``node``: its innermost function, ``here`` at first) and ``outer``."""
    for child in ast.iter_child_nodes(node):
        scope[child] = here
        if isinstance(child, FUNCTION):
            outer[child] = here
            _scopes(child, child, outer, scope)
        else:
            _scopes(child, here, outer, scope)


def _assigned(where: ast.AST, name: str, scope: dict) -> list[ast.AST]:
    """The values assigned to ``name`` in the function (or module) ``where`` itself."""
    values = []
    for node in ast.walk(where):
        if scope.get(node) is not where:
            continue
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == name for t in node.targets):
            values.append(node.value)
        elif isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr)) and \
                isinstance(node.target, ast.Name) and node.target.id == name and node.value is not None:
            values.append(node.value)
    return values


def _library() -> list[Path]:
    return [f for f in sorted((ROOT / "mpc_hunt").rglob("*.py"))
            if not any(f.relative_to(ROOT).as_posix().startswith(e) for e in EXCLUDED)]


def test_no_library_error_names_a_flag():
    assert [hit for f in _library() for hit in _flags_raised(f.read_text(encoding="utf-8"),
                                                             f.relative_to(ROOT).as_posix())] == []


def test_the_check_follows_a_message_to_where_it_is_built():
    source = """
def hint():
    return "or give --output"

def refuse(resume):
    why = f"exists ({hint()})"
    why += "; use --resume"
    raise ValueError(f"results file: {why}")

def fine():
    raise ValueError("resume: its file exists")

def nested():
    option = "--verbose"
    def inner():
        raise ValueError(f"{option}: {HELP}")
    return inner

HELP = "see --help"
NOT_RAISED = "--quiet"
"""
    assert _flags_raised(source, "x.py") == ["x.py:14: --verbose", "x.py:19: see --help",
                                          "x.py:3: or give --output", "x.py:7: ; use --resume"]


def test_an_error_shows_its_fields_as_the_library_names_them_or_as_the_command_line_does():
    refused = SettingError("path", f"s.db exists (use {field_name('resume')} to continue it)")
    assert str(refused) == "path: s.db exists (use resume to continue it)"
    assert refused.reason == "s.db exists (use resume to continue it)" and refused.fields == ("path",)
    assert refused.named(flag) == "--output: s.db exists (use --resume to continue it)"
    assert pickle.loads(pickle.dumps(refused)).named(flag) == refused.named(flag)    # as a worker hands it back
    other = BenchmarkError(f"{field_name('time_limit')}: leave it out of the {field_name('pairs')}")
    assert (str(other), other.named(flag)) == ("time_limit: leave it out of the pairs",
                                               "--time-limit: leave it out of the --pair")

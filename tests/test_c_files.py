"""C and Makefiles are files: none held in a Python string of the package, every template shipped and filled in."""

from __future__ import annotations

import ast
import re
import tomllib
from pathlib import Path

import pytest

from mpc_hunt.solving.c_template import PLACEHOLDER, TEMPLATES, render

ROOT = Path(__file__).resolve().parents[1]

# A line of C, a linker script or a Makefile: the preprocessor, a program's main, a C function's definition, a
# linker script's blocks, make's variables.
C_LINE = re.compile(r"^\s*#\s*(include|define|ifn?def|endif|pragma)\b"
                    r"|\bint\s+main\s*\("
                    r"|^\s*(static\s+)?(int|void|double|char|unsigned)\b[\w\s*]*\([^;]*\)\s*\{"
                    r"|^\s*(MEMORY|SECTIONS)\s*\{"
                    r"|\$\([A-Z_]+\)")


def c_text(source: str) -> list[str]:
    """The first C or Makefile line of each string literal of ``source`` that holds such a line among others: a C
    file's, a header's or a Makefile's text. A single line is not (one line of CasADi's generated code, quoted to
    find a place in it: :mod:`mpc_hunt.solving.backends.hpipm_codegen`)."""
    hits = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            lines = node.value.strip("\n").splitlines()
            found = [line for line in lines if C_LINE.search(line)]
            if len(lines) > 1 and found:
                hits.append(f"line {node.lineno}: {found[0].strip()}")
    return hits


def test_no_python_module_of_the_package_holds_c_or_a_makefile():
    """They are templates (mpc_hunt/solving/c_templates/, rendered by mpc_hunt/solving/c_template.py)."""
    hits = {path.relative_to(ROOT).as_posix(): c_text(path.read_text(encoding="utf-8"))
            for path in sorted((ROOT / "mpc_hunt").rglob("*.py"))}
    assert {path: found for path, found in hits.items() if found} == {}


@pytest.mark.parametrize("text", [
    '#ifndef MPC_HUNT_STEP_H\n#define MPC_HUNT_STEP_H\nint mpc_hunt_step(void);\n#endif\n',
    '#include <stdio.h>\nint main(int argc, char **argv) {\n  return 0;\n}\n',
    'static int status = -1;\nint mpc_hunt_hpipm_status(void) { return status; }\n',
    'CC ?= gcc\ncapture_step: main.o\n\t$(CC) $(CFLAGS) -o $@ $^\n',
    'MEMORY {\n  FLASH (rx) : ORIGIN = 0x00000000, LENGTH = 4M\n}\n'])
def test_the_check_finds_c_a_header_a_linker_script_and_a_makefile_in_a_string(text):
    assert len(c_text(f"TEMPLATE = {text!r}\n")) == 1


def test_the_check_finds_c_in_an_f_string_and_lets_a_docstring_and_a_quoted_line_be():
    assert len(c_text('MAKEFILE = f"CC = {cc}\\ncapture_step: main.o\\n\\t$(CC) -o $@ $^\\n"\n')) == 1
    assert c_text('"""The C export: ``main.c`` and a Makefile (``make CC=gcc``).\n\nNo C here."""\n'
                  'ANCHOR = "#include <hpipm_d_ocp_qp_utils.h>\\n"\n') == []


def _shipped(package: str) -> set[Path]:
    """The files pyproject.toml's package data ships with ``package``."""
    patterns = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"][
        "package-data"][package]
    folder = ROOT.joinpath(*package.split("."))
    return {path for pattern in patterns for path in folder.glob(pattern) if path.is_file()}


def test_every_template_and_daqps_version_are_package_data():
    """A non-editable install (``pip install .``) has them."""
    shipped = _shipped("mpc_hunt.solving")
    templates = {path for path in TEMPLATES.rglob("*") if path.is_file()}
    assert templates and templates <= shipped
    assert TEMPLATES.parent / "vendor" / "daqp" / "VERSION" in shipped


def test_a_template_is_filled_in_whole_or_refused():
    text = render("hpipm/Makefile", structure="S", deps="/deps")
    assert "structure S." in text and "DEPS ?= /deps\n" in text and "$(CC)" in text and not PLACEHOLDER.search(text)
    with pytest.raises(TypeError, match="placeholders"):
        render("hpipm/Makefile", structure="S")
    with pytest.raises(TypeError, match="placeholders"):
        render("main.c", structure="S")

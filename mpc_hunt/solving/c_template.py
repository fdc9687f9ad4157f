"""The C sources, headers and Makefiles the toolkit writes, as template files filled in.

The templates are package data in ``c_templates/``: ``main.c`` (the host program of both
exports), ``hpipm/`` (the export of the ``hpipm`` step, and the status accessors
``hpipm-codegen`` adds to CasADi's generated code), ``condensed/`` (the ``daqp-condensed``
step: the C its library is built from, ``condensed_step.c``, and its export) and
``cortex-m7/`` (the bare-metal board's program). A template is the file as written, with
``@name@`` where a value goes (the placeholders of autoconf's and CMake's ``configure_file``:
no clash with C's braces nor make's ``$``); :func:`render` fills in every one.
"""

from __future__ import annotations

import re
from pathlib import Path

TEMPLATES = Path(__file__).resolve().parent / "c_templates"
PLACEHOLDER = re.compile(r"@([a-z_][a-z0-9_]*)@")


def render(template: str, **values: object) -> str:
    """The template at ``template`` (a path in :data:`TEMPLATES`) with each ``@name@`` replaced by ``values[name]``
    (as ``str`` gives it); a template whose placeholders are not the values' names is refused, not half filled."""
    text = (TEMPLATES / template).read_text(encoding="utf-8")
    named = set(PLACEHOLDER.findall(text))
    if named != set(values):
        raise TypeError(f"template {template}: placeholders {sorted(named)}, values given for {sorted(values)}")
    return PLACEHOLDER.sub(lambda match: str(values[match.group(1)]), text)

"""Registries by name: a line names a class as ``"module:Class"``, imported when the name is first used; and
inputs given by a shipped name or a file."""

from __future__ import annotations

import importlib
from pathlib import Path

from mpc_hunt.errors import UnknownNameError


def load_class(table: dict[str, str], what: str, name: str) -> type:
    """The class a table line names as ``"module:Class"``, imported now; an unknown name lists the table's."""
    if name not in table:
        raise UnknownNameError(f"unknown {what} {name!r} (available: {', '.join(table)})")
    module, cls = table[name].split(":")
    return getattr(importlib.import_module(module), cls)


def shipped_name(name_or_file, shipped: list[str], what: str, suffix: str, listed: str = "shipped") -> str | None:
    """The shipped name ``name_or_file`` gives, or None when it is a file (a path ending in ``suffix`` or an
    existing one); anything else is an unknown name, and the error lists the ``shipped`` ones."""
    text = str(name_or_file)
    if text in shipped:
        return text
    if text.endswith(suffix) or Path(text).exists():
        return None
    raise UnknownNameError(f"unknown {what} {text!r}: neither {listed} ({', '.join(shipped)}) "
                           f"nor an existing {suffix} file")

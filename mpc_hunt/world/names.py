"""Registries by name: a table maps each name to its class; and inputs given by a shipped name or a file."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TypeVar

from mpc_hunt.errors import UnknownNameError

_Entry = TypeVar("_Entry")


def registered(table: Mapping[str, _Entry], what: str, name: str) -> _Entry:
    """The class ``table`` registers as ``name``; an unknown name lists the table's."""
    if not isinstance(name, str) or name not in table:
        raise UnknownNameError(f"unknown {what} {name!r} (available: {', '.join(table)})")
    return table[name]


def shipped_name(name_or_file, shipped: list[str], what: str, suffix: str, listed: str = "shipped") -> str | None:
    """The shipped name ``name_or_file`` gives, or None when it is a file (a path ending in ``suffix`` or an
    existing one); anything else is an unknown name, and the error lists the ``shipped`` ones."""
    text = str(name_or_file)
    if text in shipped:
        return text
    if text.endswith(suffix) or Path(text).exists():
        return None
    raise UnknownNameError(
        f"unknown {what} {text!r}: neither {listed} ({', '.join(shipped)}) nor an existing {suffix} file"
    )

"""Registries by name: a line names a class as ``"module:Class"``, imported when the name is first used."""

from __future__ import annotations

import importlib

from mpc_hunt.errors import UnknownNameError


def load_class(table: dict[str, str], what: str, name: str) -> type:
    """The class a table line names as ``"module:Class"``, imported now; an unknown name lists the table's."""
    if name not in table:
        raise UnknownNameError(f"unknown {what} {name!r} (available: {', '.join(table)})")
    module, cls = table[name].split(":")
    return getattr(importlib.import_module(module), cls)

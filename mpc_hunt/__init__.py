"""mpc-hunt: multi-robot cooperative hunting as optimisation and model-predictive control.

The package root imports nothing of its own: each public name is imported from its subpackage on first use
(``lazy_loader``, from the imports listed once in ``__init__.pyi``, which type checkers read as the package's
interface), and ``__version__`` read from the installed metadata on first use, so ``import mpc_hunt`` (and the
command line's start) loads no solver and is over at once; ``from mpc_hunt import simulate`` and
``mpc_hunt.simulate`` work as they always did, and ``mpc_hunt.sim`` imports the subpackage.
"""

from __future__ import annotations

import importlib
from typing import Any

import lazy_loader

_public, _, _names = lazy_loader.attach_stub(__name__, __file__)
__all__ = [*_names, "__version__"]


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version  # (it imports email, zipfile, …: not at start)

    try:
        return version("mpc-hunt")
    except PackageNotFoundError:  # running from a source tree that was never installed
        return "0+unknown"


def __getattr__(name: str) -> Any:
    """A public name, imported from its subpackage on first use and kept; else a subpackage, imported."""
    if name == "__version__":
        globals()[name] = value = _version()
        return value
    if name in _names:
        return _public(name)
    if name.isidentifier() and not name.startswith("_"):  # a subpackage, as the eager root used to import them
        try:
            return importlib.import_module(f"{__name__}.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":  # the subpackage is there; something it imports is not
                raise
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))

"""mpc-hunt: multi-robot cooperative hunting as optimisation and model-predictive control.

The package root imports nothing of its own: each public name is imported from its subpackage on first use (PEP
562), and ``__version__`` read from the installed metadata on first use, so ``import mpc_hunt`` (and the command
line's start) loads no solver and is over at once; ``from mpc_hunt import simulate`` and ``mpc_hunt.simulate``
work as they always did, and ``mpc_hunt.sim`` imports the subpackage.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # the names as the type checker and editors see them; at run time, ``__getattr__`` below
    __version__: str
    from mpc_hunt.capture import (
        CaptureProblem,
        CaptureWeights,
        Certificate,
        Evaluation,
        Solution,
        Status,
        Structure,
        WarmStart,
        evaluate,
        shift_plan,
    )
    from mpc_hunt.control import (
        Command,
        Controller,
        ControllerSpec,
        EncirclingController,
        Enclosure,
        HuntingStrategy,
        Observation,
        make_controller,
    )
    from mpc_hunt.errors import MpcHuntError, ScenarioError, SolverError, SolverNotFoundError, UnknownNameError
    from mpc_hunt.sim import HuntResult, simulate
    from mpc_hunt.solving import CaptureMPC, CaptureSolver, MPCStep, pairs, solve
    from mpc_hunt.world import (
        Attacker,
        Belief,
        CircleStatus,
        Defender,
        HuntParameters,
        Obstacle,
        Scenario,
        builtin_names,
        builtin_scenario,
        load_scenario,
        resolve_scenario,
        save_scenario,
        success_test,
    )

__all__ = [
    "Attacker",
    "Belief",
    "CaptureMPC",
    "CaptureProblem",
    "CaptureSolver",
    "CaptureWeights",
    "Certificate",
    "CircleStatus",
    "Command",
    "Controller",
    "ControllerSpec",
    "Defender",
    "EncirclingController",
    "Enclosure",
    "Evaluation",
    "HuntParameters",
    "HuntResult",
    "HuntingStrategy",
    "MPCStep",
    "MpcHuntError",
    "Observation",
    "Obstacle",
    "Scenario",
    "ScenarioError",
    "Solution",
    "SolverError",
    "SolverNotFoundError",
    "Status",
    "Structure",
    "UnknownNameError",
    "WarmStart",
    "builtin_names",
    "builtin_scenario",
    "evaluate",
    "load_scenario",
    "make_controller",
    "pairs",
    "resolve_scenario",
    "save_scenario",
    "shift_plan",
    "simulate",
    "solve",
    "success_test",
    "__version__",
]

_HOMES = {  # the subpackage each public name is imported from (the same as the imports above)
    "mpc_hunt.capture": (
        "CaptureProblem",
        "CaptureWeights",
        "Certificate",
        "Evaluation",
        "Solution",
        "Status",
        "Structure",
        "WarmStart",
        "evaluate",
        "shift_plan",
    ),
    "mpc_hunt.control": (
        "Command",
        "Controller",
        "ControllerSpec",
        "EncirclingController",
        "Enclosure",
        "HuntingStrategy",
        "Observation",
        "make_controller",
    ),
    "mpc_hunt.errors": ("MpcHuntError", "ScenarioError", "SolverError", "SolverNotFoundError", "UnknownNameError"),
    "mpc_hunt.sim": ("HuntResult", "simulate"),
    "mpc_hunt.solving": ("CaptureMPC", "CaptureSolver", "MPCStep", "pairs", "solve"),
    "mpc_hunt.world": (
        "Attacker",
        "Belief",
        "CircleStatus",
        "Defender",
        "HuntParameters",
        "Obstacle",
        "Scenario",
        "builtin_names",
        "builtin_scenario",
        "load_scenario",
        "resolve_scenario",
        "save_scenario",
        "success_test",
    ),
}
_HOME = {name: module for module, names in _HOMES.items() for name in names}


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
    home = _HOME.get(name)
    if home is not None:
        value = getattr(importlib.import_module(home), name)
        globals()[name] = value  # the next use is a plain attribute
        return value
    if name.isidentifier() and not name.startswith("_"):  # a subpackage, as the eager root used to import them
        try:
            return importlib.import_module(f"{__name__}.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":  # the subpackage is there; something it imports is not
                raise
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))

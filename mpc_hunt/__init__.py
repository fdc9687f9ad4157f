"""mpc-hunt: multi-robot cooperative hunting as optimisation and model-predictive control."""

from importlib.metadata import PackageNotFoundError, version

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

try:
    __version__ = version("mpc-hunt")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"

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

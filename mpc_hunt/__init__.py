"""mpc-hunt: multi-robot cooperative hunting as optimisation and model-predictive control."""

from importlib.metadata import PackageNotFoundError, version

from mpc_hunt.capture_problem import CaptureProblem, CaptureWeights
from mpc_hunt.controller import Command, Controller, Observation
from mpc_hunt.encircling import EncirclingController
from mpc_hunt.errors import MpcHuntError, ScenarioError, SolverError, SolverNotFoundError, UnknownNameError
from mpc_hunt.evaluator import Evaluation, evaluate
from mpc_hunt.hunt_result import HuntResult
from mpc_hunt.registry import make_controller, pairs
from mpc_hunt.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario
from mpc_hunt.scenario_io import (builtin_names, builtin_scenario, load_scenario, resolve_scenario,
                                  save_scenario)
from mpc_hunt.simulator import simulate
from mpc_hunt.solution import Solution, Status, WarmStart
from mpc_hunt.solver import CaptureSolver, solve
from mpc_hunt.strategy import HuntingStrategy

try:
    __version__ = version("mpc-hunt")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"

__all__ = [
    "Attacker", "CaptureProblem", "CaptureSolver", "CaptureWeights", "Command", "Controller", "Defender",
    "EncirclingController", "Evaluation", "HuntParameters", "HuntResult", "HuntingStrategy", "MpcHuntError",
    "Observation", "Obstacle", "Scenario", "ScenarioError", "Solution", "SolverError", "SolverNotFoundError",
    "Status", "UnknownNameError", "WarmStart", "builtin_names", "builtin_scenario", "evaluate", "load_scenario",
    "make_controller", "pairs", "resolve_scenario", "save_scenario", "simulate", "solve", "__version__",
]

"""mpc-hunt: multi-robot cooperative hunting as optimisation and model-predictive control."""

from mpc_hunt.capture_problem import CaptureProblem, CaptureWeights
from mpc_hunt.errors import MpcHuntError, ScenarioError, SolverError, UnknownNameError
from mpc_hunt.evaluator import Evaluation, evaluate
from mpc_hunt.hunt_result import HuntResult
from mpc_hunt.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario
from mpc_hunt.scenario_io import (builtin_names, builtin_scenario, load_scenario, resolve_scenario,
                                  save_scenario)
from mpc_hunt.simulator import simulate
from mpc_hunt.solution import Solution, Status
from mpc_hunt.solver import CaptureSolver, solve
from mpc_hunt.strategy import HuntingStrategy

__all__ = [
    "Attacker", "CaptureProblem", "CaptureSolver", "CaptureWeights", "Defender", "Evaluation",
    "HuntParameters", "HuntResult", "HuntingStrategy", "MpcHuntError", "Obstacle", "Scenario",
    "ScenarioError", "Solution", "SolverError", "Status", "UnknownNameError", "builtin_names",
    "builtin_scenario", "evaluate", "load_scenario", "resolve_scenario", "save_scenario", "simulate",
    "solve",
]

"""The capture stage (Eqs. 12–15): the problem at one state, the one solver interface over every formulation and
backend (the registry), the solution, and the evaluator that scores every plan on the true problem."""

from mpc_hunt.capture.evaluator import Evaluation, evaluate
from mpc_hunt.capture.loop import CaptureLoop
from mpc_hunt.capture.plan import shift_plan
from mpc_hunt.capture.problem import CaptureProblem, CaptureWeights
from mpc_hunt.capture.registry import pairs
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.capture.solver import CaptureSolver, solve

__all__ = ["CaptureLoop", "CaptureProblem", "CaptureSolver", "CaptureWeights", "Evaluation", "Solution", "Status", "WarmStart",
           "evaluate", "pairs", "shift_plan", "solve"]

"""The capture stage's contract (Eqs. 12–15): the problem at one state and its structure, the data a formulation
hands a backend, the solution, and the evaluator that scores every plan on the true problem.

The formulations (:mod:`mpc_hunt.formulations`) build on it; the solving machinery
(:mod:`mpc_hunt.solving`: registry, backends, solver, export) on both.
"""

from mpc_hunt.capture.certificate import Certificate
from mpc_hunt.capture.evaluator import Evaluation, evaluate
from mpc_hunt.capture.plan import shift_plan
from mpc_hunt.capture.problem import CaptureProblem, CaptureWeights, EncloseWeights, Reference
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.capture.structure import Structure

__all__ = [
    "CaptureProblem",
    "CaptureWeights",
    "Certificate",
    "EncloseWeights",
    "Evaluation",
    "Reference",
    "Solution",
    "Status",
    "Structure",
    "WarmStart",
    "evaluate",
    "shift_plan",
]

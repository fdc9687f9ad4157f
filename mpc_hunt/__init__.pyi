"""The package root's public names, each imported from its subpackage on first use (``__init__.py``).

The one list of them: ``lazy_loader`` reads these imports when the package is imported and makes ``__all__``
and the lazy ``__getattr__`` of them; type checkers and editors read them as the package's interface.
"""

__version__: str

from .capture import CaptureProblem as CaptureProblem
from .capture import CaptureWeights as CaptureWeights
from .capture import Certificate as Certificate
from .capture import Evaluation as Evaluation
from .capture import Solution as Solution
from .capture import Status as Status
from .capture import Structure as Structure
from .capture import WarmStart as WarmStart
from .capture import evaluate as evaluate
from .capture import shift_plan as shift_plan
from .control import Command as Command
from .control import Controller as Controller
from .control import ControllerSpec as ControllerSpec
from .control import EncirclingController as EncirclingController
from .control import Enclosure as Enclosure
from .control import HuntingStrategy as HuntingStrategy
from .control import Observation as Observation
from .control import make_controller as make_controller
from .errors import MpcHuntError as MpcHuntError
from .errors import ScenarioError as ScenarioError
from .errors import SolverError as SolverError
from .errors import SolverNotFoundError as SolverNotFoundError
from .errors import UnknownNameError as UnknownNameError
from .sim import HuntResult as HuntResult
from .sim import simulate as simulate
from .solving import CaptureMPC as CaptureMPC
from .solving import CaptureSolver as CaptureSolver
from .solving import MPCStep as MPCStep
from .solving import pairs as pairs
from .solving import solve as solve
from .world import Attacker as Attacker
from .world import Belief as Belief
from .world import CircleStatus as CircleStatus
from .world import Defender as Defender
from .world import HuntParameters as HuntParameters
from .world import Obstacle as Obstacle
from .world import Scenario as Scenario
from .world import builtin_names as builtin_names
from .world import builtin_scenario as builtin_scenario
from .world import load_scenario as load_scenario
from .world import resolve_scenario as resolve_scenario
from .world import save_scenario as save_scenario
from .world import success_test as success_test

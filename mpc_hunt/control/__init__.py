"""Controllers: the protocol (observation in, command out; a controller never sees the world), the paper's
hunting strategy with its capture stage (either objective), the two baselines, and the recommended one."""

from mpc_hunt.control.controller import Command, Controller, Observation
from mpc_hunt.control.encircling import EncirclingController
from mpc_hunt.control.enclosure import Enclosure
from mpc_hunt.control.recommended import PAPER, RECOMMENDED, RECOMMENDED_CONTROLLER
from mpc_hunt.control.spec import ControllerSpec, make_controller
from mpc_hunt.control.strategy import HuntingStrategy

__all__ = [
    "Command",
    "Controller",
    "ControllerSpec",
    "EncirclingController",
    "Enclosure",
    "HuntingStrategy",
    "Observation",
    "PAPER",
    "RECOMMENDED",
    "RECOMMENDED_CONTROLLER",
    "make_controller",
]

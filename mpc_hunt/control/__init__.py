"""Controllers: the protocol (observation in, command out; a controller never sees the world), the paper's
hunting strategy with its capture stage, the potential-field baseline, and the recommended settings."""

from mpc_hunt.control.controller import Command, Controller, Observation
from mpc_hunt.control.controllers import make_controller
from mpc_hunt.control.encircling import EncirclingController
from mpc_hunt.control.recommended import PAPER, RECOMMENDED
from mpc_hunt.control.strategy import HuntingStrategy

__all__ = ["Command", "Controller", "EncirclingController", "HuntingStrategy", "Observation", "PAPER",
           "RECOMMENDED", "make_controller"]

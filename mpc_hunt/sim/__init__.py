"""The closed loop: the simulator integrates the world (Eqs. 1–2) under a controller's commands and reports one
hunt's result."""

from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.sim.simulator import simulate

__all__ = ["HuntResult", "simulate"]

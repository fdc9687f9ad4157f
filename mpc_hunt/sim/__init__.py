"""The closed loop: the simulator integrates the world (Eqs. 1–2) under a controller's commands and reports a
hunt's result; a batch of hunts at once (docs/engine.md)."""

from mpc_hunt.sim.batch import simulate_batch
from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.sim.simulator import simulate

__all__ = ["HuntResult", "simulate", "simulate_batch"]

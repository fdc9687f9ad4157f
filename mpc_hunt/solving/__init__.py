"""Solving the capture stage: formulations and backends by name (the registry), the backends, the one solver
object over every pair, the receding horizon over it, the control loop's step and its C export."""

from mpc_hunt.solving.mpc import CaptureMPC, MPCStep
from mpc_hunt.solving.registry import pairs
from mpc_hunt.solving.solver import CaptureSolver, solve

__all__ = ["CaptureMPC", "CaptureSolver", "MPCStep", "pairs", "solve"]

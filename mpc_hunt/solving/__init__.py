"""Solving the capture stage: formulations and backends by name (the registry), the backends, the one solver
object over every pair, the control loop's step and its C export."""

from mpc_hunt.solving.registry import pairs
from mpc_hunt.solving.solver import CaptureSolver, solve

__all__ = ["CaptureSolver", "pairs", "solve"]

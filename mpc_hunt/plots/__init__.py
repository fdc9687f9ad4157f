"""Figures of one hunt: its trajectories (`plot_hunt`) and an animation (`animate_hunt`)."""

from mpc_hunt.plots.animation import animate_hunt
from mpc_hunt.plots.hunt import plot_hunt

__all__ = ["animate_hunt", "plot_hunt"]

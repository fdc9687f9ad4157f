"""Every figure: one hunt's trajectories (`plot_hunt`) and animation (`animate_hunt`); hunts zoomed on their capture
region (capture_region.py), a sweep's typical hunts among them (typical_hunts.py); a sweep's figures (sweep.py) and
a compare run's (compare.py)."""

from mpc_hunt.plots.animation import animate_hunt
from mpc_hunt.plots.hunt import plot_hunt

__all__ = ["animate_hunt", "plot_hunt"]

"""An animated GIF of a hunt: trails so far, current positions and the attacker's perception circle."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.animation import PillowWriter

from mpc_hunt.plots.hunt import (
    END_MARKER,
    START_MARKER,
    draw_markers,
    draw_obstacles,
    draw_paths,
    draw_perception,
    frame_axes,
    hunt_title,
    last_finite_step,
    marker_legend,
    new_figure,
    paths,
    settle_layout,
)
from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.world.scenario import Scenario

ANIMATION_SIZE = (6.4, 4.8)
ANIMATION_DPI = 80


def frame_steps(last: int, frames: int) -> np.ndarray:
    """At most ``frames`` steps spread evenly over 0..last, both ends included."""
    return np.unique(np.linspace(0, last, min(frames, last + 1)).round().astype(int))


def animate_hunt(result: HuntResult, scenario: Scenario, path: str | Path, frames: int = 120, fps: int = 15) -> None:
    """Write the hunt as an animated GIF of at most ``frames`` frames shown at ``fps``."""
    if frames < 1:
        raise ValueError(f"frames: must be at least 1, got {frames}")
    if fps < 1:
        raise ValueError(f"fps: must be at least 1, got {fps}")
    fig, ax = new_figure(ANIMATION_SIZE, ANIMATION_DPI)
    draw_obstacles(ax, scenario)
    trails = draw_paths(ax, result)
    draw_markers(ax, result, 0, START_MARKER, size=5.0)
    current = draw_markers(ax, result, 0, END_MARKER)
    perception = draw_perception(ax, scenario, result.attacker[0], "perception radius", linestyle="--", linewidth=0.8)
    clock = ax.text(0.02, 0.98, "", transform=ax.transAxes, va="top", fontsize="small")
    marker_legend(ax, {START_MARKER: "start", END_MARKER: "now"})
    frame_axes(ax, result, scenario, hunt_title(result, scenario))
    settle_layout(fig)
    last = last_finite_step(result)
    tracks = paths(result)

    def show(step: int) -> None:
        for trail, marker, p in zip(trails, current, tracks):
            trail.set_data(p[: step + 1, 0], p[: step + 1, 1])
            marker.set_data(p[step : step + 1, 0], p[step : step + 1, 1])
        perception.center = tuple(result.attacker[step])
        done = step == last and result.captured
        clock.set_text(f"t = {result.times[step]:.1f} s" + (" (captured)" if done else ""))

    writer = PillowWriter(fps=fps)
    with writer.saving(fig, path, ANIMATION_DPI):
        for step in frame_steps(last, frames):
            show(step)
            writer.grab_frame()

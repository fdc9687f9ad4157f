"""Hunts side by side, each zoomed on where it was decided: the last ``TAIL_S`` seconds of every robot's path,
drawn bold over the faint whole path, with the attacker's perception radius R_agg and the hunting circle R_hunt
round its last position, the obstacles and the arena's edge."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Rectangle

from mpc_hunt.plots.hunt import (
    END_MARKER,
    colours,
    draw_markers,
    draw_obstacles,
    draw_perception,
    last_finite_step,
    paths,
    set_window,
    settle_layout,
)
from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.world.scenario import Scenario

TAIL_S = 60.0  # s of each path drawn bold, up to the hunt's end
ZOOM_MARGIN = 1.5  # m round the robots' tails
PANEL = (5.0, 5.0)  # inches per hunt
DPI = 110


def _window(result: HuntResult, scenario: Scenario, tail: int, end: int) -> tuple[np.ndarray, np.ndarray]:
    points = np.concatenate([p[tail : end + 1] for p in paths(result)])
    points = points[np.isfinite(points).all(axis=1)]
    reach = max(scenario.attacker.perception_radius, ZOOM_MARGIN)
    low, high = points.min(axis=0) - reach, points.max(axis=0) + reach
    half = (high - low).max() / 2  # square, so both panels read at one scale per panel
    centre = (low + high) / 2
    return centre - half, centre + half


def plot_capture_regions(cases: list[tuple[HuntResult, Scenario, str]], path: str | Path) -> None:
    """Write one panel per (result, scenario, title) to ``path``, zoomed on the hunt's last ``TAIL_S`` s."""
    fig = Figure(figsize=(PANEL[0] * len(cases), PANEL[1]), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, len(cases), squeeze=False)[0]
    for ax, (result, scenario, title) in zip(axes, cases):
        end = last_finite_step(result)
        tail = max(0, end - int(round(TAIL_S / scenario.hunt.time_step)))
        draw_obstacles(ax, scenario)
        if scenario.arena is not None:
            x0, y0, x1, y1 = scenario.arena
            ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, edgecolor="black", linewidth=1.5, zorder=2))
        names = ["attacker"] + [f"defender {i + 1}" for i in range(result.defenders.shape[1])]
        for p, c, name in zip(paths(result), colours(result), names):
            ax.plot(p[: end + 1, 0], p[: end + 1, 1], color=c, linewidth=0.6, alpha=0.3, zorder=3)
            ax.plot(p[tail : end + 1, 0], p[tail : end + 1, 1], color=c, linewidth=1.6, zorder=3, label=name)
        draw_markers(ax, result, end, END_MARKER)
        a = result.attacker[end]
        draw_perception(ax, scenario, a, "perception radius R_agg", linestyle=":", zorder=5)
        ax.add_patch(
            Circle(
                a,
                scenario.hunt.hunt_radius,
                fill=False,
                edgecolor="black",
                linestyle="--",
                zorder=5,
                label="hunting circle R_hunt",
            )
        )
        set_window(ax, *_window(result, scenario, tail, end), title, fontsize=9)
        ax.legend(fontsize=7, loc="best")
    settle_layout(fig)
    fig.savefig(path)

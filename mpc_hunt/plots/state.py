"""One moment of a hunt as an RGB image: what the environments' ``render()`` returns (``render_mode="rgb_array"``)."""

from __future__ import annotations

from typing import cast

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.patches import Circle, Rectangle

from mpc_hunt.plots.hunt import ATTACKER_COLOUR, MARGIN, defender_colour, draw_obstacles, new_figure
from mpc_hunt.world.scenario import Scenario

IMAGE_SIZE = (4.0, 4.0)  # inches
IMAGE_DPI = 80


def state_image(
    scenario: Scenario, time: float, attacker: np.ndarray, defenders: np.ndarray, trail: list[np.ndarray] | None = None
) -> np.ndarray:
    """The arena, the obstacles, the hunting radius round the attacker and everybody's position (the attacker's
    ``trail`` of past positions, if given) at ``time``: an (H, W, 3) uint8 array."""
    fig, ax = new_figure(IMAGE_SIZE, IMAGE_DPI)
    draw_obstacles(ax, scenario)
    points = [np.asarray(attacker).reshape(1, 2), np.asarray(defenders).reshape(-1, 2)]
    if scenario.arena is not None:
        x_min, y_min, x_max, y_max = scenario.arena
        ax.add_patch(Rectangle((x_min, y_min), x_max - x_min, y_max - y_min, fill=False, edgecolor="0.2"))
        points.append(np.array([[x_min, y_min], [x_max, y_max]]))
    if trail:
        path = np.array(trail)
        ax.plot(path[:, 0], path[:, 1], color=ATTACKER_COLOUR, linewidth=0.8, alpha=0.6)
    ax.add_patch(
        Circle(
            (float(attacker[0]), float(attacker[1])),
            scenario.hunt.hunt_radius,
            fill=False,
            edgecolor=ATTACKER_COLOUR,
            linestyle="--",
        )
    )
    ax.plot(*attacker, "o", color=ATTACKER_COLOUR)
    for i, d in enumerate(np.asarray(defenders).reshape(-1, 2)):
        ax.plot(*d, "o", color=defender_colour(i))
    every = np.concatenate(points)
    finite = every[np.all(np.isfinite(every), axis=1)]
    low, high = finite.min(axis=0) - MARGIN, finite.max(axis=0) + MARGIN
    ax.set_xlim(low[0], high[0])
    ax.set_ylim(low[1], high[1])
    ax.set_aspect("equal")
    ax.set_title(f"{scenario.name}, t = {time:.1f} s", fontsize=9)
    fig.canvas.draw()
    image = np.asarray(cast(FigureCanvasAgg, fig.canvas).buffer_rgba())[..., :3].copy()  # new_figure's canvas
    return image

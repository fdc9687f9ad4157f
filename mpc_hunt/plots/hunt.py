"""The trajectory figure of a hunt (as the paper's Figs. 7–8), and the drawing it shares with the animation.

Everything is drawn on a :class:`matplotlib.figure.Figure` with an Agg canvas,
never through pyplot, so no display is needed.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle

from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.scenario import Scenario

ATTACKER_COLOUR = "tab:red"
DEFENDER_COLOURS = (
    "tab:blue",
    "tab:green",
    "tab:orange",
    "tab:purple",
    "tab:brown",
    "tab:cyan",
    "tab:pink",
    "tab:olive",
    "tab:gray",
)
OBSTACLE_COLOUR = "0.6"
START_MARKER = "o"
END_MARKER = "s"
MARGIN = 1.0  # m of free space around everything drawn
FIGURE_SIZE = (8.0, 6.0)
FIGURE_DPI = 120
LAYOUT_PASSES = 5  # constrained layout around an equal-aspect axes settles over a few draws


def new_figure(size: tuple[float, float], dpi: float) -> tuple[Figure, Axes]:
    """A figure on an Agg canvas (no pyplot), laid out so an outside legend fits."""
    fig = Figure(figsize=size, dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    return fig, fig.add_subplot()


def settle_layout(fig: Figure) -> None:
    """Run the constrained layout for ``LAYOUT_PASSES`` draws, by when it has settled, then freeze it."""
    for _ in range(LAYOUT_PASSES):
        fig.canvas.draw()
    fig.set_layout_engine("none")


def defender_colour(i: int) -> str:
    return DEFENDER_COLOURS[i % len(DEFENDER_COLOURS)]


def hunt_title(result: HuntResult, scenario: Scenario) -> str:
    return f"{scenario.name}, {'with' if result.prediction else 'without'} prediction"


def last_finite_step(result: HuntResult) -> int:
    """The last step at which every position is finite (a hunt may end on a non-finite state)."""
    finite = np.isfinite(result.attacker).all(axis=1) & np.isfinite(result.defenders).all(axis=(1, 2))
    return int(np.flatnonzero(finite)[-1]) if finite.any() else 0


def paths(result: HuntResult) -> list[np.ndarray]:
    """The attacker's path, then each defender's: (K+1, 2) each."""
    return [result.attacker] + [result.defenders[:, i] for i in range(result.defenders.shape[1])]


def colours(result: HuntResult) -> list[str]:
    """One colour per path of :func:`paths`."""
    return [ATTACKER_COLOUR] + [defender_colour(i) for i in range(result.defenders.shape[1])]


def draw_obstacles(ax: Axes, scenario: Scenario) -> None:
    """Grey discs, each with a faint ring at the protective distance from its surface."""
    reach = scenario.hunt.protective_distance
    for j, o in enumerate(scenario.obstacles):
        first = j == 0
        ax.add_patch(
            Circle(
                o.centre,
                o.radius,
                facecolor=OBSTACLE_COLOUR,
                edgecolor="0.35",
                zorder=1,
                label="obstacle" if first else None,
            )
        )
        ax.add_patch(
            Circle(
                o.centre,
                o.radius + reach,
                fill=False,
                edgecolor=OBSTACLE_COLOUR,
                linestyle=":",
                linewidth=0.8,
                zorder=1,
                label="protective distance" if first else None,
            )
        )


def draw_paths(ax: Axes, result: HuntResult, *, with_lengths: bool = False) -> list[Line2D]:
    """Every whole path, labelled (defenders optionally with their path length); returns the lines."""
    labels = ["attacker"] + [
        f"defender {i + 1}" + (f" ({length:.2f} m)" if with_lengths else "")
        for i, length in enumerate(result.path_lengths)
    ]
    return [
        ax.plot(p[:, 0], p[:, 1], color=c, linewidth=1.4, label=label, zorder=3)[0]
        for p, c, label in zip(paths(result), colours(result), labels)
    ]


def draw_markers(ax: Axes, result: HuntResult, step: int, marker: str, size: float = 7.0) -> list[Line2D]:
    """Every robot's position at ``step`` as ``marker``; returns one marker line per path."""
    return [
        ax.plot(
            p[step, 0],
            p[step, 1],
            marker=marker,
            markersize=size,
            color=c,
            markeredgecolor="black",
            markeredgewidth=0.6,
            linestyle="none",
            zorder=4,
        )[0]
        for p, c in zip(paths(result), colours(result))
    ]


def draw_perception(ax: Axes, scenario: Scenario, centre, label: str, **style) -> Circle:
    """The attacker's perception radius R_agg round ``centre``, an unfilled circle in its colour drawn with
    ``style``."""
    circle = Circle(
        centre, scenario.attacker.perception_radius, fill=False, edgecolor=ATTACKER_COLOUR, label=label, **style
    )
    ax.add_patch(circle)
    return circle


def marker_legend(ax: Axes, labels: dict[str, str]) -> None:
    """Legend-only black markers explaining the marker shapes, e.g. {START_MARKER: "start"}."""
    for marker, label in labels.items():
        ax.plot([], [], marker=marker, color="white", markeredgecolor="black", linestyle="none", label=label)


def frame_axes(ax: Axes, result: HuntResult, scenario: Scenario, title: str) -> None:
    """Limits that hold every path and obstacle, equal aspect, labels in metres, an outside legend."""
    points = np.concatenate([p[np.isfinite(p).all(axis=1)] for p in paths(result)])
    lows, highs = [points.min(axis=0)], [points.max(axis=0)]
    if scenario.obstacles:
        c, r = scenario.obstacle_centres, scenario.obstacle_radii[:, None]
        lows.append((c - r).min(axis=0))
        highs.append((c + r).max(axis=0))
    set_window(ax, np.min(lows, axis=0) - MARGIN, np.max(highs, axis=0) + MARGIN, title)
    ax.figure.legend(loc="outside right upper", fontsize="small")


def set_window(ax: Axes, low: np.ndarray, high: np.ndarray, title: str, fontsize: float | None = None) -> None:
    """The axes show ``low``..``high`` (m) at equal aspect, labelled in metres, on a faint grid."""
    ax.set_xlim(low[0], high[0])
    ax.set_ylim(low[1], high[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.grid(alpha=0.3)
    ax.set_title(title, fontsize=fontsize)


def predicted_path(result: HuntResult) -> np.ndarray | None:
    """The attacker's straight line as first predicted (the paper's red dotted line), (2, 2), or None.

    The prediction is first made at the first step whose intercepts differ from
    the attacker's own position (its velocity is then known); the line runs from
    the attacker there to the farthest of that step's intercepts. None without
    prediction, since the approach targets are then the attacker's current positions.
    """
    if not result.prediction:
        return None
    for k in range(len(result.intercepts)):
        targets = result.intercepts[k][np.isfinite(result.intercepts[k]).all(axis=1)]
        reach = norm(targets - result.attacker[k])
        if len(targets) and reach.max() > 0:
            return np.array([result.attacker[k], targets[np.argmax(reach)]])
    return None


def plot_hunt(result: HuntResult, scenario: Scenario, path: str | Path, title: str | None = None) -> None:
    """Write the trajectory figure of one hunt to ``path`` (format from its extension)."""
    fig, ax = new_figure(FIGURE_SIZE, FIGURE_DPI)
    draw_obstacles(ax, scenario)
    draw_paths(ax, result, with_lengths=True)
    end = last_finite_step(result)
    draw_markers(ax, result, 0, START_MARKER)
    draw_markers(ax, result, end, END_MARKER)
    predicted = predicted_path(result)
    if predicted is not None:
        # wide enough to show beside the attacker's path, which it follows until the herding starts
        ax.plot(
            predicted[:, 0],
            predicted[:, 1],
            color=ATTACKER_COLOUR,
            linestyle=":",
            linewidth=3.0,
            alpha=0.6,
            label="predicted attacker path",
            zorder=2,
        )
    if result.captured:
        ax.add_patch(
            Circle(
                result.attacker[end],
                result.final_hunting_radius,
                fill=False,
                edgecolor="black",
                linestyle="--",
                linewidth=1.0,
                zorder=5,
                label=f"hunting circle ({result.final_hunting_radius:.2f} m)",
            )
        )
    marker_legend(ax, {START_MARKER: "start", END_MARKER: "end"})
    frame_axes(ax, result, scenario, hunt_title(result, scenario) if title is None else title)
    settle_layout(fig)
    fig.savefig(path)

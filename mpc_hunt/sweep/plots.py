"""A sweep's figures, from its rows alone: success rate against defenders, obstacles and speed ratio,
and a histogram of capture times (one line or bar group per strategy)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

BY = (("n_defenders", "defenders"), ("n_obstacles", "obstacles"), ("speed_ratio", "speed ratio v_a / v_d"))


def _rate_by(rows: list[dict], key: str) -> tuple[np.ndarray, np.ndarray]:
    counted = [r for r in rows if r["outcome"] != "uncapturable"]
    if key == "speed_ratio":   # a continuous parameter: four equal bins
        edges = np.linspace(0.0, 1.0, 5)
        values = [edges[min(np.searchsorted(edges, r[key], side="right") - 1, 3)] + 0.125 for r in counted]
    else:
        values = [r[key] for r in counted]
    xs = np.array(sorted(set(values)))
    rates = np.array([np.mean([r["outcome"] == "captured" for r, v in zip(counted, values) if v == x]) for x in xs])
    return xs, rates


def write_plots(rows: list[dict], folder: str | Path) -> list[Path]:
    """Write the four figures as PNG into ``folder``; returns their paths."""
    folder = Path(folder)
    strategies = list(dict.fromkeys(r["strategy"] for r in rows))
    written = []
    for key, label in BY:
        fig = Figure(figsize=(5, 3.5))
        FigureCanvasAgg(fig)
        ax = fig.add_subplot()
        for s in strategies:
            xs, rates = _rate_by([r for r in rows if r["strategy"] == s], key)
            ax.plot(xs, 100 * rates, marker="o", label=s)
        ax.set_xlabel(label + (" (bin centres)" if key == "speed_ratio" else ""))
        ax.set_ylabel("captured (%)")
        ax.set_ylim(-5, 105)
        ax.legend(fontsize=7)
        fig.tight_layout()
        written.append(folder / f"success_by_{key}.png")
        fig.savefig(written[-1])
    fig = Figure(figsize=(5, 3.5))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    times = [[r["capture_time_s"] for r in rows if r["strategy"] == s and r["outcome"] == "captured"]
             for s in strategies]
    if any(times):
        ax.hist([t for t in times], bins=20, label=strategies)
    ax.set_xlabel("capture time (s)")
    ax.set_ylabel("hunts")
    ax.legend(fontsize=7)
    fig.tight_layout()
    written.append(folder / "capture_times.png")
    fig.savefig(written[-1])
    return written

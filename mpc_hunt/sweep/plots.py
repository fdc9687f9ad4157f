"""A sweep's figures, from its rows alone: success among the reachable hunts against defenders, obstacles and
speed ratio, each group's rate with its 95 % Wilson interval (one line per strategy), and a histogram of capture
times."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from mpc_hunt.sweep.summary import wilson

BY = (("n_defenders", "defenders"), ("n_obstacles", "obstacles"), ("speed_ratio", "speed ratio v_a / v_d"))
SPEED_BINS = np.linspace(0.0, 1.0, 5)   # a continuous parameter: four equal bins, drawn at their centres
DODGE = 0.06                            # of a group's spacing: strategies side by side, their bars apart


def _group(row: dict, key: str) -> float:
    if key == "speed_ratio":
        i = min(int(np.searchsorted(SPEED_BINS, row[key], side="right")) - 1, len(SPEED_BINS) - 2)
        return float(SPEED_BINS[i] + SPEED_BINS[i + 1]) / 2
    return float(row[key])


def rate_by(rows: list[dict], key: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per value of ``key``: the groups, the success rate among their reachable hunts and its interval (2, n)."""
    reachable = [r for r in rows if r["outcome"] != "uncapturable" and r["reachable"]]
    groups = [_group(r, key) for r in reachable]
    xs = np.array(sorted(set(groups)))
    won = [sum(r["outcome"] == "captured" for r, g in zip(reachable, groups) if g == x) for x in xs]
    n = [groups.count(x) for x in xs]
    rates = np.array([w / m for w, m in zip(won, n)])
    bounds = np.array([wilson(w, m) for w, m in zip(won, n)]).reshape(-1, 2).T
    return xs, rates, bounds


def write_plots(rows: list[dict], folder: str | Path) -> list[Path]:
    """Write the four figures as PNG into ``folder``; returns their paths."""
    folder = Path(folder)
    strategies = list(dict.fromkeys(r["strategy"] for r in rows))
    written = []
    for key, label in BY:
        fig = Figure(figsize=(5.5, 3.8))
        FigureCanvasAgg(fig)
        ax = fig.add_subplot()
        spacing = 0.25 if key == "speed_ratio" else 1.0
        for j, s in enumerate(strategies):
            xs, rates, bounds = rate_by([r for r in rows if r["strategy"] == s], key)
            shift = (j - (len(strategies) - 1) / 2) * DODGE * spacing
            ax.errorbar(xs + shift, 100 * rates, yerr=100 * np.abs(bounds - rates), marker="o", capsize=3,
                        label=s)
        ticks = sorted({_group(r, key) for r in rows if r["outcome"] != "uncapturable" and r["reachable"]})
        ax.set_xticks(ticks)
        ax.set_xlabel(label + (" (bin centres)" if key == "speed_ratio" else ""))
        ax.set_ylabel("captured of reachable hunts (%)")
        ax.set_title("95 % Wilson intervals", fontsize=8)
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

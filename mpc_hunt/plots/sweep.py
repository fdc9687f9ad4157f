"""A sweep's figures, from its rows alone: success among the reachable hunts against defenders, obstacles and
speed ratio, each group's rate with its 95 % Wilson interval (one line per strategy, one panel per attacker),
success per attacker, and a histogram of capture times. When the rows hold several beliefs, a line is a strategy
with one belief."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from mpc_hunt.sweep.summary import combination, wilson

BY = (("n_defenders", "defenders"), ("n_obstacles", "obstacles"), ("speed_ratio", "speed ratio v_a / v_d"))
SPEED_BINS = np.linspace(0.0, 1.0, 5)  # a continuous parameter: four equal bins, drawn at their centres
DODGE = 0.06  # of a group's spacing: strategies side by side, their bars apart
RATE_LABEL = "captured of reachable hunts (%)"


def _group(row: dict, key: str) -> float:
    if key == "speed_ratio":
        i = min(int(np.searchsorted(SPEED_BINS, row[key], side="right")) - 1, len(SPEED_BINS) - 2)
        return float(SPEED_BINS[i] + SPEED_BINS[i + 1]) / 2
    return float(row[key])


def _reachable(rows: list[dict]) -> list[dict]:
    return [r for r in rows if r["outcome"] != "uncapturable" and r["reachable"]]


def rate_by(rows: list[dict], key: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per value of ``key``: the groups, the success rate among their reachable hunts and its interval (2, n)."""
    reachable = _reachable(rows)
    groups = [_group(r, key) for r in reachable]
    xs = np.array(sorted(set(groups)))
    won = [sum(r["outcome"] == "captured" for r, g in zip(reachable, groups) if g == x) for x in xs]
    n = [groups.count(x) for x in xs]
    rates = np.array([w / m for w, m in zip(won, n)])
    bounds = np.array([wilson(w, m) for w, m in zip(won, n)]).reshape(-1, 2).T
    return xs, rates, bounds


def lines_by_attacker(rows: list[dict]) -> tuple[list[str], dict[str, dict[str, list[dict]]]]:
    """The attackers, and per line (the strategy, with its belief when the rows hold several) per attacker its
    rows; both in order of first appearance."""
    several = len({combination(r)[2] for r in rows}) > 1
    attackers: dict[str, None] = {}
    lines: dict[str, dict[str, list[dict]]] = {}
    for r in rows:
        strategy, attacker, belief = combination(r)
        attackers[attacker] = None
        lines.setdefault(f"{strategy}, {belief}" if several else strategy, {}).setdefault(attacker, []).append(r)
    return list(attackers), lines


def _figure(panels: int, width: float = 5.5) -> tuple[Figure, np.ndarray]:
    """A figure of ``panels`` axes side by side (at least one), sharing the y axis."""
    fig = Figure(figsize=(max(width, 4.5 * panels), 3.8))
    FigureCanvasAgg(fig)
    return fig, fig.subplots(1, max(1, panels), sharey=True, squeeze=False)[0]


def _save(fig: Figure, path: Path) -> Path:
    fig.savefig(path, bbox_inches="tight")  # the whole figure, a legend beside the axes included
    return path


def _success_by(attackers: list[str], lines: dict, key: str, label: str, path: Path) -> Path:
    """Success among reachable hunts against ``key``, one panel per attacker, one line per strategy."""
    fig, axes = _figure(len(attackers))
    spacing = 0.25 if key == "speed_ratio" else 1.0
    for ax, attacker in zip(axes, attackers):
        mine = {name: by[attacker] for name, by in lines.items() if attacker in by}
        for j, (name, rows) in enumerate(mine.items()):
            xs, rates, bounds = rate_by(rows, key)
            shift = (j - (len(mine) - 1) / 2) * DODGE * spacing
            ax.errorbar(xs + shift, 100 * rates, yerr=100 * np.abs(bounds - rates), marker="o", capsize=3, label=name)
        ax.set_xticks(sorted({_group(r, key) for rows in mine.values() for r in _reachable(rows)}))
        ax.set_xlabel(label + (" (bin centres)" if key == "speed_ratio" else ""))
        ax.set_title(("" if len(attackers) == 1 else f"attacker {attacker}: ") + "95 % Wilson intervals", fontsize=8)
        ax.set_ylim(-5, 105)
        ax.legend(fontsize=7)
    axes[0].set_ylabel(RATE_LABEL)
    return _save(fig, path)


def _success_by_attacker(attackers: list[str], lines: dict, path: Path) -> Path:
    """Success among reachable hunts per attacker, one series per strategy, with 95 % Wilson intervals."""
    fig, (ax,) = _figure(1, width=5.5 + 0.7 * len(attackers))
    for j, (name, by) in enumerate(lines.items()):
        reachable = [(i, _reachable(by.get(a, []))) for i, a in enumerate(attackers)]
        points = [(i, sum(r["outcome"] == "captured" for r in rows), len(rows)) for i, rows in reachable if rows]
        if not points:
            continue
        xs = np.array([i for i, _, _ in points]) + (j - (len(lines) - 1) / 2) * DODGE
        rates = np.array([w / n for _, w, n in points])
        bounds = np.array([wilson(w, n) for _, w, n in points]).T
        ax.errorbar(
            xs, 100 * rates, yerr=100 * np.abs(bounds - rates), marker="o", capsize=3, linestyle="none", label=name
        )
    ax.set_xticks(range(len(attackers)), attackers)
    ax.set_xlabel("attacker")
    ax.set_ylabel(RATE_LABEL)
    ax.set_title("95 % Wilson intervals", fontsize=8)
    ax.set_ylim(-5, 105)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside the axes, not over the points
    return _save(fig, path)


def _capture_times(attackers: list[str], lines: dict, path: Path) -> Path:
    """A histogram of capture times, one series per strategy (and attacker, when there are several)."""
    fig = Figure(figsize=(5, 3.5))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    series = {
        (name if len(attackers) == 1 else f"{name} vs {a}"): [
            r["capture_time_s"] for r in rows if r["outcome"] == "captured"
        ]
        for name, by in lines.items()
        for a, rows in by.items()
    }
    if any(series.values()):
        ax.hist(list(series.values()), bins=20, label=list(series))
        ax.legend(fontsize=7)
    ax.set_xlabel("capture time (s)")
    ax.set_ylabel("hunts")
    return _save(fig, path)


def write_plots(rows: list[dict], folder: str | Path) -> list[Path]:
    """Write the five figures as PNG into ``folder``; returns their paths."""
    folder = Path(folder)
    attackers, lines = lines_by_attacker(rows)
    written = [_success_by(attackers, lines, key, label, folder / f"success_by_{key}.png") for key, label in BY]
    written.append(_success_by_attacker(attackers, lines, folder / "success_by_attacker.png"))
    written.append(_capture_times(attackers, lines, folder / "capture_times.png"))
    return written

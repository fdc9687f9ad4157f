"""The figures of a compare run: performance profile, time against gap, time against horizon.

- ``performance_profile.png``: the Dolan–Moré profile of all-in solve time over
  the pairs, a failed solve counted as never solved; one panel per mode and horizon.
- ``time_vs_gap.png``: each pair's median all-in time against its median
  optimality gap (drawn at 1e-12 when smaller), coloured by its largest true
  violation; one panel per mode and horizon.
- ``time_vs_horizon.png``: each pair's median all-in time against the horizon; one panel per mode.

Drawn on Agg canvases, never through pyplot.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure
from matplotlib.ticker import LogLocator, NullFormatter

from mpc_hunt.bench.compare import CompareRun
from mpc_hunt.bench.metrics import performance_profile

FIGURES = ("performance_profile.png", "time_vs_gap.png", "time_vs_horizon.png")
MARKERS = "osD^v<>pPX*h8Hd1234+x"
COLOURS = (
    "tab:blue",
    "tab:orange",
    "tab:green",
    "tab:red",
    "tab:purple",
    "tab:brown",
    "tab:pink",
    "tab:gray",
    "tab:olive",
    "tab:cyan",
    "black",
    "darkgoldenrod",
)
LINESTYLES = ("-", "--", ":", "-.")
PANEL = (4.2, 3.4)
DPI = 110
GAP_FLOOR = 1e-12  # smaller gaps (0 or negative included) are drawn at this height
VIOLATION_FLOOR = 1e-12


def _figure(rows: int, cols: int) -> tuple[Figure, np.ndarray]:
    fig = Figure(figsize=(PANEL[0] * cols + 1.5, PANEL[1] * rows), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig, np.atleast_2d(fig.subplots(rows, cols, squeeze=False))


def pair_style(k: int) -> dict:
    """The k-th pair's colour, marker and line style: the first 20 pairs have markers of their own (the scatter
    tells them apart by marker alone), and no two of the first 48 share colour and line style."""
    return {
        "color": COLOURS[k % len(COLOURS)],
        "marker": MARKERS[k % len(MARKERS)],
        "linestyle": LINESTYLES[k // len(COLOURS) % len(LINESTYLES)],
    }


def _label(pair: tuple[str, str]) -> str:
    return f"{pair[0]}/{pair[1]}"


def _log_x(ax) -> None:
    """A log time axis labelled at whole decades only (minor labels crowd a short range)."""
    ax.set_xscale("log")
    ax.xaxis.set_major_locator(LogLocator(base=10))
    ax.xaxis.set_minor_formatter(NullFormatter())


def profile_times(run: CompareRun, mode: str, horizon: int) -> dict[tuple[str, str], np.ndarray]:
    """Each pair's all-in times (inf where it failed) on the problems every pair finished, in one order."""
    times: dict[tuple[str, str], dict[str, float]] = {pair: {} for pair in run.pairs}
    for r in run.records:
        if r.mode == mode and r.horizon == horizon:
            times[(r.formulation, r.backend)][r.problem] = r.solve_time if r.success else np.inf
    common = sorted(set.intersection(*(set(t) for t in times.values()))) if times else []
    return {pair: np.array([t[p] for p in common]) for pair, t in times.items() if common}


def plot_profile(run: CompareRun, path: Path) -> None:
    fig, axes = _figure(len(run.modes), len(run.horizons))
    for i, mode in enumerate(run.modes):
        for j, horizon in enumerate(run.horizons):
            ax = axes[i, j]
            times = profile_times(run, mode, horizon)
            if times:
                taus, profile = performance_profile({_label(p): t for p, t in times.items()})
                top = max(2.0, float(taus[-1]) * 1.5)
                index = {_label(p): k for k, p in enumerate(run.pairs)}
                for label, rho in profile.items():
                    ax.step(
                        np.append(taus, top),
                        np.append(rho, rho[-1]),
                        where="post",
                        label=label,
                        **pair_style(index[label]),
                        markevery=[0],
                        lw=1.3,
                    )
                _log_x(ax)
            ax.set(
                title=f"{mode}, N = {horizon}",
                xlabel="τ (time ÷ fastest on the problem)",
                ylabel="share of problems solved",
                ylim=(-0.02, 1.02),
            )
            ax.grid(alpha=0.3)
    axes[0, -1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    fig.savefig(path)


def plot_time_gap(run: CompareRun, rows: list[dict], path: Path) -> None:
    fig, axes = _figure(len(run.modes), len(run.horizons))
    violations = [max(r["max_violation"] or 0.0, VIOLATION_FLOOR) for r in rows]
    norm = LogNorm(vmin=VIOLATION_FLOOR, vmax=max(max(violations, default=1.0), 1e-3))
    scatter = None
    for i, mode in enumerate(run.modes):
        for j, horizon in enumerate(run.horizons):
            ax = axes[i, j]
            for r in rows:
                if r["mode"] != mode or r["horizon"] != horizon or r["optimality_gap_median"] is None:
                    continue
                k = run.pairs.index((r["formulation"], r["backend"]))
                scatter = ax.scatter(
                    r["solve_time_median_s"] * 1e3,
                    max(r["optimality_gap_median"], GAP_FLOOR),
                    c=[max(r["max_violation"] or 0.0, VIOLATION_FLOOR)],
                    norm=norm,
                    cmap="viridis",
                    marker=pair_style(k)["marker"],
                    s=60,
                    edgecolors="k",
                    label=_label(run.pairs[k]),
                )
            _log_x(ax)
            ax.set_yscale("log")
            ax.margins(0.2)
            ax.set(
                title=f"{mode}, N = {horizon}",
                xlabel="median all-in time (ms)",
                ylabel=f"median optimality gap (≥ {GAP_FLOOR:g})",
            )
            ax.grid(alpha=0.3)
    if scatter is not None:
        fig.colorbar(scatter, ax=axes[:, -1].tolist(), label="largest true violation (m)")
        handles, labels = axes[0, 0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="outside lower center", ncols=min(6, len(labels)), fontsize="small")
    fig.savefig(path)


def plot_time_horizon(run: CompareRun, rows: list[dict], path: Path) -> None:
    fig, axes = _figure(1, len(run.modes))
    for i, mode in enumerate(run.modes):
        ax = axes[0, i]
        for k, pair in enumerate(run.pairs):
            points = sorted(
                (r["horizon"], r["solve_time_median_s"] * 1e3)
                for r in rows
                if r["mode"] == mode and (r["formulation"], r["backend"]) == pair
            )
            if points:
                ax.plot(*zip(*points), **pair_style(k), label=_label(pair))
        ax.set_yscale("log")
        ax.set(title=mode, xlabel="horizon N", ylabel="median all-in time (ms)", xticks=run.horizons)
        ax.grid(alpha=0.3)
    axes[0, -1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    fig.savefig(path)


def plot_compare(run: CompareRun, rows: list[dict], folder: Path) -> list[Path]:
    """Write the three figures into ``folder``; returns their paths."""
    paths = [folder / name for name in FIGURES]
    plot_profile(run, paths[0])
    plot_time_gap(run, rows, paths[1])
    plot_time_horizon(run, rows, paths[2])
    return paths

"""The figure of a sweep's typical hunts (:func:`mpc_hunt.sweep.typical.typical_hunts`): each zoomed on its capture
region (:func:`mpc_hunt.plots.capture_region.plot_capture_regions`), titled with its strategy, its attacker and
belief when not the default, its scenario, and its capture time or its cause of loss and closest approach."""

from __future__ import annotations

from pathlib import Path

from mpc_hunt.plots.capture_region import plot_capture_regions
from mpc_hunt.sweep.typical import TypicalHunt
from mpc_hunt.world.behaviours import DEFAULT_BEHAVIOUR
from mpc_hunt.world.belief import Belief

FIGURE = "typical_hunts.png"


def _title(hunt: TypicalHunt) -> str:
    row = hunt.row
    how = (
        f"captured at {row['capture_time_s']:.0f} s"
        if hunt.kind == "captured"
        else f"lost ({row['cause']}), closest approach {row['min_attacker_distance_m']:.2f} m"
    )
    against = (
        ""
        if (row["attacker"], row["belief"]) == (DEFAULT_BEHAVIOUR, Belief().label())
        else f" vs {row['attacker']}, belief {row['belief']}"
    )
    return f"typical {hunt.kind}: {row['strategy']}{against}, {row['name']}\n{how}"


def plot_typical_hunts(hunts: list[TypicalHunt], folder: Path) -> list[Path]:
    """Write the hunts side by side into ``folder``/typical_hunts.png; returns its path, or [] when there is none."""
    if not hunts:
        return []
    plot_capture_regions([(h.result, h.scenario, _title(h)) for h in hunts], folder / FIGURE)
    return [folder / FIGURE]

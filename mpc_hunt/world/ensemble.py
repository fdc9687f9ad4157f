"""How much a closed-loop result owes to the last bits: the same hunt, its starts moved by a nanometre.

A closed-loop hunt amplifies any difference in the last bit of a float (the
order of a sum, a fused multiply-add, another CPU's kernels) into a different
sequence of steps. So a committed closed-loop figure is stated with its spread:
the hunt is rerun with every robot's start moved by at most ``scale`` (1e-9 m
by default, far below any physical meaning), and the figure's band is the
median, least and largest value over those members and the nominal run
(docs/robustness.md, "Results that hold on every machine").
"""

from __future__ import annotations

import dataclasses
import math
from statistics import median

import numpy as np

from mpc_hunt.world.scenario import Scenario

SCALE = 1e-9  # m: the largest move of a start along each axis


def perturbed(scenario: Scenario, rng: np.random.Generator, scale: float = SCALE) -> Scenario:
    """``scenario`` with each robot's start moved by a uniform offset in [-scale, scale]² (``rng`` draws it)."""

    def moved(start) -> tuple[float, float]:
        dx, dy = rng.uniform(-scale, scale, size=2)
        return float(start[0] + dx), float(start[1] + dy)

    attacker = dataclasses.replace(scenario.attacker, start=moved(scenario.attacker.start))
    defenders = tuple(dataclasses.replace(d, start=moved(d.start)) for d in scenario.defenders)
    return dataclasses.replace(scenario, attacker=attacker, defenders=defenders)


def band(values: list[float]) -> dict:
    """Median, least and largest of a figure over an ensemble."""
    return {"median": float(median(values)), "min": float(min(values)), "max": float(max(values))}


def widened(b: dict, fraction: float, floor: float) -> tuple[float, float]:
    """The interval a rerun must land in: the band widened on each side by ``fraction`` of its width, at least
    ``floor`` (a finite ensemble's extremes are not the distribution's: its next member may fall just outside)."""
    margin = max(fraction * (b["max"] - b["min"]), floor)
    return b["min"] - margin, b["max"] + margin


def outside_band(value: float | None, b: dict | None, fraction: float, floor: float) -> bool:
    """True when ``value`` leaves the widened band (or exists where the ensemble had none, or the reverse)."""
    if value is None or b is None:
        return (value is None) != (b is None)
    low, high = widened(b, fraction, floor)
    return not (low <= value <= high) or not math.isfinite(value)

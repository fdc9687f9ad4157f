"""A strategy's typical captured and typical lost hunt, chosen from a sweep's rows, and a row's hunt rerun; the best
strategy's typical hunts, rerun (drawn by :mod:`mpc_hunt.plots.typical_hunts`).

Typical captured: the capture whose time is nearest the strategy's median capture time.
Typical lost: among the reachable hunts it lost, those lost by the commonest cause; of them, the one whose
closest defender–attacker approach is nearest that group's median. Ties go to the lowest hunt index, then to
the first row. A strategy's rows of every attacker and belief count together; a rerun runs the row's own.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.sweep.runner import hunt_rngs
from mpc_hunt.sweep.summary import best_strategy
from mpc_hunt.world.behaviours import with_behaviour
from mpc_hunt.world.belief import parse_belief
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.scenario_io import loads_scenario


def _nearest_median(rows: list[dict], key: str) -> dict:
    median = float(np.median([r[key] for r in rows]))
    return min(rows, key=lambda r: (abs(r[key] - median), r["index"]))


def typical_rows(rows: list[dict], strategy: str) -> dict[str, dict]:
    """``{"captured": row, "lost": row}`` for ``strategy``, each only if it has such a hunt."""
    mine = sorted((r for r in rows if r["strategy"] == strategy), key=lambda r: r["index"])
    captured = [r for r in mine if r["outcome"] == "captured"]
    lost = [
        r
        for r in mine
        if r["outcome"] == "failed"
        and r["reachable"]
        and r["cause"] != "error"
        and r["min_attacker_distance_m"] is not None
    ]
    typical = {}
    if captured:
        typical["captured"] = _nearest_median(captured, "capture_time_s")
    if lost:
        cause = Counter(r["cause"] for r in lost).most_common(1)[0][0]
        typical["lost"] = _nearest_median([r for r in lost if r["cause"] == cause], "min_attacker_distance_m")
    return typical


def rerun(row: dict) -> tuple[Scenario, HuntResult]:
    """The hunt of a sweep row, run again from the scenario, strategy, attacker and belief it stores, with the
    random generators the sweep gave it (:func:`mpc_hunt.sweep.runner.hunt_rngs`)."""
    scenario = with_behaviour(loads_scenario(row["scenario_toml"], row["name"]), row["attacker"])
    world, belief_rng = hunt_rngs(row["seed"], row["index"])
    controller = ControllerSpec.parse(row["strategy"]).build(
        scenario, belief=parse_belief(row["belief"]), rng=belief_rng
    )
    return scenario, simulate(scenario, controller, rng=world)


@dataclass(frozen=True)
class TypicalHunt:
    """A typical hunt rerun: its ``kind`` ("captured" or "lost"), its sweep row, its scenario and its result."""

    kind: str
    row: dict
    scenario: Scenario
    result: HuntResult


def typical_hunts(rows: list[dict], summaries: list[dict]) -> list[TypicalHunt]:
    """The best strategy's (:func:`mpc_hunt.sweep.summary.best_strategy`) typical captured and lost hunt, rerun;
    [] when there is no summary."""
    if not summaries:
        return []
    return [TypicalHunt(kind, row, *rerun(row)) for kind, row in typical_rows(rows, best_strategy(summaries)).items()]

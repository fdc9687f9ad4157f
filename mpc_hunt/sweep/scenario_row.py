"""A scenario as one flat row of a results table, and the 'capturable by definition' label.

A sweep stores one row per hunt; ``scenario_row`` gives the scenario's part of
it: scalars to query by, and the scenario's full TOML to rebuild it exactly.
"""

from __future__ import annotations

import math
from dataclasses import asdict

from mpc_hunt.sweep.reachability import edge_race_lost, race_labels
from mpc_hunt.world.hunting_circle import MIN_MEMBERS
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.scenario_io import dumps_scenario


def capturable_by_definition(scenario: Scenario) -> bool:
    """Can the hunting circle ever have the three members Eqs. 4–5 need?

    Its members are the defender robots plus obstacles standing in for them
    (``hunting_circle.members``, docs/model.md, E5 and E7): at most every defender and
    every obstacle. With fewer than ``MIN_MEMBERS`` = 3 of them in all, the
    success test can never hold and the hunt fails by definition. True is only
    necessary for a capture: the obstacles may lie too far apart to serve.
    """
    return len(scenario.defenders) + len(scenario.obstacles) >= MIN_MEMBERS


def scenario_row(scenario: Scenario, *, seed: int | None = None, index: int | None = None) -> dict[str, object]:
    """The scenario's parameters as one flat dict of scalars (str, int, float, bool or None).

    Keys: ``name``, ``seed`` and ``index`` (as given: the sweep's seed and the
    scenario's index in it), ``n_defenders``, ``n_obstacles``,
    ``capturable_by_definition``, ``reachable`` and ``comfortable``
    (:func:`mpc_hunt.sweep.reachability.reachable` and ``comfortable``),
    ``edge_race_lost`` (:func:`mpc_hunt.sweep.reachability.edge_race_lost`),
    ``defender_speed_min`` and ``_max`` (m/s),
    ``attacker_speed`` (m/s), ``speed_ratio`` (attacker / slowest defender),
    ``perception_radius`` (R_agg, m), ``attacker_heading`` (rad, of the nominal
    velocity; None if it is zero), ``attacker_start_x`` and ``_y``,
    ``obstacle_radius_min`` and ``_max`` (None without obstacles),
    ``arena_x_min``, ``arena_y_min``, ``arena_x_max``, ``arena_y_max`` (None
    without an arena), ``failed_defender`` and ``fails_at`` (the first defender
    that fails and when, s; None if none does), ``hunt_<name>`` for every hunt
    parameter, and
    ``scenario_toml``, the whole scenario (``loads_scenario`` rebuilds it).
    """
    a = scenario.attacker
    speeds = [d.max_speed for d in scenario.defenders]
    radii = [o.radius for o in scenario.obstacles]
    vx, vy = a.nominal_velocity
    arena = scenario.arena or (None, None, None, None)
    failing = [(i, d.fails_at) for i, d in enumerate(scenario.defenders) if d.fails_at is not None]
    failed_defender, fails_at = min(failing, key=lambda f: f[1], default=(None, None))
    reachable, comfortable = race_labels(scenario)
    row: dict[str, object] = {
        "name": scenario.name,
        "seed": seed,
        "index": index,
        "n_defenders": len(scenario.defenders),
        "n_obstacles": len(scenario.obstacles),
        "capturable_by_definition": capturable_by_definition(scenario),
        "reachable": reachable,
        "comfortable": comfortable,
        "edge_race_lost": edge_race_lost(scenario),
        "defender_speed_min": min(speeds),
        "defender_speed_max": max(speeds),
        "attacker_speed": a.max_speed,
        "speed_ratio": a.max_speed / min(speeds),
        "perception_radius": a.perception_radius,
        "attacker_heading": math.atan2(vy, vx) if (vx, vy) != (0.0, 0.0) else None,
        "attacker_start_x": a.start[0],
        "attacker_start_y": a.start[1],
        "obstacle_radius_min": min(radii, default=None),
        "obstacle_radius_max": max(radii, default=None),
        "arena_x_min": arena[0],
        "arena_y_min": arena[1],
        "arena_x_max": arena[2],
        "arena_y_max": arena[3],
        "failed_defender": failed_defender,
        "fails_at": fails_at,
    }
    row.update({f"hunt_{k}": v for k, v in asdict(scenario.hunt).items()})
    row["scenario_toml"] = dumps_scenario(scenario)
    return row

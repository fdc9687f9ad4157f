"""A hunt's result from its recorded paths: how it ended and the figures a report reads (clearances, separation,
path lengths, the final hunting radius)."""

from __future__ import annotations

import numpy as np

from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.world.arena import margin
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.hunting_circle import success_test


def hunt_result(
    scenario,
    controller,
    attacker,
    defenders,
    stages,
    intercepts,
    termination,
    held,
) -> HuntResult:
    """The result of a hunt of ``scenario`` by ``controller`` that took K steps: the attacker's (K + 1, 2) and the
    defenders' (K + 1, n, 2) positions, each step's capture-stage flags (K, n) and intercepts (K, n, 2), how it
    ended and for how many steps the success test held at its end."""
    hunt = scenario.hunt
    T = hunt.time_step
    K = len(attacker) - 1
    n = defenders.shape[1]
    finite = np.all(np.isfinite(attacker), axis=1) & np.all(np.isfinite(defenders), axis=(1, 2))
    a, d = attacker[finite], defenders[finite]
    centres, radii = scenario.obstacle_centres, scenario.obstacle_radii
    steps = np.diff(d, axis=0)
    path_lengths = norm(steps).sum(axis=0) if len(d) > 1 else np.zeros(n)
    final = success_test(a[-1], d[-1], centres, radii, hunt.hunt_radius, hunt.centre_tolerance)
    clearance = attacker_clearance = None
    # capture stage or not: the least clearance its commands led to
    by_stage: dict[bool, float | None] = {True: None, False: None}
    if len(radii):
        clearance = float(np.min(norm(d[:, :, None, :] - centres[None, None]) - radii))
        attacker_clearance = float(np.min(norm(a[:, None, :] - centres[None]) - radii))
        moved = finite[1:]  # position k + 1 is where the command of step k led
        reached = np.min(norm(defenders[1:][moved][:, :, None, :] - centres[None, None]) - radii, axis=2)
        stage = stages.reshape(K, n)[moved]
        for capture in by_stage:
            if np.any(stage == capture):
                by_stage[capture] = float(np.min(reached[stage == capture]))
    separation = None
    if n > 1:
        gaps = norm(d[:, :, None, :] - d[:, None, :, :])
        gaps[:, np.arange(n), np.arange(n)] = np.inf
        separation = float(gaps.min())
    captured = termination == "captured"
    return HuntResult(
        scenario=scenario.name,
        controller=controller.describe(),
        times=np.arange(K + 1) * T,
        attacker=attacker,
        defenders=defenders,
        capture_stage=stages.reshape(K, n),
        intercepts=intercepts.reshape(K, n, 2),
        termination=termination,
        captured=captured,
        capture_time=(K - held + 1) * T if captured else None,
        path_lengths=path_lengths,
        final_hunting_radius=final.radius,
        min_obstacle_clearance=clearance,
        min_defender_separation=separation,
        min_attacker_distance=float(np.min(norm(a[:, None, :] - d))),
        attacker_min_obstacle_clearance=attacker_clearance,
        approach_min_obstacle_clearance=by_stage[False],
        capture_min_obstacle_clearance=by_stage[True],
        min_arena_margin=None if scenario.arena is None else float(np.min(margin(scenario.arena, d))),
    )

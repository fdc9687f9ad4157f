"""Hunts that no controller can win: every defender is too far to reach the attacker in time.

Until a defender comes within R_agg of the attacker, the attacker does not
perceive it (Eq. 9 sums over the defenders within R_agg) and follows its
undisturbed path, set by its nominal intent and the obstacles alone (Eq. 2).
Until one comes within R_hunt, the success test cannot hold (Eqs. 4–5: every
member within R_hunt). A defender covers at most v_i·T per step, in any
direction (obstacles only lengthen its way). So if, along the undisturbed path
a_0 … a_K, up to the step K at which the attacker leaves the arena or the time
limit ends, every defender i keeps |p_i(0) − a_k| − max(R_agg, R_hunt) > v_i·k·T,
then the attacker never sees a defender and the hunt fails whatever the
defenders do. Such a hunt is *unreachable*; the converse does not hold (a
reachable hunt may still be lost by every controller).

A reachable hunt may still be a race that only a perfect controller wins: one
defender arriving a step before the attacker leaves cannot enclose it. The
stricter label *comfortable* asks that at least min(3, N_d) defenders (three
are the fewest that enclose) can each come within that distance of the
undisturbed path at least ``SPARE_TIME`` (20 s) before the attacker leaves the
arena or the time limit ends: time to close the circle once they are there.

With fewer than three robots an obstacle must be a member (``hunting_circle.members``),
so its surface must come within R_hunt of the attacker. Until the first defender
can be within R_agg, at step k_0, the attacker is on its undisturbed path, at
a_{k_0}; from there it moves at most v_a per unit time, pushed or not (Eq. 2
caps it). So a hunt in which every obstacle's surface stays farther than
R_hunt + v_a (t_limit − k_0 T) from a_{k_0} cannot be won either: such a hunt is
unreachable too.
"""

from __future__ import annotations

import math

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.sim.world_step import steps
from mpc_hunt.world.attacker import velocity_of
from mpc_hunt.world.geometry import length, norm
from mpc_hunt.world.packed import X_MAX, X_MIN, Y_MAX, Y_MIN, T
from mpc_hunt.world.scenario import Scenario

SPARE_TIME = 20.0  # s: what a comfortable hunt leaves the defenders to close the circle
ENCLOSING = 3  # the fewest defenders that can enclose an attacker without an obstacle


@kernel
def race(p0, starts, speeds, centres, radii, prm, limit, reach):
    """(the first step at which each defender can be within ``reach`` of the undisturbed path, or −1 for never;
    that path, a_0 … a_K, up to where the attacker leaves the arena, stops being finite or ``limit`` steps)."""
    nobody = np.empty((0, 2))
    path = np.empty((limit + 1, 2))
    first = np.full(starts.shape[0], -1)
    p = p0.copy()
    for k in range(limit + 1):
        path[k] = p
        for i in range(starts.shape[0]):
            if first[i] < 0 and length(p[0] - starts[i, 0], p[1] - starts[i, 1]) - reach <= speeds[i] * k * prm[T]:
                first[i] = k
        gone = p[0] < prm[X_MIN] or p[0] > prm[X_MAX] or p[1] < prm[Y_MIN] or p[1] > prm[Y_MAX]
        if k == limit or (k > 0 and (gone or not (math.isfinite(p[0]) and math.isfinite(p[1])))):
            return first, path[: k + 1]
        vx, vy = velocity_of(p, nobody, centres, radii, prm)
        p = np.array([p[0] + prm[T] * vx, p[1] + prm[T] * vy])
    return first, path


def arrival_steps(scenario: Scenario) -> tuple[np.ndarray, np.ndarray]:
    """(the first step at which each defender can be within reach of the undisturbed path, or −1 for never;
    that path, up to where the attacker leaves or time runs out): :func:`race`."""
    s = scenario
    reach = max(s.attacker.perception_radius, s.hunt.hunt_radius)
    return race(np.array(s.attacker.start, dtype=float), s.defender_starts, s.defender_max_speeds,
                s.obstacle_centres, s.obstacle_radii, s.packed, steps(s)[0], reach)  # fmt: skip


def undisturbed_path(scenario: Scenario) -> np.ndarray:
    """The attacker's positions a_0, a_1, … (rows) with no defender in sight, until it leaves the arena or time
    runs out."""
    return arrival_steps(scenario)[1]


def obstacle_in_reach(scenario: Scenario, first: np.ndarray, path: np.ndarray) -> bool:
    """With fewer than three defenders: can the attacker, at its top speed from where the first defender can
    meet it, come within R_hunt of some obstacle's surface before the time limit (the module's docstring)?
    Always True with three or more."""
    if len(scenario.defenders) >= ENCLOSING:
        return True
    if not len(scenario.obstacles) or not np.any(first >= 0):
        return False
    k0 = int(np.min(first[first >= 0]))
    hunt = scenario.hunt
    gaps = norm(path[k0] - scenario.obstacle_centres) - scenario.obstacle_radii
    return bool(
        np.min(gaps) - hunt.hunt_radius <= scenario.attacker.max_speed * (hunt.time_limit - k0 * hunt.time_step)
    )


def race_labels(scenario: Scenario) -> tuple[bool, bool]:
    """(:func:`reachable`, :func:`comfortable`) from one run of the undisturbed path."""
    first, path = arrival_steps(scenario)
    reached = bool(np.any(first >= 0)) and obstacle_in_reach(scenario, first, path)
    spare = int(round(SPARE_TIME / scenario.hunt.time_step))
    in_time = int(np.sum((first >= 0) & (first <= len(path) - 1 - spare))) >= min(ENCLOSING, len(first))
    return reached, reached and in_time


def comfortable(scenario: Scenario) -> bool:
    """Can at least min(3, N_d) defenders reach the attacker's undisturbed path ``SPARE_TIME`` before it
    leaves, and an obstacle stand in where it must (see the module's docstring)? Implies :func:`reachable`."""
    return race_labels(scenario)[1]


def reachable(scenario: Scenario) -> bool:
    """Can some defender, at full speed in a straight line, come within max(R_agg, R_hunt) of the
    attacker's undisturbed path in time, and, with fewer than three defenders, can an obstacle stand in
    (see the module's docstring)? False: the hunt cannot be won."""
    return race_labels(scenario)[0]


EDGE_SPACING = 0.05  # m: the arena's edges are checked at points this far apart


def edge_race_lost(scenario: Scenario) -> bool:
    """Could an attacker that runs straight for the arena's edge at v_a reach some edge point before every
    defender can come within R_hunt of it (each at its top speed, in a straight line)? False without an arena.

    A hunt whose attacker wins this race is lost against an evader that runs for that point from the start,
    whatever the defenders do: no defender can stand in its way in time. The paper's attacker does not run (it
    follows its intent until it perceives a defender), so such a hunt may still be reachable and comfortable;
    the label is what an evader needs beside them (docs/robustness.md). Obstacles are ignored: they lengthen
    the attacker's way as well as the defenders'.
    """
    if scenario.arena is None:
        return False
    x_min, y_min, x_max, y_max = scenario.arena
    xs = np.linspace(x_min, x_max, max(2, int(math.ceil((x_max - x_min) / EDGE_SPACING)) + 1))
    ys = np.linspace(y_min, y_max, max(2, int(math.ceil((y_max - y_min) / EDGE_SPACING)) + 1))
    edge = np.vstack(
        [
            np.column_stack([xs, np.full_like(xs, y_min)]),
            np.column_stack([xs, np.full_like(xs, y_max)]),
            np.column_stack([np.full_like(ys, x_min), ys]),
            np.column_stack([np.full_like(ys, x_max), ys]),
        ]
    )
    attacker_time = norm(edge - np.array(scenario.attacker.start)) / scenario.attacker.max_speed
    gaps = np.maximum(norm(edge[:, None, :] - scenario.defender_starts[None]) - scenario.hunt.hunt_radius, 0.0)
    defender_time = np.min(gaps / scenario.defender_max_speeds, axis=1)
    return bool(np.any(attacker_time < defender_time))

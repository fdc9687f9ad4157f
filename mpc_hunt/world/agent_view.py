"""What a learned agent reads: a fixed-length view of a hunt, the same for any team size and obstacle count.

The PPO attacker (:mod:`mpc_hunt.world.behaviours.ppo`) and the PPO team
(:mod:`mpc_hunt.control.ppo_team`) read these views, in training
(``python studies/train_ppo.py``) and when they play. Lengths are in units of
:data:`LENGTH` and clipped to ±:data:`REACH`, speeds in units of the defenders' top
speed; the world's axes are kept (the arena's edges are along them). Robots and
obstacles fill a fixed number of slots, nearest first, each with a flag that says
whether it holds one (an empty slot is zeros):

- :func:`attacker_view` (:data:`ATTACKER_VIEW` numbers): the attacker's margins to the
  arena's four edges; its intent's unit vector and speed; for up to
  :data:`DEFENDER_SLOTS` of the defenders it senses (within its sensing radius, as every
  attacker behaviour senses), their position relative to it and their velocity;
  for up to :data:`OBSTACLE_SLOTS` obstacles, the centre relative to it, the distance
  to the surface and the radius.
- :func:`defender_views` (:data:`DEFENDER_VIEW` numbers a row), for each defender i: the attacker
  relative to it, the attacker's velocity, intent and speed; its own velocity; the
  attacker's margins to the edges and its own; the team's size; for up to
  :data:`MATE_SLOTS` team-mates (nearest it first), each relative to it and to the
  attacker; for up to :data:`OBSTACLE_SLOTS` obstacles (nearest the attacker first),
  the centre relative to the attacker and to it, and the radius.

A defender sees the whole state (the paper's broadcast), as the environments' observation does; the
attacker, the defenders it senses.
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.geometry import length, norm, unit
from mpc_hunt.world.packed import HAS_ARENA, X_MAX, X_MIN, Y_MAX, Y_MIN

LENGTH = 5.0  # m: the unit of a view's lengths
REACH = 4.0  # a view's lengths are clipped to ±REACH · LENGTH (20 m, the sweep's arena)
DEFENDER_SLOTS = 5
MATE_SLOTS = 4
OBSTACLE_SLOTS = 3
ATTACKER_VIEW = 4 + 3 + 5 * DEFENDER_SLOTS + 5 * OBSTACLE_SLOTS
DEFENDER_VIEW = 2 + 2 + 3 + 2 + 4 + 4 + 1 + 5 * MATE_SLOTS + 6 * OBSTACLE_SLOTS


def _length(v) -> np.ndarray:
    """Lengths ``v`` in view units, each :func:`clipped`."""
    v = np.asarray(v, dtype=float)
    return np.array([clipped(x) for x in v.ravel().tolist()]).reshape(v.shape)


def margins(arena, p: np.ndarray) -> np.ndarray:
    """``p``'s distances to the arena's edges (x_min, x_max, y_min, y_max), in view units; REACH without an arena."""
    if arena is None:
        return np.full(4, REACH)
    x_min, y_min, x_max, y_max = arena
    return _length([p[0] - x_min, x_max - p[0], p[1] - y_min, y_max - p[1]])


def _slots(rows: list[np.ndarray], count: int, width: int) -> np.ndarray:
    """``rows`` (nearest first) in ``count`` slots of ``width`` numbers and a flag; the rest zeros."""
    out = np.zeros((count, width + 1))
    for k, row in enumerate(rows[:count]):
        out[k, :width], out[k, width] = row, 1.0
    return out.ravel()


def attacker_view(scenario, p_a: np.ndarray, p_d: np.ndarray, v_d: np.ndarray, radius: float) -> np.ndarray:
    """The attacker's view (the module's docstring) of the attacker at ``p_a`` and the defenders at ``p_d`` moving
    at ``v_d``, those strictly within ``radius`` sensed."""
    a, top = scenario.attacker, float(scenario.defender_max_speeds.max())
    rel = p_d - p_a
    distance = norm(rel)
    order = [i for i in np.argsort(distance, kind="stable") if distance[i] < radius]
    defenders = [np.concatenate([_length(rel[i]), v_d[i] / top]) for i in order]
    centres, radii = scenario.obstacle_centres, scenario.obstacle_radii
    surface = norm(centres - p_a) - radii if len(radii) else np.empty(0)
    obstacles = [
        np.concatenate([_length(centres[j] - p_a), _length([surface[j], radii[j]])])
        for j in np.argsort(surface, kind="stable")
    ]
    intent = unit(np.asarray(a.nominal_velocity, dtype=float))
    return np.concatenate(
        [
            margins(scenario.arena, p_a),
            intent,
            [a.max_speed / top],
            _slots(defenders, DEFENDER_SLOTS, 4),
            _slots(obstacles, OBSTACLE_SLOTS, 4),
        ]
    )


def defender_views(scenario, p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, v_d: np.ndarray) -> np.ndarray:
    """Every defender's view (the module's docstring), a row each; ``v_a`` and ``v_d`` the velocities over the last
    step (:func:`views_of`)."""
    a, top = scenario.attacker, float(scenario.defender_max_speeds.max())
    p_d = np.asarray(p_d, dtype=float).reshape(-1, 2)
    intent = unit(np.asarray(a.nominal_velocity, dtype=float))
    return views_of(np.asarray(p_a, dtype=float), np.asarray(v_a, dtype=float), p_d,
                    np.asarray(v_d, dtype=float).reshape(-1, 2), scenario.obstacle_centres, scenario.obstacle_radii,
                    intent, a.max_speed / top, top, scenario.packed)  # fmt: skip


@kernel
def clipped(x: float) -> float:
    """A length in view units, clipped to ±REACH (NumPy's clip: NaN kept)."""
    x = x / LENGTH
    return x if x != x else min(max(x, -REACH), REACH)


@kernel
def views_of(p_a, v_a, p_d, v_d, centres, radii, intent, speed, top, prm) -> np.ndarray:
    """The defenders' views (the module's docstring), a row each: ``intent`` the attacker's unit intent, ``speed``
    its top speed over the defenders', ``top``; the arena's edges from ``prm``."""
    n, m = p_d.shape[0], radii.shape[0]
    out = np.zeros((n, DEFENDER_VIEW))
    surface = np.empty(m)
    for j in range(m):
        surface[j] = length(centres[j, 0] - p_a[0], centres[j, 1] - p_a[1]) - radii[j]
    nearest_attacker = np.argsort(surface, kind="mergesort")
    for i in range(n):
        row = out[i]
        mx, my = p_d[i, 0], p_d[i, 1]
        row[0], row[1] = clipped(p_a[0] - mx), clipped(p_a[1] - my)
        row[2], row[3] = v_a[0] / top, v_a[1] / top
        row[4], row[5], row[6] = intent[0], intent[1], speed
        row[7], row[8] = v_d[i, 0] / top, v_d[i, 1] / top
        for k, (px, py) in enumerate(((p_a[0], p_a[1]), (mx, my))):
            if prm[HAS_ARENA]:
                row[9 + 4 * k], row[10 + 4 * k] = clipped(px - prm[X_MIN]), clipped(prm[X_MAX] - px)
                row[11 + 4 * k], row[12 + 4 * k] = clipped(py - prm[Y_MIN]), clipped(prm[Y_MAX] - py)
            else:
                row[9 + 4 * k : 13 + 4 * k] = REACH
        row[17] = n / DEFENDER_SLOTS
        others = np.empty(n - 1, dtype=np.int64)
        away = np.empty(n - 1)
        c = 0
        for j in range(n):
            if j != i:
                others[c], away[c] = j, length(p_d[j, 0] - mx, p_d[j, 1] - my)
                c += 1
        order = others[np.argsort(away, kind="mergesort")]  # nearest first, ties in index order
        for k in range(min(MATE_SLOTS, n - 1)):
            j, at = order[k], 18 + 5 * k
            row[at], row[at + 1] = clipped(p_d[j, 0] - mx), clipped(p_d[j, 1] - my)
            row[at + 2], row[at + 3] = clipped(p_d[j, 0] - p_a[0]), clipped(p_d[j, 1] - p_a[1])
            row[at + 4] = 1.0
        for k in range(min(OBSTACLE_SLOTS, m)):
            j, at = nearest_attacker[k], 18 + 5 * MATE_SLOTS + 6 * k
            row[at], row[at + 1] = clipped(centres[j, 0] - p_a[0]), clipped(centres[j, 1] - p_a[1])
            row[at + 2], row[at + 3] = clipped(centres[j, 0] - mx), clipped(centres[j, 1] - my)
            row[at + 4], row[at + 5] = clipped(radii[j]), 1.0
    return out

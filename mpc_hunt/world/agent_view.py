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
- :func:`defender_view` (:data:`DEFENDER_VIEW` numbers), for defender i: the attacker
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

from mpc_hunt.world.geometry import norm, unit

LENGTH = 5.0  # m: the unit of a view's lengths
REACH = 4.0  # a view's lengths are clipped to ±REACH · LENGTH (20 m, the sweep's arena)
DEFENDER_SLOTS = 5
MATE_SLOTS = 4
OBSTACLE_SLOTS = 3
ATTACKER_VIEW = 4 + 3 + 5 * DEFENDER_SLOTS + 5 * OBSTACLE_SLOTS
DEFENDER_VIEW = 2 + 2 + 3 + 2 + 4 + 4 + 1 + 5 * MATE_SLOTS + 6 * OBSTACLE_SLOTS


def _length(v) -> np.ndarray:
    return np.clip(np.asarray(v, dtype=float) / LENGTH, -REACH, REACH)


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


def defender_view(scenario, i: int, p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, v_d: np.ndarray) -> np.ndarray:
    """Defender ``i``'s view (the module's docstring); ``v_a`` and ``v_d`` the velocities over the last step."""
    a, top = scenario.attacker, float(scenario.defender_max_speeds.max())
    me = p_d[i]
    others = [j for j in range(len(p_d)) if j != i]
    others.sort(key=lambda j: float(norm(p_d[j] - me)))
    mates = [np.concatenate([_length(p_d[j] - me), _length(p_d[j] - p_a)]) for j in others]
    centres, radii = scenario.obstacle_centres, scenario.obstacle_radii
    surface = norm(centres - p_a) - radii if len(radii) else np.empty(0)
    obstacles = [
        np.concatenate([_length(centres[j] - p_a), _length(centres[j] - me), _length([radii[j]])])
        for j in np.argsort(surface, kind="stable")
    ]
    intent = unit(np.asarray(a.nominal_velocity, dtype=float))
    return np.concatenate(
        [
            _length(p_a - me),
            np.asarray(v_a, dtype=float) / top,
            intent,
            [a.max_speed / top],
            v_d[i] / top,
            margins(scenario.arena, p_a),
            margins(scenario.arena, me),
            [len(p_d) / DEFENDER_SLOTS],
            _slots(mates, MATE_SLOTS, 4),
            _slots(obstacles, OBSTACLE_SLOTS, 5),
        ]
    )

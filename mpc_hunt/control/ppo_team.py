"""``ppo``: the Voronoi rule with a correction that one neural policy, shared by the team, learned by PPO.

Residual policy learning (Johannink et al., ICRA 2019; Silver et al., arXiv 1812.06298):
each step the Voronoi baseline (:mod:`mpc_hunt.control.voronoi`) gives every defender a
base velocity b_i; every ``decision_steps`` steps each active defender reads its own
view of the hunt (:func:`team_views`: :func:`mpc_hunt.world.agent_view.defender_views`,
the attacker, its velocity and intent, its team-mates, the nearest obstacles, the
arena's edges, and its base velocity) and the team's network (:mod:`mpc_hunt.world.mlp`,
evaluated in NumPy) gives its correction a_i in [−1, 1]², held until the next decision;
it asks for b_i + ``RESIDUAL`` · v_d · a_i. Every robot runs the same network (parameter
sharing, as multi-agent PPO does), so the team may have any size. The asked velocities
pass the same shield as every controller's (:func:`shielded`: capped at the robot's
speed, no step into an obstacle's R_safe or out of the arena, then the separation
filter, which keeps R_safe and the arena as well); the training ran with it too, before
R_safe and the arena joined the separation filter (the two differ only where a robot is
squeezed between a team-mate and an obstacle or the edge). Trained with Stable-Baselines3's PPO on a team of
3 against a mix of the world's attacker behaviours (``python studies/train_ppo.py``,
docs/envs.md), shipped as ``ppo_team.npz`` beside this module. Why a correction of the
baseline rather than a policy from nothing: with an hour of two cores, PPO from a random
network never captured, nor did a network cloned from the baseline (docs/envs.md).
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.control.controller import Command, Observation, attacker_velocity_estimate
from mpc_hunt.control.voronoi import VoronoiController
from mpc_hunt.world.agent_view import DEFENDER_VIEW, defender_views
from mpc_hunt.world.arena import safe_of
from mpc_hunt.world.geometry import capped
from mpc_hunt.world.mlp import ShippedPolicy
from mpc_hunt.world.packed import HAS_ARENA, MIN_SEPARATION, SAFETY, X_MAX, X_MIN, Y_MAX, Y_MIN, T
from mpc_hunt.world.safety import safety_arrays
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.separation import onto_rows, separation_rows

RESIDUAL = 0.5  # the largest correction, per component, as a share of the top speed
TEAM_VIEW = DEFENDER_VIEW + 2
TEAM_POLICY = ShippedPolicy(__package__, "ppo_team.npz", "defender", TEAM_VIEW)  # the team's network


def team_views(
    scenario: Scenario, p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, v_d: np.ndarray, base: np.ndarray
) -> np.ndarray:
    """Every defender's view, a row each: :func:`~mpc_hunt.world.agent_view.defender_views` and its base velocity,
    over the top speed."""
    top = float(scenario.defender_max_speeds.max())
    return np.hstack([defender_views(scenario, p_a, v_a, p_d, v_d), np.asarray(base, dtype=float) / top])


def corrected(
    scenario: Scenario, p_d: np.ndarray, base: np.ndarray, corrections: np.ndarray, active: np.ndarray
) -> np.ndarray:
    """The team's velocities: each base velocity plus its correction (``RESIDUAL`` · v_d · a_i), :func:`shielded`."""
    top = float(scenario.defender_max_speeds.max())
    return shielded(scenario, p_d, base + RESIDUAL * top * np.asarray(corrections, dtype=float), active)


def shielded(scenario: Scenario, p_d: np.ndarray, wished: np.ndarray, active: np.ndarray) -> np.ndarray:
    """The team's ``wished`` velocities capped at each robot's speed, kept out of obstacles' R_safe and in the
    arena, then separated (the module's docstring), the separation filter keeping R_safe and the arena too (a
    projection onto a separation row alone could push a robot into an obstacle); a stopped robot's row is 0
    (:func:`shield`)."""
    s, p_d = scenario, np.asarray(p_d, dtype=float)
    v = np.zeros_like(p_d)
    shield(p_d, np.asarray(wished, dtype=float), np.asarray(active, dtype=bool), s.defender_max_speeds,
           s.obstacle_centres, s.obstacle_radii, s.packed, v)  # fmt: skip
    return v


@kernel
def shield(p_d, wished, active, speeds, centres, radii, prm, v) -> None:
    """:func:`shielded` into ``v`` (zeros on entry): each active robot's wish capped (:func:`capped`) and kept safe
    (:func:`safe_of`), then projected (:func:`onto_rows`) onto its separation rows (every stopped robot held where
    it stands), its obstacles' rows and the arena's (each relaxed to b ≤ 0: never worse than now), in that order."""
    T_ = prm[T]
    for i in range(p_d.shape[0]):
        if active[i]:
            vx, vy = capped(wished[i, 0], wished[i, 1], speeds[i])
            v[i, 0], v[i, 1] = safe_of(p_d[i], vx, vy, centres, radii, prm)
    for i in range(p_d.shape[0]):
        if not active[i]:
            continue
        A_sep, b_sep = separation_rows(i, p_d, active, p_d, T_, prm[MIN_SEPARATION])
        A_safe, b_safe = safety_arrays(p_d[i], centres, radii, prm[SAFETY], T_)
        edges = 4 if prm[HAS_ARENA] else 0
        r = b_sep.shape[0]
        A, b = np.empty((r + b_safe.shape[0] + edges, 2)), np.empty(r + b_safe.shape[0] + edges)
        A[:r], b[:r] = A_sep, b_sep
        A[r : r + b_safe.shape[0]], b[r : r + b_safe.shape[0]] = A_safe, b_safe  # each b ≤ 0 (safety_arrays)
        r += b_safe.shape[0]
        if edges:
            x, y = p_d[i, 0], p_d[i, 1]
            for k, (ax, ay, gap) in enumerate(
                (
                    (T_, 0.0, prm[X_MIN] - x),
                    (-T_, 0.0, x - prm[X_MAX]),
                    (0.0, T_, prm[Y_MIN] - y),
                    (0.0, -T_, y - prm[Y_MAX]),
                )
            ):
                A[r + k, 0], A[r + k, 1] = ax, ay
                b[r + k] = gap if gap < 0.0 else 0.0  # as min(0.0, gap)
        v[i, 0], v[i, 1] = onto_rows(v[i, 0], v[i, 1], A, b, speeds[i], 0.0)


class PpoTeam:
    """The Voronoi rule corrected by the trained network on every defender (CLI ``--controller ppo``; the module's
    docstring)."""

    SUMMARY = (
        "the Voronoi encirclement with a correction one neural policy, shared by the team, learned by PPO "
        "(Stable-Baselines3)"
    )

    def __init__(self, scenario: Scenario, *, policy: str | None = None):
        self.scenario, self.policy_path = scenario, policy
        self.network = TEAM_POLICY.network(policy)
        self.base = VoronoiController(scenario)
        self.held = 0
        self.corrections: np.ndarray | None = None
        self.last: np.ndarray | None = None

    def describe(self) -> dict:
        return {"controller": "ppo", "policy": self.policy_path or TEAM_POLICY.name}

    def command(self, obs: Observation) -> Command:
        s = self.scenario
        p_a, P = obs.attacker, obs.defenders
        T = s.hunt.time_step
        base = self.base.command(obs)
        if self.held == 0 or self.corrections is None:  # (None only before the first decision, held 0 then)
            v_a = attacker_velocity_estimate(obs, T)
            v_d = np.zeros_like(P) if self.last is None else (P - self.last) / T
            views = team_views(s, p_a, v_a, P, v_d, base.velocities)
            self.corrections = np.array([self.network.action(view) for view in views])
            self.held = self.network.decision_steps
        self.held -= 1
        self.last = P.copy()
        velocities = corrected(s, P, base.velocities, self.corrections, obs.active)
        return Command(velocities, base.capture_stage, base.intercepts)

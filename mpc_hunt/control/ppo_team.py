"""``ppo``: the Voronoi rule with a correction that one neural policy, shared by the team, learned by PPO.

Residual policy learning (Johannink et al., ICRA 2019; Silver et al., arXiv 1812.06298):
each step the Voronoi baseline (:mod:`mpc_hunt.control.voronoi`) gives every defender a
base velocity b_i; every ``decision_steps`` steps each active defender reads its own
view of the hunt (:func:`team_view`: :func:`mpc_hunt.world.agent_view.defender_view`,
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

from mpc_hunt.control.controller import Command, Observation, attacker_velocity_estimate
from mpc_hunt.control.voronoi import VoronoiController
from mpc_hunt.world.agent_view import DEFENDER_VIEW, defender_view
from mpc_hunt.world.arena import arena_rows, safe_velocity
from mpc_hunt.world.geometry import saturate
from mpc_hunt.world.mlp import ShippedPolicy
from mpc_hunt.world.safety import safety_rows
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.separation import keep_separation

RESIDUAL = 0.5  # the largest correction, per component, as a share of the top speed
TEAM_VIEW = DEFENDER_VIEW + 2
TEAM_POLICY = ShippedPolicy(__package__, "ppo_team.npz", "defender", TEAM_VIEW)  # the team's network


def team_view(
    scenario: Scenario, i: int, p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, v_d: np.ndarray, base: np.ndarray
) -> np.ndarray:
    """Defender ``i``'s view: :func:`~mpc_hunt.world.agent_view.defender_view` and its base velocity, over the
    top speed."""
    top = float(scenario.defender_max_speeds.max())
    return np.concatenate([defender_view(scenario, i, p_a, v_a, p_d, v_d), base[i] / top])


def corrected(
    scenario: Scenario, p_d: np.ndarray, base: np.ndarray, corrections: np.ndarray, active: np.ndarray
) -> np.ndarray:
    """The team's velocities: each base velocity plus its correction (``RESIDUAL`` · v_d · a_i), :func:`shielded`."""
    top = float(scenario.defender_max_speeds.max())
    return shielded(scenario, p_d, base + RESIDUAL * top * np.asarray(corrections, dtype=float), active)


def shielded(scenario: Scenario, p_d: np.ndarray, wished: np.ndarray, active: np.ndarray) -> np.ndarray:
    """The team's ``wished`` velocities capped at each robot's speed, kept out of obstacles' R_safe and in the
    arena, then separated (the module's docstring), the separation filter keeping R_safe and the arena too (a
    projection onto a separation row alone could push a robot into an obstacle); a stopped robot's row is 0."""
    s, hunt = scenario, scenario.hunt
    speeds, T = s.defender_max_speeds, hunt.time_step
    v = np.zeros_like(p_d)
    for i in np.flatnonzero(active):
        v[i] = safe_velocity(s, p_d[i], saturate(wished[i], speeds[i]))

    def clear(i: int) -> list:
        rows = safety_rows(p_d[i], s.obstacle_centres, s.obstacle_radii, hunt.safety_distance, T)
        return [(a, min(b, 0.0)) for a, b in rows] + arena_rows(p_d[i], s.arena, T)

    return keep_separation(p_d, v, active, p_d, T, speeds, hunt.min_separation, also=clear)


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
            self.corrections = np.array(
                [self.network.action(team_view(s, i, p_a, v_a, P, v_d, base.velocities)) for i in range(len(P))]
            )
            self.held = self.network.decision_steps
        self.held -= 1
        self.last = P.copy()
        velocities = corrected(s, P, base.velocities, self.corrections, obs.active)
        return Command(velocities, base.capture_stage, base.intercepts)

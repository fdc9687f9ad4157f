"""``ppo``: an evader whose velocity is a neural policy trained by PPO against the recommended controller.

With no defender sensed (within its sensing radius) it follows its intent, as every
behaviour does (:func:`mpc_hunt.world.behaviours.base.undisturbed`; the reachable and
comfortable labels hold for it too). With defenders sensed it reads its view of the
hunt (:func:`mpc_hunt.world.agent_view.attacker_view`: the sensed defenders and their
velocities over the last step, the obstacles, the arena's edges) and its network
(:mod:`mpc_hunt.world.mlp`, evaluated in NumPy) gives an action a in [−1, 1]²; it
moves at v_a · a, capped at v_a and kept out of every obstacle, for
``decision_steps`` steps of the world, or until it senses nobody; the first step it
senses someone again is a new decision. The network is trained with Stable-Baselines3's PPO on
:class:`~mpc_hunt.envs.AttackerEnv` (``python studies/train_ppo.py``, docs/envs.md)
and shipped as ``ppo_attacker.npz`` beside this module.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.world.agent_view import ATTACKER_VIEW, attacker_view
from mpc_hunt.world.behaviours.base import attacker_move, sensed, undisturbed
from mpc_hunt.world.mlp import Mlp, ShippedPolicy
from mpc_hunt.world.packed import sensing_radius

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario

ATTACKER_POLICY = ShippedPolicy(__package__, "ppo_attacker.npz", "attacker", ATTACKER_VIEW)  # the attacker's network


class PpoAttacker:
    """Along the trained network's action while defenders are sensed (the module's docstring)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator, policy: Mlp | None = None):
        self.scenario = scenario
        self.radius = sensing_radius(scenario)
        self.policy = ATTACKER_POLICY.network() if policy is None else policy
        self.held, self.action = 0, np.zeros(2)
        self.last: np.ndarray | None = None

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        p_a, p_d = np.asarray(p_a, dtype=float), np.asarray(p_d, dtype=float).reshape(-1, 2)
        v_d = np.zeros_like(p_d) if self.last is None else (p_d - self.last) / self.scenario.hunt.time_step
        self.last = p_d.copy()
        if not len(sensed(p_a, p_d, self.radius)):
            self.held = 0
            return undisturbed(self.scenario, p_a)
        if self.held == 0:
            self.action = self.policy.action(attacker_view(self.scenario, p_a, p_d, v_d, self.radius))
            self.held = self.policy.decision_steps
        self.held -= 1
        return attacker_move(self.scenario, p_a, self.scenario.attacker.max_speed * self.action)

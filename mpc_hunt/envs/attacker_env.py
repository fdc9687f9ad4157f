"""The attacker as a Gymnasium agent, against a controller of the project (by default the recommended one).

Action: the attacker's velocity (m/s), a Box of ± the fastest attacker the hunts
hold, checked by :mod:`mpc_hunt.envs.actions`; the world caps its length at the
hunt's v_a and keeps it out of every obstacle. Observation: :mod:`mpc_hunt.envs.observation`.
Reward: the attacker's (:mod:`mpc_hunt.envs.episode`). The defenders' controller,
a name with its options or a :class:`~mpc_hunt.control.spec.ControllerSpec`, is
checked once when the environment is built (:func:`mpc_hunt.envs.policies.controller_spec`)
and built anew at every reset on the defenders' ``belief`` (never the attacker's law).
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from mpc_hunt.control.recommended import RECOMMENDED_CONTROLLER
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.envs.base import HuntEnv
from mpc_hunt.envs.hunts import Hunts
from mpc_hunt.envs.policies import controller_spec
from mpc_hunt.sweep.random_scenario import ScenarioRanges
from mpc_hunt.world.belief import Belief
from mpc_hunt.world.scenario import Scenario


class AttackerEnv(HuntEnv):
    """The attacker learns; the defenders run ``controller``: a name with ``controller_options`` (the spec's fields
    and options, :meth:`ControllerSpec.of`: the recommended stage for a field not given), or a spec."""

    def __init__(
        self,
        scenario: Scenario | None = None,
        ranges: ScenarioRanges | None = None,
        defenders: int | None = None,
        controller: str | ControllerSpec = RECOMMENDED_CONTROLLER,
        controller_options: dict | None = None,
        belief: Belief = Belief(),
        render_mode: str | None = None,
    ):
        super().__init__(Hunts(scenario, ranges, defenders), render_mode)
        speed = self.hunts.attacker_speed
        self.action_space = spaces.Box(-speed, speed, shape=(2,), dtype=np.float64)
        self.belief = belief
        self.controller_spec = controller_spec(
            controller, controller_options, "controller_options", self.hunts.probe(), belief
        )  # a bad name or option fails here, once
        self.controller = None

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        other = self.new_episode(seed, options)
        self.controller = self.controller_spec.build(self.scenario, belief=self.belief, rng=other)
        return self.current.observation(), self.info()

    def step(self, action):
        e, action = self.started(), self.checked(action)  # both before the controller moves
        command = self.controller.command(e.controller_observation())
        outcome = e.step(command.velocities, e.attacker_move(action))
        return e.observation(), outcome.reward, outcome.terminated, outcome.truncated, self.info()

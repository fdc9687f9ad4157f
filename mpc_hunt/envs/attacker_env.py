"""The attacker as a Gymnasium agent, against a controller of the project (by default the recommended one).

Action: the attacker's velocity (m/s), a Box of ± the fastest attacker the hunts
hold, checked by :mod:`mpc_hunt.envs.actions`; the world caps its length at the
hunt's v_a and keeps it out of every obstacle. Observation: :mod:`mpc_hunt.envs.observation`.
Reward: the attacker's (:mod:`mpc_hunt.envs.episode`). The defenders' controller
is built anew at every reset by :func:`mpc_hunt.control.controllers.make_controller`
on the defenders' ``belief`` (never the attacker's law); its name and options are
checked once when the environment is built
(:func:`mpc_hunt.control.controllers.checked_controller`).
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from mpc_hunt.control.controllers import checked_controller, make_controller
from mpc_hunt.control.recommended import RECOMMENDED_CONTROLLER, solver_settings
from mpc_hunt.envs.base import HuntEnv
from mpc_hunt.envs.hunts import Hunts
from mpc_hunt.errors import OptionError
from mpc_hunt.sweep.random_scenario import ScenarioRanges
from mpc_hunt.world.belief import Belief
from mpc_hunt.world.scenario import Scenario


class AttackerEnv(HuntEnv):
    """The attacker learns; the defenders run ``controller`` (with ``controller_options``; the recommended
    solver settings for a controller that solves a capture problem, when none are given)."""

    def __init__(self, scenario: Scenario | None = None, ranges: ScenarioRanges | None = None,
                 defenders: int | None = None, controller: str = RECOMMENDED_CONTROLLER,
                 controller_options: dict | None = None, belief: Belief = Belief(), render_mode: str | None = None):
        super().__init__(Hunts(scenario, ranges, defenders), render_mode)
        speed = self.hunts.attacker_speed
        self.action_space = spaces.Box(-speed, speed, shape=(2,), dtype=np.float64)
        if controller_options is not None and not isinstance(controller_options, dict):
            raise OptionError(f"controller_options: a dict of the controller's options or None, got "
                              f"{type(controller_options).__name__}")
        self.controller_name, self.belief = controller, belief
        self.controller_options = solver_settings(controller) if controller_options is None \
            else dict(controller_options)
        checked_controller(controller, self.hunts.probe(), argument="controller_options", belief=belief,
                           **self.controller_options)                   # a bad name or option fails here, once
        self.controller = None

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        other = self.new_episode(seed, options)
        self.controller = make_controller(self.controller_name, self.scenario, belief=self.belief, rng=other,
                                          **self.controller_options)
        return self.episode.observation(), self.info()

    def step(self, action):
        e, action = self.started(), self.checked(action)        # both before the controller moves
        command = self.controller.command(e.controller_observation())
        outcome = e.step(command.velocities, e.attacker_move(action))
        return e.observation(), outcome.reward, outcome.terminated, outcome.truncated, self.info()

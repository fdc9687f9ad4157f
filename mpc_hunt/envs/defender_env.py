"""The defending team as one Gymnasium agent, against an attacker behaviour of the world (by default its scenario's).

Action: every defender's velocity (m/s), a Box of shape (defenders, 2) within ± the
fastest defender's speed, checked by :mod:`mpc_hunt.envs.actions` (exactly that
shape); the world caps each at its robot's max speed (Eq. 1).
Observation: :mod:`mpc_hunt.envs.observation`. Reward: the defenders' (the
negative of :mod:`mpc_hunt.envs.episode`'s). The attacker moves by ``attacker``
(a behaviour's name; None keeps each hunt's own, the paper's for a random hunt),
its randomness drawn from the reset's seed.
"""

from __future__ import annotations

from typing import cast

import numpy as np
from gymnasium import spaces

from mpc_hunt.envs.base import HuntEnv
from mpc_hunt.envs.hunts import Hunts
from mpc_hunt.errors import UnknownNameError
from mpc_hunt.sweep.random_scenario import ScenarioRanges
from mpc_hunt.world.behaviours import BEHAVIOURS, make_behaviour, with_behaviour
from mpc_hunt.world.behaviours.base import Behaviour
from mpc_hunt.world.scenario import Scenario


class DefenderEnv(HuntEnv):
    """The team learns; the attacker follows ``attacker`` (the module's docstring)."""

    def __init__(
        self,
        scenario: Scenario | None = None,
        ranges: ScenarioRanges | None = None,
        defenders: int | None = None,
        attacker: str | None = None,
        render_mode: str | None = None,
    ):
        super().__init__(Hunts(scenario, ranges, defenders), render_mode)
        speed = self.hunts.defender_speed
        self.action_space = spaces.Box(-speed, speed, shape=(self.hunts.team, 2), dtype=np.float64)
        if attacker is not None and (not isinstance(attacker, str) or attacker not in BEHAVIOURS):
            raise UnknownNameError(f"attacker: unknown behaviour {attacker!r} (available: {', '.join(BEHAVIOURS)})")
        self.attacker_name = attacker
        self.behaviour: Behaviour | None = None

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        other = self.new_episode(seed, options)
        scenario = self.scenario if self.attacker_name is None else with_behaviour(self.scenario, self.attacker_name)
        self.behaviour = make_behaviour(scenario, other)
        return self.current.observation(), self.info()

    def step(self, action):
        e, action = self.started(), self.checked(action)  # both before the attacker's behaviour draws
        behaviour = cast(Behaviour, self.behaviour)  # the reset's, as started() checked
        outcome = e.step(action, behaviour.velocity(e.attacker, e.defenders))
        return e.observation(), -outcome.reward, outcome.terminated, outcome.truncated, self.info()

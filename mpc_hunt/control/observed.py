"""The attacker's velocity as the defenders see it: the mean of its last observed steps, capped at its top speed."""

from __future__ import annotations

from collections import deque

import numpy as np

from mpc_hunt.control.controller import Observation
from mpc_hunt.world.geometry import saturate
from mpc_hunt.world.scenario import Scenario

VELOCITY_WINDOW = 5  # observed steps averaged into the attacker's velocity


class ObservedVelocity:
    """Fed every observation of a hunt in turn; ``update`` returns the attacker's mean velocity over the last
    ``VELOCITY_WINDOW`` observed steps, capped at v_a (zero before it has moved once)."""

    def __init__(self, scenario: Scenario):
        self.time_step = scenario.hunt.time_step
        self.max_speed = scenario.attacker.max_speed
        self._seen: deque = deque(maxlen=VELOCITY_WINDOW + 1)

    def update(self, obs: Observation) -> np.ndarray:
        if obs.previous_attacker is not None and not self._seen:
            self._seen.append(np.array(obs.previous_attacker, dtype=float))
        self._seen.append(np.array(obs.attacker, dtype=float))
        if len(self._seen) < 2:
            return np.zeros(2)
        mean = (self._seen[-1] - self._seen[0]) / (self.time_step * (len(self._seen) - 1))
        return saturate(mean, self.max_speed)

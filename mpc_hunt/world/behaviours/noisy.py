"""``noisy``: the paper's attacker plus a bounded random disturbance.

Each step, a velocity drawn uniformly from the disc of radius ``disturbance``
× v_a (the scenario's ``disturbance``, else ``DEFAULT_DISTURBANCE``) by the
passed-in random generator is added to the resultant of Eq. 2 before the cap at
v_a: the model the defenders hold, with a push they cannot predict.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.world import attacker
from mpc_hunt.world.behaviours.base import keep_out
from mpc_hunt.world.geometry import saturate

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario

DEFAULT_DISTURBANCE = 1.0  # of v_a: the disturbance's largest size unless the scenario gives one


class NoisyAttacker:
    """Eq. 2's resultant plus a disturbance of at most ``disturbance`` × v_a, capped at v_a."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator):
        self.scenario = scenario
        self.rng = rng
        given = scenario.attacker.disturbance
        self.size = (DEFAULT_DISTURBANCE if given is None else given) * scenario.attacker.max_speed

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        angle = self.rng.uniform(0.0, 2 * math.pi)
        length = self.size * math.sqrt(self.rng.uniform())
        push = length * np.array([math.cos(angle), math.sin(angle)])
        v = saturate(attacker.resultant(self.scenario, p_a, p_d) + push, self.scenario.attacker.max_speed)
        return keep_out(self.scenario, p_a, v)

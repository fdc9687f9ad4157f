"""``apf``: the paper's attacker (Eqs. 2 and 9), the default; it senses the defenders within R_agg."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.world import attacker
from mpc_hunt.world.behaviours.base import keep_out

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario


class ApfAttacker:
    """Its nominal intent plus the defenders' and obstacles' fields, capped at v_a (Eq. 2)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator):
        self.scenario = scenario

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        return keep_out(self.scenario, p_a, attacker.velocity(self.scenario, p_a, p_d))

"""``apf``: the paper's attacker (Eqs. 2 and 9), the default; it senses the defenders within R_agg."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.attacker import velocity_of
from mpc_hunt.world.behaviours.base import kept_out

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario


@kernel
def apf_velocity(p_a: np.ndarray, p_d: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """Its nominal intent plus the defenders' and obstacles' fields, capped at v_a (Eq. 2), kept out of every
    obstacle."""
    vx, vy = velocity_of(p_a, p_d, centres, radii, prm)
    return kept_out(p_a, vx, vy, centres, radii, prm)


class ApfAttacker:
    """Its nominal intent plus the defenders' and obstacles' fields, capped at v_a (Eq. 2)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator):
        self.scenario = scenario

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        s = self.scenario
        p_a, p_d = np.asarray(p_a, dtype=float), np.asarray(p_d, dtype=float).reshape(-1, 2)
        return np.array(apf_velocity(p_a, p_d, s.obstacle_centres, s.obstacle_radii, s.packed))

"""``apf``: the paper's attacker (Eqs. 2 and 9), the default; it senses the defenders within R_agg."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.attacker import velocity_of
from mpc_hunt.world.behaviours.base import CompiledBehaviour, kept_out

if TYPE_CHECKING:
    pass


@kernel
def apf_velocity(p_a: np.ndarray, p_d: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """Its nominal intent plus the defenders' and obstacles' fields, capped at v_a (Eq. 2), kept out of every
    obstacle."""
    vx, vy = velocity_of(p_a, p_d, centres, radii, prm)
    return kept_out(p_a, vx, vy, centres, radii, prm)


class ApfAttacker(CompiledBehaviour):
    """Its nominal intent plus the defenders' and obstacles' fields, capped at v_a (Eq. 2)."""

    rule = staticmethod(apf_velocity)

"""``noisy``: the paper's attacker plus a bounded random disturbance.

Each step, a velocity drawn uniformly from the disc of radius ``disturbance``
× v_a (the scenario's ``disturbance``, else
:data:`~mpc_hunt.world.packed.DEFAULT_DISTURBANCE`) by the
passed-in random generator is added to the resultant of Eq. 2 before the cap at
v_a: the model the defenders hold, with a push they cannot predict. The draws are the hunt's own (:func:`draw`),
so a hunt moves the same alone or in a batch.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.attacker import resultant_of
from mpc_hunt.world.behaviours.base import CompiledBehaviour, kept_out
from mpc_hunt.world.geometry import capped
from mpc_hunt.world.packed import DISTURBANCE, V_A

if TYPE_CHECKING:
    pass


def draw(rng: np.random.Generator) -> tuple[float, float]:
    """One step's draws: (the push's bearing in [0, 2π), the square root of a uniform draw, its length's share)."""
    return rng.uniform(0.0, 2 * math.pi), math.sqrt(rng.uniform())


@kernel
def noisy_velocity(
    p_a: np.ndarray,
    p_d: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    prm: np.ndarray,
    angle: float,
    share: float,
):
    """Eq. 2's resultant plus the push of length ``share`` × the disturbance along ``angle``, capped at v_a."""
    size = prm[DISTURBANCE] * share
    x, y = resultant_of(p_a, p_d, centres, radii, prm)
    vx, vy = capped(x + size * math.cos(angle), y + size * math.sin(angle), prm[V_A])
    return kept_out(p_a, vx, vy, centres, radii, prm)


class NoisyAttacker(CompiledBehaviour):
    """Eq. 2's resultant plus a disturbance of at most ``disturbance`` × v_a, capped at v_a."""

    rule = staticmethod(noisy_velocity)

    def extra(self) -> tuple:
        """This step's draws from the hunt's generator (:func:`draw`)."""
        return draw(self.rng)

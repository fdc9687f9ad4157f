"""The paper's attacker: what it perceives and how it moves (Eqs. 2 and 9).

The world moves the attacker by its scenario's behaviour
(:mod:`mpc_hunt.world.behaviours`; ``apf``, the default, is these rules); the
defenders predict it with these rules applied to their belief
(:mod:`mpc_hunt.world.belief`), which may differ from the world in every
parameter and in the behaviour itself.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.field import nominal_intent, obstacle_push, pushes
from mpc_hunt.world.geometry import capped, norm
from mpc_hunt.world.packed import ETA, K_D, K_O, NOMINAL_X, NOMINAL_Y, PROTECTIVE, R_AGG, V_A

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario


def perceives(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """Defenders within R_agg: the attacker reacts to them, and they are in the capture stage."""
    return norm(np.asarray(p_a, dtype=float) - np.asarray(p_d, dtype=float)) < scenario.attacker.perception_radius


def nominal_velocity(scenario: Scenario) -> np.ndarray:
    """The attacker's nominal intent, capped at its max speed (docs/model.md, E6)."""
    a = scenario.attacker
    return nominal_intent(np.array(a.nominal_velocity), a.max_speed)


@kernel
def resultant_of(p_a: np.ndarray, p_d: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """The resultant on the attacker (Eq. 9 plus its nominal intent), the parameters ``prm``
    (:mod:`mpc_hunt.world.packed`): u = v_nom + k_d Σ_i H(p_a − p_di) + k_o Σ_o H(r_ao)."""
    dx, dy = pushes(p_a, p_d, prm[R_AGG], prm[ETA])
    ox, oy = obstacle_push(p_a, centres, radii, prm[PROTECTIVE], prm[ETA])
    return prm[NOMINAL_X] + prm[K_D] * dx + prm[K_O] * ox, prm[NOMINAL_Y] + prm[K_D] * dy + prm[K_O] * oy


@kernel
def velocity_of(p_a: np.ndarray, p_d: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray):
    """Eq. 2: the resultant, capped at the attacker's max speed."""
    x, y = resultant_of(p_a, p_d, centres, radii, prm)
    return capped(x, y, prm[V_A])


def resultant(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """The resultant on the attacker (Eq. 9 plus its nominal intent) for defenders at ``p_d``."""
    a, d, c, r = _arrays(scenario, p_a, p_d)
    return np.array(resultant_of(a, d, c, r, scenario.packed))


def velocity(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """Eq. 2: the resultant, capped at the attacker's max speed."""
    a, d, c, r = _arrays(scenario, p_a, p_d)
    return np.array(velocity_of(a, d, c, r, scenario.packed))


def _arrays(scenario: Scenario, p_a, p_d) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    p_d = np.asarray(p_d, dtype=float).reshape(-1, 2)
    return np.asarray(p_a, dtype=float), p_d, scenario.obstacle_centres, scenario.obstacle_radii

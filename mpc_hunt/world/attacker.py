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

from mpc_hunt.world.field import attacker_resultant, nominal_intent
from mpc_hunt.world.geometry import norm, saturate

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario


def perceives(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """Defenders within R_agg: the attacker reacts to them, and they are in the capture stage."""
    return norm(np.asarray(p_a, dtype=float) - np.asarray(p_d, dtype=float)) < scenario.attacker.perception_radius


def nominal_velocity(scenario: Scenario) -> np.ndarray:
    """The attacker's nominal intent, capped at its max speed (docs/model.md, E6)."""
    a = scenario.attacker
    return nominal_intent(np.array(a.nominal_velocity), a.max_speed)


def resultant(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """The resultant on the attacker (Eq. 9 plus its nominal intent) for defenders at ``p_d``."""
    a, hunt = scenario.attacker, scenario.hunt
    return attacker_resultant(
        p_a,
        p_d,
        scenario.obstacle_centres,
        scenario.obstacle_radii,
        nominal=nominal_velocity(scenario),
        perception_radius=a.perception_radius,
        protective_distance=hunt.protective_distance,
        eta=hunt.eta,
        k_d=hunt.k_d,
        k_o=hunt.k_o,
    )


def velocity(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """Eq. 2: the resultant, capped at the attacker's max speed."""
    return saturate(resultant(scenario, p_a, p_d), scenario.attacker.max_speed)

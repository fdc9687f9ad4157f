"""The attacker of a scenario: what it perceives and how it moves (Eqs. 2 and 9).

One place for the rules that the world (the simulator) and the defenders'
model of it (the capture problem, the strategy) share.
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.world.field import attacker_resultant, nominal_intent
from mpc_hunt.world.geometry import norm, saturate
from mpc_hunt.world.scenario import Scenario


def perceives(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """Defenders within R_agg: the attacker reacts to them, and they are in the capture stage."""
    return norm(np.asarray(p_a, dtype=float) - np.asarray(p_d, dtype=float)) < scenario.attacker.perception_radius


def nominal_velocity(scenario: Scenario) -> np.ndarray:
    """The attacker's nominal intent, capped at its max speed (NOTES E6)."""
    a = scenario.attacker
    return nominal_intent(np.array(a.nominal_velocity), a.max_speed)


def resultant(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """The resultant on the attacker (Eq. 9 plus its nominal intent) for defenders at ``p_d``."""
    a, hunt = scenario.attacker, scenario.hunt
    return attacker_resultant(p_a, p_d, scenario.obstacle_centres, scenario.obstacle_radii,
                              nominal=nominal_velocity(scenario), perception_radius=a.perception_radius,
                              protective_distance=hunt.protective_distance, eta=hunt.eta,
                              k_d=hunt.k_d, k_o=hunt.k_o)


def velocity(scenario: Scenario, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
    """Eq. 2: the resultant, capped at the attacker's max speed."""
    return saturate(resultant(scenario, p_a, p_d), scenario.attacker.max_speed)

"""The approaching stage (Eq. 6): head for the intercept point, avoid obstacles.

u_di = ω (p'_di − p_di) + (1 − ω) [Σ_o H(r_io) + Σ_j≠i H(p_di − p_dj)], capped at
the defender's speed. The paper's H here is "the defender response to the
obstacles or the defender": obstacles act over ``protective_distance`` from
their surface, other defenders over twice ``min_separation``, so an approaching
defender turns away before it breaks the separation the capture stage keeps.
The printed ω(p_di − p'_di) would drive the defender away from the intercept
(docs/model.md, E3). With prediction off, or when no intercept exists (docs/model.md, E8),
p'_di is the attacker's current position (pure pursuit).
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.world.field import obstacle_repulsion, repulsion
from mpc_hunt.world.geometry import saturate
from mpc_hunt.world.prediction import intercept_point
from mpc_hunt.world.scenario import Scenario


def approach_target(p_a: np.ndarray, v_a: np.ndarray, p_d: np.ndarray, speed: float, prediction: bool) -> np.ndarray:
    """p'_di: the predicted intercept, or the attacker's position without prediction."""
    if prediction:
        point = intercept_point(p_a, v_a, p_d, speed)
        if point is not None:
            return point
    return np.asarray(p_a, dtype=float)


def approach_velocity(
    scenario: Scenario, p_d: np.ndarray, target: np.ndarray, speed: float, others: np.ndarray
) -> np.ndarray:
    """Eq. 6 with the sign of docs/model.md, E3, capped at ``speed``; ``others`` are the other defenders."""
    hunt = scenario.hunt
    avoid = obstacle_repulsion(
        p_d, scenario.obstacle_centres, scenario.obstacle_radii, hunt.protective_distance, hunt.eta
    )
    avoid = avoid + repulsion(
        p_d - np.asarray(others, dtype=float).reshape(-1, 2), 2.0 * hunt.min_separation, hunt.eta
    ).sum(axis=0)
    u = hunt.omega * (np.asarray(target, dtype=float) - p_d) + (1.0 - hunt.omega) * avoid
    return saturate(u, speed)

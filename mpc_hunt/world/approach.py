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

from mpc_hunt.compiled import kernel
from mpc_hunt.world.field import obstacle_push, push
from mpc_hunt.world.geometry import capped
from mpc_hunt.world.packed import ETA, MIN_SEPARATION, OMEGA, PROTECTIVE
from mpc_hunt.world.scenario import Scenario


@kernel
def approach_of(p_d, i, tx, ty, speed, centres, radii, prm):
    """Eq. 6 for defender ``i`` of ``p_d`` (the others repel it) towards (tx, ty), with the sign of docs/model.md,
    E3, capped at ``speed``; the parameters ``prm`` (:mod:`mpc_hunt.world.packed`)."""
    p = p_d[i]
    ax, ay = obstacle_push(p, centres, radii, prm[PROTECTIVE], prm[ETA])
    dx = dy = 0.0
    for j in range(p_d.shape[0]):
        if j != i:
            hx, hy = push(p[0] - p_d[j, 0], p[1] - p_d[j, 1], 2.0 * prm[MIN_SEPARATION], prm[ETA])
            dx += hx
            dy += hy
    ax, ay = ax + dx, ay + dy
    w = prm[OMEGA]
    return capped(w * (tx - p[0]) + (1.0 - w) * ax, w * (ty - p[1]) + (1.0 - w) * ay, speed)


def approach_velocity(
    scenario: Scenario, p_d: np.ndarray, target: np.ndarray, speed: float, others: np.ndarray
) -> np.ndarray:
    """Eq. 6 with the sign of docs/model.md, E3, capped at ``speed``; ``others`` are the other defenders."""
    s = scenario
    team = np.vstack([np.asarray(p_d, dtype=float).reshape(1, 2), np.asarray(others, dtype=float).reshape(-1, 2)])
    tx, ty = np.asarray(target, dtype=float)
    return np.array(approach_of(team, 0, tx, ty, float(speed), s.obstacle_centres, s.obstacle_radii, s.packed))

"""A scenario as the numbers its compiled rules read: one float vector, each parameter at a named index.

The compiled rules (:mod:`mpc_hunt.compiled`) take a hunt's arrays (positions, obstacle centres and radii) and
this vector, ``prm``; a batch of hunts stacks one row per hunt (:mod:`mpc_hunt.sim.batch`). The defaults an
attacker behaviour falls back on (its sensing radius, the ``noisy`` attacker's disturbance) are resolved here,
once, so a rule never sees a missing value.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.world.field import nominal_intent

if TYPE_CHECKING:
    from mpc_hunt.world.scenario import Scenario

DEFAULT_SENSING = 3.0  # m: an evader's sensing radius unless its scenario gives one (docs/model.md)
DEFAULT_DISTURBANCE = 1.0  # of v_a: the noisy attacker's largest disturbance unless the scenario gives one

(
    T,  # the time step (s)
    HUNT_RADIUS,  # R_hunt (Eq. 5)
    CENTRE_TOLERANCE,  # Eq. 4's tolerance
    ETA,  # η (Eq. 2)
    K_D,  # k_d (Eq. 9)
    K_O,  # k_o (Eq. 9)
    OMEGA,  # ω (Eq. 6)
    PROTECTIVE,  # an obstacle's field range, from its surface
    SAFETY,  # R_safe (Eq. 15)
    MIN_SEPARATION,  # the defenders' least separation
    LEAST_DISTANCE,  # the capture problem's least defender–attacker distance
    V_A,  # the attacker's max speed
    R_AGG,  # the attacker's perception radius
    SENSING,  # how far an evader senses defenders
    DISTURBANCE,  # the noisy attacker's largest disturbance (m/s)
    NOMINAL_X,  # the attacker's nominal intent, capped at v_a (docs/model.md, E6)
    NOMINAL_Y,
    HAS_ARENA,  # 1.0 when the scenario has an arena, else 0.0 (and the four edges are ±inf)
    X_MIN,
    Y_MIN,
    X_MAX,
    Y_MAX,
) = range(22)
SIZE = 22


def sensing_radius(scenario: Scenario) -> float:
    """How far the attacker senses defenders: the scenario's ``sensing_radius``, else ``DEFAULT_SENSING``."""
    given = scenario.attacker.sensing_radius
    return DEFAULT_SENSING if given is None else given


def parameters(scenario: Scenario) -> np.ndarray:
    """``prm``, the vector of the module's docstring, of ``scenario``."""
    h, a = scenario.hunt, scenario.attacker
    prm = np.empty(SIZE)
    prm[T], prm[HUNT_RADIUS], prm[CENTRE_TOLERANCE] = h.time_step, h.hunt_radius, h.centre_tolerance
    prm[ETA], prm[K_D], prm[K_O], prm[OMEGA] = h.eta, h.k_d, h.k_o, h.omega
    prm[PROTECTIVE], prm[SAFETY], prm[MIN_SEPARATION] = h.protective_distance, h.safety_distance, h.min_separation
    prm[LEAST_DISTANCE] = h.min_attacker_distance
    prm[V_A], prm[R_AGG], prm[SENSING] = a.max_speed, a.perception_radius, sensing_radius(scenario)
    prm[DISTURBANCE] = (DEFAULT_DISTURBANCE if a.disturbance is None else a.disturbance) * a.max_speed
    prm[NOMINAL_X], prm[NOMINAL_Y] = nominal_intent(np.array(a.nominal_velocity), a.max_speed)
    arena = scenario.arena
    prm[HAS_ARENA] = arena is not None
    prm[X_MIN], prm[Y_MIN], prm[X_MAX], prm[Y_MAX] = (-np.inf, -np.inf, np.inf, np.inf) if arena is None else arena
    return prm

"""The capture-stage problem (Eqs. 12–15) at one state, over a horizon of N steps.

Decision: the positions of the *controlled* defenders (those in the capture
stage, |r_ai| < R_agg) at steps 1..N; the other defenders are held where they
are. The attacker's positions follow from its APF dynamics (Eq. 2) under the
planned defender positions. See docs/formulations.md for the mathematics.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mpc_hunt.errors import MpcHuntError
from mpc_hunt.world import attacker
from mpc_hunt.world.hunting_circle import desired_velocity, members
from mpc_hunt.world.scenario import Scenario


class ProblemError(MpcHuntError, ValueError):
    """A capture problem was given an impossible state (wrong shape, NaN, nobody to control)."""


# Steps (20 s at T = 0.1 s): the formulations' set-up grows with N, and no capture needs a longer look-ahead.
MAX_HORIZON = 200

@dataclass(frozen=True)
class CaptureWeights:
    """Weights of the objective's terms; fixed for every scenario (docs/formulations.md).

    force: Eq. 12, the force error per v_a,max; ring: the common distance drawn
    to R_hunt / 2, per R_hunt; move: step length per r_d (smoothness);
    equal_distance: the exact (L1) penalty on Eq. 14's slack, per R_hunt².
    """

    force: float = 1.0
    ring: float = 0.1
    move: float = 1e-3
    equal_distance: float = 1e3


@dataclass(frozen=True)
class CaptureProblem:
    """One capture-stage problem: the state, the horizon and everything the constraints need."""

    scenario: Scenario
    attacker_position: np.ndarray
    defender_positions: np.ndarray
    controlled: np.ndarray
    desired_velocity: np.ndarray
    horizon: int = 1
    weights: CaptureWeights = field(default_factory=CaptureWeights)

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        n = len(self.scenario.defenders)
        for name, shape in (("attacker_position", (2,)), ("defender_positions", (n, 2)),
                            ("desired_velocity", (2,))):
            value = np.array(getattr(self, name), dtype=float)
            if value.shape != shape:
                raise ProblemError(f"{name}: expected shape {shape}, got {value.shape}")
            if not np.all(np.isfinite(value)):
                raise ProblemError(f"{name}: must be finite, got {value.tolist()}")
            value.setflags(write=False)
            set_(self, name, value)
        controlled = np.array(self.controlled, dtype=bool).reshape(-1)
        if controlled.shape != (n,):
            raise ProblemError(f"controlled: expected {n} flags, got {controlled.shape[0]}")
        if not controlled.any():
            raise ProblemError("controlled: no defender is in the capture stage")
        controlled.setflags(write=False)
        set_(self, "controlled", controlled)
        if isinstance(self.horizon, bool) or not isinstance(self.horizon, (int, np.integer)) or \
                not 1 <= self.horizon <= MAX_HORIZON:
            raise ProblemError(f"horizon: must be a whole number from 1 to {MAX_HORIZON}, got {self.horizon!r}")
        set_(self, "horizon", int(self.horizon))

    @classmethod
    def at_state(cls, scenario: Scenario, attacker_position, defender_positions, horizon: int = 1,
                 weights: CaptureWeights | None = None, active=None) -> "CaptureProblem":
        """The problem the strategy poses at this state (controlled set and u'_a derived).

        ``active`` (default: every defender) marks the robots that can move; a
        failed one is held where it stands, like a defender in the approaching stage.
        """
        p_a = np.asarray(attacker_position, dtype=float)
        p_d = np.asarray(defender_positions, dtype=float)
        a, hunt = scenario.attacker, scenario.hunt
        controlled = attacker.perceives(scenario, p_a, p_d)
        if active is not None:
            controlled = controlled & np.asarray(active, dtype=bool)
        circle = members(p_a, p_d, scenario.obstacle_centres, scenario.obstacle_radii, a.perception_radius)
        u_des = desired_velocity(p_a, circle.centre, a.max_speed, hunt.hunt_radius)
        return cls(scenario, p_a, p_d, controlled, u_des, horizon, weights or CaptureWeights())

    # Derived quantities, named as in the paper.
    @property
    def time_step(self) -> float:
        return self.scenario.hunt.time_step

    @property
    def nominal_velocity(self) -> np.ndarray:
        return attacker.nominal_velocity(self.scenario)

    @property
    def step_limits(self) -> np.ndarray:
        """r_d of Eq. 13 for every defender: v_d,max · T."""
        return self.scenario.defender_max_speeds * self.time_step

    @property
    def ring_radius(self) -> float:
        """The radius the hunting circle contracts to: R_hunt / 2."""
        return 0.5 * self.scenario.hunt.hunt_radius

    @property
    def structure(self) -> tuple[int, int, int, int]:
        """What fixes a formulation's sizes: (controlled, held, obstacles, horizon)."""
        nc = int(self.controlled.sum())
        return (nc, len(self.controlled) - nc, len(self.scenario.obstacles), self.horizon)

    @property
    def signature(self) -> tuple:
        """The structure and which defenders are controlled: when two problems may share duals."""
        return self.structure + (tuple(int(i) for i in np.flatnonzero(self.controlled)),)

    def resultant(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        """The attacker's resultant (Eq. 9 plus its nominal intent) for defenders at ``p_d``."""
        return attacker.resultant(self.scenario, p_a, p_d)

    def attacker_step(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        """One Euler step of Eq. 2: p_a + T · sat(resultant, v_a,max)."""
        return np.asarray(p_a, dtype=float) + self.time_step * attacker.velocity(self.scenario, p_a, p_d)

    def held_plan(self) -> np.ndarray:
        """Every defender held where it is for the whole horizon: shape (N, n, 2)."""
        return np.repeat(self.defender_positions[None], self.horizon, axis=0)

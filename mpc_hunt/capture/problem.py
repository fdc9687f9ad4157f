"""The capture-stage problem (Eqs. 12–15) at one state, over a horizon of N steps.

Decision: the positions of the *controlled* defenders (those in the capture
stage, |r_ai| < R_agg) at steps 1..N; the other defenders are held where they
are. The attacker's positions follow from its APF dynamics (Eq. 2) under the
planned defender positions. See docs/formulations.md for the mathematics.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import cast

import numpy as np

from mpc_hunt.arguments import out_of_range, shown
from mpc_hunt.capture.structure import Structure
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.world import attacker
from mpc_hunt.world.hunting_circle import desired_velocity, members
from mpc_hunt.world.scenario import Scenario


class ProblemError(MpcHuntError, ValueError):
    """A capture problem was given an impossible state (wrong shape, NaN, nobody to control)."""


# Steps (20 s at T = 0.1 s): the formulations' set-up grows with N, and no capture needs a longer look-ahead.
MAX_HORIZON = 200


def horizon_error(horizon: object) -> str | None:
    """Why ``horizon`` is not a horizon, a whole number of steps from 1 to :data:`MAX_HORIZON`, or None: the one
    rule of a horizon's bounds (a problem's, a controller's, a command line's), in the words of every count's
    refusal (:func:`mpc_hunt.arguments.out_of_range`)."""
    if isinstance(horizon, bool) or not isinstance(horizon, (int, np.integer)):
        return (
            f"expected a whole number from 1 to {MAX_HORIZON}, got "
            f"{shown(horizon) if isinstance(horizon, str) else repr(horizon)}"
        )
    return out_of_range(int(horizon), 1, MAX_HORIZON)


def checked_horizon(horizon: object) -> int:
    """``horizon`` as an int, else a :class:`ProblemError` naming it (:func:`horizon_error`)."""
    why = horizon_error(horizon)
    if why:
        raise ProblemError(f"horizon: {why}")
    return int(cast(int, horizon))  # as checked


# What the capture stage minimises (docs/formulations.md): ``paper``, Eq. 12 as published (force error, ring,
# smoothness, Eq. 14's penalty); ``enclose``, a reference of places on the hunting circle tracked through the
# attacker's response (built by the controller, :mod:`mpc_hunt.control.enclosure`).
OBJECTIVES = ("paper", "enclose")


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
class EncloseWeights:
    """Weights of the ``enclose`` objective (docs/formulations.md); each step's slot weight is the reference's.

    attacker: the attacker's predicted position to the reference's;
    edge: the attacker's predicted position beyond the arena less ``edge_margin``; move: step length
    (smoothness); each per r̄_d, the controlled defenders' mean step. Eq. 14 is not part of it: the
    places on the circle decide the distances.
    """

    attacker: float = 10.0
    edge: float = 10.0
    edge_margin: float = 1.0
    move: float = 1e-3


@dataclass(frozen=True)
class Reference:
    """Where the ``enclose`` objective wants everybody at steps 1..N, and how much each step counts.

    defenders: (N, n, 2) a place for every defender (rows of defenders not controlled are ignored);
    attacker: (N, 2) where the attacker should be; slot_weight: (N,) the weight of step k's places.
    """

    defenders: np.ndarray
    attacker: np.ndarray
    slot_weight: np.ndarray


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
    objective: str = "paper"
    reference: Reference | None = None
    enclose_weights: EncloseWeights = field(default_factory=EncloseWeights)

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        n = len(self.scenario.defenders)
        for name, shape in (("attacker_position", (2,)), ("defender_positions", (n, 2)), ("desired_velocity", (2,))):
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
        set_(self, "horizon", checked_horizon(self.horizon))
        if self.objective not in OBJECTIVES:
            raise ProblemError(f"objective: unknown {self.objective!r} (available: {', '.join(OBJECTIVES)})")
        if self.objective == "enclose":
            set_(self, "reference", self._checked_reference(n))

    @property
    def enclose_reference(self) -> Reference:
        """The reference of an ``enclose`` problem (checked on construction); refused for another objective."""
        if self.reference is None:
            raise ProblemError(f"reference: the {self.objective} objective has none")
        return self.reference

    def _checked_reference(self, n: int) -> Reference:
        ref, N = self.reference, self.horizon
        if not isinstance(ref, Reference):
            raise ProblemError(
                "reference: the enclose objective needs a Reference (mpc_hunt.control.enclosure builds one)"
            )
        arrays = {}
        for name, shape in (("defenders", (N, n, 2)), ("attacker", (N, 2)), ("slot_weight", (N,))):
            value = np.array(getattr(ref, name), dtype=float)
            if value.shape != shape or not np.all(np.isfinite(value)):
                raise ProblemError(f"reference.{name}: expected finite values of shape {shape}, got {value.shape}")
            value.setflags(write=False)
            arrays[name] = value
        return Reference(**arrays)

    @classmethod
    def at_state(
        cls,
        scenario: Scenario,
        attacker_position,
        defender_positions,
        horizon: int = 1,
        weights: CaptureWeights | None = None,
        active=None,
        reference: Reference | None = None,
        enclose_weights: EncloseWeights | None = None,
    ) -> "CaptureProblem":
        """The problem the strategy poses at this state (controlled set and u'_a derived).

        ``active`` (default: every defender) marks the robots that can move; a
        failed one is held where it stands, like a defender in the approaching stage.
        With a ``reference`` the objective is ``enclose``, which plans every active
        defender and has no herding target (u'_a is zero); ``enclose_weights`` (default: ``EncloseWeights()``) its
        terms' weights.
        """
        p_a = np.asarray(attacker_position, dtype=float)
        p_d = np.asarray(defender_positions, dtype=float)
        a, hunt = scenario.attacker, scenario.hunt
        controlled = attacker.perceives(scenario, p_a, p_d) if reference is None else np.ones(len(p_d), bool)
        if active is not None:
            controlled = controlled & np.asarray(active, dtype=bool)
        u_des = np.zeros(2)
        if reference is None:
            circle = members(p_a, p_d, scenario.obstacle_centres, scenario.obstacle_radii, a.perception_radius)
            u_des = desired_velocity(p_a, circle.centre, a.max_speed, hunt.hunt_radius)
        return cls(
            scenario,
            p_a,
            p_d,
            controlled,
            u_des,
            horizon,
            weights or CaptureWeights(),
            "paper" if reference is None else "enclose",
            reference,
            enclose_weights or EncloseWeights(),
        )

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

    @cached_property
    def structure(self) -> Structure:
        """What fixes a formulation's sizes and expressions (:class:`~mpc_hunt.capture.structure.Structure`)."""
        nc = int(self.controlled.sum())
        return Structure(nc, len(self.controlled) - nc, len(self.scenario.obstacles), self.horizon, self.objective)

    @cached_property
    def signature(self) -> tuple:
        """The structure and which defenders are controlled: when two problems may share duals."""
        return self.structure, tuple(np.flatnonzero(self.controlled).tolist())

    def resultant(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        """The attacker's resultant (Eq. 9 plus its nominal intent) for defenders at ``p_d``."""
        return attacker.resultant(self.scenario, p_a, p_d)

    def attacker_step(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        """One Euler step of Eq. 2: p_a + T · sat(resultant, v_a,max)."""
        return np.asarray(p_a, dtype=float) + self.time_step * attacker.velocity(self.scenario, p_a, p_d)

    def held_plan(self) -> np.ndarray:
        """Every defender held where it is for the whole horizon: shape (N, n, 2)."""
        return np.repeat(self.defender_positions[None], self.horizon, axis=0)

    def plan_with(self, controlled: np.ndarray) -> np.ndarray:
        """Every defender's positions (N, n, 2): the controlled defenders' from ``controlled`` (N·n_c·2 numbers,
        step by step), the others held."""
        positions = np.asarray(controlled, dtype=float).reshape(self.horizon, self.structure.planned, 2)
        if not self.structure.fixed:  # every defender controlled
            return positions.copy()
        plan = self.held_plan()
        plan[:, self.controlled] = positions
        return plan

    def plan_from_x(self, x: np.ndarray) -> np.ndarray:
        """Every defender's positions (N, n, 2) from a decision vector that starts with the controlled
        defenders' positions (the rest, slacks and the like, is ignored)."""
        return self.plan_with(np.asarray(x, dtype=float)[: self.structure.plan_size])

    def x_from_plan(self, plan: np.ndarray) -> np.ndarray:
        """The controlled defenders' positions of a full plan, flat (inverse of :meth:`plan_with`)."""
        return np.asarray(plan, dtype=float)[:, self.controlled].reshape(-1)

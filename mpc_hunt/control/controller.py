"""What the simulator drives: a controller sees an observation and returns a command.

A controller never sees the world: only the defenders' shared knowledge at
time t (the UAV's broadcast in the paper's Fig. 2). It may keep memory between
steps (the plan it applied); a new hunt gets a new controller.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from mpc_hunt.capture.solution import Solution
from mpc_hunt.compiled import kernel


@dataclass(frozen=True)
class Observation:
    """What the defenders know at time t."""

    time: float
    attacker: np.ndarray
    previous_attacker: np.ndarray | None
    defenders: np.ndarray
    failed: np.ndarray | None = None  # (n,) bool: robots that have stopped for good (None: none)

    @property
    def active(self) -> np.ndarray:
        """The defenders that can still move."""
        return np.ones(len(self.defenders), dtype=bool) if self.failed is None else ~self.failed


@dataclass(frozen=True)
class Command:
    """The defenders' velocities for the next step, and why."""

    velocities: np.ndarray  # (n, 2)
    capture_stage: np.ndarray  # (n,) bool
    intercepts: np.ndarray  # (n, 2): approach targets p'_di (NaN where none)
    solution: Solution | None = None  # the capture-stage solve of this step, if any
    fallback: bool = False  # the command did not come from a successful solve


@runtime_checkable
class Controller(Protocol):
    """The defenders' controller: ``command`` each step; ``describe`` for reports."""

    def command(self, obs: Observation) -> Command: ...

    def describe(self) -> dict:
        """Plain data naming the controller and its settings (``controller`` key first)."""
        ...


def attacker_velocity_estimate(obs: Observation, time_step: float) -> np.ndarray:
    """Eq. 7's line of motion: the finite difference of the last two observed positions."""
    return estimated_velocity(np.asarray(obs.attacker, dtype=float), previous_of(obs), float(time_step))


@kernel
def estimated_velocity(p_a: np.ndarray, previous: np.ndarray, time_step: float) -> np.ndarray:
    """Eq. 7's line of motion from the attacker's position and its ``previous`` one (NaN before the first step:
    no estimate, zero)."""
    if not (math.isfinite(previous[0]) and math.isfinite(previous[1])):
        return np.zeros(2)
    return np.array([(p_a[0] - previous[0]) / time_step, (p_a[1] - previous[1]) / time_step])


def previous_of(obs: Observation) -> np.ndarray:
    """The attacker's last observed position as the compiled rules take it: NaN before the first step."""
    return np.full(2, np.nan) if obs.previous_attacker is None else np.asarray(obs.previous_attacker, dtype=float)


@runtime_checkable
class BatchRule(Protocol):
    """A batch's controllers of one kind as one compiled rule (:meth:`BatchedController.batched`)."""

    def commands(
        self,
        mine: np.ndarray,
        p_a: np.ndarray,
        previous: np.ndarray,
        p_d: np.ndarray,
        n: np.ndarray,
        failed: np.ndarray,
        velocities: np.ndarray,
        capture: np.ndarray,
        intercepts: np.ndarray,
    ) -> None:
        """Command every hunt b of ``mine`` from its observation, the batch's arrays: the attacker at ``p_a[b]``,
        last at ``previous[b]`` (NaN before the first step), the defenders ``p_d[b, :n[b]]``, ``failed[b]``
        those stopped for good; into ``velocities[b]``, ``capture[b]`` and ``intercepts[b]``."""
        ...


class BatchedController(Controller, Protocol):
    """A controller whose rule also commands a whole batch of hunts in one call (:mod:`mpc_hunt.sim.batch`)."""

    @staticmethod
    def batched(controllers: Sequence) -> BatchRule:
        """The rule of a batch's ``controllers`` of this kind (None where a hunt is commanded otherwise)."""
        ...

"""What a solving controller tracks: its reference, the half of the controller the capture stage does not own.

A solving controller is a reference × the capture stage solved over a receding
horizon (:class:`~mpc_hunt.control.strategy.HuntingStrategy`). A reference is
built from the defenders' believed scenario and the horizon; at each step it
says where each defender should be over the horizon (a
:class:`~mpc_hunt.capture.problem.Reference` of places, tracked by the
``enclose`` objective, every active defender in the capture stage), or nothing
for the paper's Eq. 12, whose capture stage holds the defenders within R_agg
(Eqs. 4–5) while the others approach by Eq. 6. A new solving controller is a
new reference (one file) and one line in :data:`mpc_hunt.control.controllers.CONTROLLERS`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np

from mpc_hunt.capture.problem import EncloseWeights, Reference
from mpc_hunt.control.controller import Observation
from mpc_hunt.world import attacker
from mpc_hunt.world.scenario import Scenario


class CaptureReference(Protocol):
    """The reference half of a solving controller (the module's docstring)."""

    NAME: str  # the controller's name (:data:`~mpc_hunt.control.controllers.CONTROLLERS`)
    SUMMARY: str  # one line: what the controller does (the CLI's help, the docs)
    OBJECTIVE: str  # the capture objective it poses: "paper" or "enclose"

    @property
    def weights(self) -> EncloseWeights | None:
        """The enclose objective's weights; None for the paper's."""

    def __init__(self, scenario: Scenario, horizon: int) -> None: ...

    def capture_stage(self, obs: Observation) -> np.ndarray:
        """Which defenders the capture stage plans now (the others approach by Eq. 6)."""

    def reference(self, obs: Observation) -> Reference | None:
        """Places for every defender and the attacker over steps 1..N, or None for Eq. 12."""


class PaperObjective:
    """The paper's capture stage, Eq. 12 as published: no places to track; the defenders within R_agg plan."""

    NAME, OBJECTIVE = "paper", "paper"
    SUMMARY = (
        "the paper's strategy: Eq. 6 towards the predicted intercept outside R_agg, the capture-stage "
        "optimisation (Eqs. 12-15) within it"
    )
    weights = None

    def __init__(self, scenario: Scenario, horizon: int):
        self.scenario = scenario

    def capture_stage(self, obs: Observation) -> np.ndarray:
        """The active defenders the attacker perceives, within R_agg (Eq. 9)."""
        return attacker.perceives(self.scenario, obs.attacker, obs.defenders) & obs.active

    def reference(self, obs: Observation) -> None:
        return None


class Places:
    """The base of a reference of places, tracked by the enclose objective with every active defender: a
    subclass sets ``NAME``, ``SUMMARY``, ``weights`` and builds :meth:`reference`.

    ``posed``, if given, returns at each step the scenario whose attacker the places predict (a controller whose
    model of the attacker changes: the adapt controller's current model); else it is ``scenario`` throughout.
    """

    OBJECTIVE = "enclose"

    def __init__(self, scenario: Scenario, horizon: int, posed: Callable[[], Scenario] | None = None):
        self._scenario, self._posed = scenario, posed
        self.horizon = horizon

    @property
    def scenario(self) -> Scenario:
        """The defenders' believed scenario the places are built on this step."""
        return self._scenario if self._posed is None else self._posed()

    def capture_stage(self, obs: Observation) -> np.ndarray:
        """Every active defender: nothing switches at R_agg."""
        return obs.active.copy()

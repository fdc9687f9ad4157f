"""The capture problem the strategy poses at a hunt's state (what ``mpc-hunt solve``, ``export`` and the
benchmarks' problem sets solve)."""

from __future__ import annotations

from mpc_hunt.capture.problem import OBJECTIVES, CaptureProblem
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.enclosure import Enclosure
from mpc_hunt.errors import UnknownNameError
from mpc_hunt.world.hunt_state import HuntState
from mpc_hunt.world.scenario import Scenario


def posed_problem(scenario: Scenario, state: HuntState, horizon: int = 1, objective: str = "paper") -> CaptureProblem:
    """The capture problem at ``state``: Eq. 12 as published (``paper``), or the enclose objective with the
    places the enclose controller would set on its first step from this state (``enclose``)."""
    active = ~scenario.failed(state.time)
    reference = None
    if objective == "enclose":
        observation = Observation(state.time, state.attacker, None, state.defenders, ~active)
        reference = Enclosure(scenario, horizon).reference(observation)
    elif objective not in OBJECTIVES:
        raise UnknownNameError(f"objective: unknown {objective!r} (available: {', '.join(OBJECTIVES)})")
    return CaptureProblem.at_state(
        scenario, state.attacker, state.defenders, horizon, active=active, reference=reference
    )

"""States at which a single capture-stage problem is posed (``mpc-hunt solve``).

The default is reproducible from the scenario alone: the first state of its
closed-loop run under the paper's strategy (one-step NLP, prediction on) at
which every defender is in the capture stage and the hunting circle has formed,
i.e. the defenders' distances to the attacker differ by at most 2 r_d (so
Eq. 14 can hold from the first step). A state can also be read from, and
written to, a JSON file (:mod:`mpc_hunt.world.hunt_state`).
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.control.controller import Observation
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.world import attacker
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.hunt_state import HuntState
from mpc_hunt.world.scenario import Scenario


def circle_formed(scenario: Scenario, obs: Observation) -> bool:
    """Every working defender within R_agg, their distances to the attacker within 2 r_d of each other."""
    active = obs.active
    if not active.any():
        return False
    d = norm(obs.attacker - obs.defenders[active])
    r_d = float(np.min(scenario.defender_max_speeds)) * scenario.hunt.time_step
    return bool(
        attacker.perceives(scenario, obs.attacker, obs.defenders[active]).all() and d.max() - d.min() <= 2 * r_d
    )


def first_formed_circle(scenario: Scenario, progress=None) -> HuntState:
    """The default state of ``mpc-hunt solve`` (see the module's docstring)."""
    found: list[Observation] = []

    def until(obs: Observation) -> bool:
        if circle_formed(scenario, obs):
            found.append(obs)
            return True
        return False

    simulate(scenario, until=until, progress=progress)
    if not found:
        raise MpcHuntError(f"scenario {scenario.name!r}: the hunting circle never formed in its closed-loop run")
    obs = found[0]
    return HuntState(obs.time, obs.attacker, obs.defenders)


def formed_circle_states(scenario: Scenario, count: int, progress=None) -> list[HuntState]:
    """``count`` consecutive states of the same closed-loop run, from the first with a formed circle.

    The states a capture-stage controller meets in turn (for warm-started
    benchmarks); fewer if the run stops first (capture or time limit).
    """
    found: list[Observation] = []

    def until(obs: Observation) -> bool:
        if found or circle_formed(scenario, obs):
            found.append(obs)
        return len(found) > count

    simulate(scenario, until=until, progress=progress)
    return [HuntState(obs.time, obs.attacker, obs.defenders) for obs in found[:count]]


# END

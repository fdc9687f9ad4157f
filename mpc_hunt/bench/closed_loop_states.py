"""Problem-set builder: capture-stage states of a closed-loop hunt, every k-th, in runs of consecutive states.

The hunt is the scenario's closed-loop run under the paper's strategy (one-step
NLP, prediction on), recorded once. A capture-stage state is one at which at
least one defender is within R_agg. Starting from the first, every
``every``-th capture-stage state starts a run of ``run_length`` consecutive
capture-stage states (one time step apart); a run of more than one state is
kept as a ``sequence`` for warm-started solving. Each problem is tagged
``closed-loop`` and with the families active at its one-step optimum
(:mod:`mpc_hunt.bench.activity`). The same run gives the scenario's default state.
"""

from __future__ import annotations

from mpc_hunt.bench.activity import ActivityProbe
from mpc_hunt.bench.capture_state import circle_formed
from mpc_hunt.bench.problem_set import ProblemEntry
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.control.controller import Observation
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.world import attacker
from mpc_hunt.world.hunt_state import HuntState
from mpc_hunt.world.scenario import Scenario


def capture_stage_observations(scenario: Scenario, progress=None) -> list[tuple[int, Observation]]:
    """(step, observation) of every capture-stage state of the scenario's closed-loop run, in order."""
    found: list[tuple[int, Observation]] = []
    T = scenario.hunt.time_step

    def record(obs: Observation) -> bool:
        if attacker.perceives(scenario, obs.attacker, obs.defenders).any():
            found.append((round(obs.time / T), obs))
        return False

    simulate(scenario, until=record, progress=progress)
    return found


def default_entry(scenario: Scenario, states: list[tuple[int, Observation]], probe: ActivityProbe) -> ProblemEntry:
    """The state ``mpc-hunt solve`` starts from, tagged ``default``: the first at which the hunting circle has
    formed (:func:`mpc_hunt.bench.capture_state.first_formed_circle`, found here in the recorded run)."""
    for _, obs in states:
        if circle_formed(scenario, obs):
            problem = CaptureProblem.at_state(scenario, obs.attacker, obs.defenders, 1, active=obs.active)
            return ProblemEntry(
                f"{scenario.name}/default",
                scenario.name,
                HuntState(obs.time, obs.attacker, obs.defenders),
                None,
                ("default",) + probe.tags(problem),
            )
    raise MpcHuntError(f"scenario {scenario.name!r}: the hunting circle never formed in its closed-loop run")


def closed_loop_entries(
    scenario: Scenario, states: list[tuple[int, Observation]], every: int, run_length: int, probe: ActivityProbe
) -> list[ProblemEntry]:
    """Every ``every``-th of the capture-stage ``states``, each starting a run of ``run_length``."""
    if every < 1:
        raise MpcHuntError(f"every: must be at least 1, got {every}")
    if not 1 <= run_length <= every:  # runs that overlapped would hold the same state twice
        raise MpcHuntError(f"run_length: must be from 1 to every ({every}), got {run_length}")
    entries = []
    for start in range(0, len(states), every):
        run = states[start : start + run_length]
        if len(run) < run_length or any(b[0] != a[0] + 1 for a, b in zip(run, run[1:])):
            continue  # the capture stage broke off (every defender left R_agg): no full run here
        sequence = f"{scenario.name}/run-{run[0][0]}" if run_length > 1 else None
        for step, obs in run:
            problem = CaptureProblem.at_state(scenario, obs.attacker, obs.defenders, 1, active=obs.active)
            entries.append(
                ProblemEntry(
                    f"{scenario.name}/step-{step}",
                    scenario.name,
                    HuntState(obs.time, obs.attacker, obs.defenders),
                    sequence,
                    ("closed-loop",) + probe.tags(problem),
                )
            )
    return entries

"""Assemble a problem set from the builders: default states, closed-loop runs and random states.

The one recipe behind the shipped set (``studies/default_problems.py``) and
``mpc-hunt problems --build``. Everything it draws comes from the generator
handed in, so the same arguments give the same file.
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.bench.activity import ActivityProbe
from mpc_hunt.bench.closed_loop_states import capture_stage_observations, closed_loop_entries, default_entry
from mpc_hunt.bench.problem_set import ProblemEntry, ProblemSet
from mpc_hunt.bench.random_states import random_entries
from mpc_hunt.errors import SettingError
from mpc_hunt.world.scenario import Scenario


def build_problem_set(
    scenarios: list[Scenario],
    rng: np.random.Generator,
    *,
    every: int,
    run_length: int,
    random_per_case: int,
    description: str,
    progress=None,
    sampled: set[str] | None = None,
) -> ProblemSet:
    """For each scenario its default state (tagged ``default``) and, if it is ``sampled`` (default: every
    scenario), its closed-loop runs, from one closed-loop run; then ``random_per_case`` random states per
    constraint family around the first scenario's robots. ``progress``, if given, is called with each run's
    simulated time."""
    if random_per_case and scenarios and len(scenarios[0].defenders) < 3:
        raise SettingError(
            "random_per_case",
            f"random states need at least 3 defenders; the first scenario, "
            f"{scenarios[0].name}, has {len(scenarios[0].defenders)}: give 0, or "
            "put another scenario first",
        )
    probe = ActivityProbe()
    named: dict[str, Scenario] = {}
    problems: list[ProblemEntry] = []
    for scenario in scenarios:
        named[scenario.name] = scenario
        states = capture_stage_observations(scenario, progress)
        problems.append(default_entry(scenario, states, probe))
        if sampled is None or scenario.name in sampled:
            problems += closed_loop_entries(scenario, states, every, run_length, probe)
    if random_per_case:
        extra, entries = random_entries(scenarios[0], random_per_case, rng, probe)
        named.update(extra)
        problems += entries
    return ProblemSet(named, tuple(problems), description)

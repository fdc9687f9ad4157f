"""Shared fixtures: a small capture problem with every constraint family in play."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mpc_hunt import Attacker, CaptureProblem, Defender, HuntParameters, Obstacle, Scenario


def small_scenario(obstacles=((6.0, 11.8, 0.3),), defenders: int = 3) -> Scenario:
    """Three defenders, one obstacle near the capture point (starts are irrelevant to the problem)."""
    starts = [(0.0, 0.0), (20.0, 0.0), (0.0, 20.0), (20.0, 20.0)][:defenders]
    return Scenario(
        name="small",
        defenders=tuple(Defender(start=s, max_speed=0.08) for s in starts),
        attacker=Attacker(start=(10.0, 10.0), nominal_velocity=(0.2, -0.2), max_speed=0.03,
                          perception_radius=1.0),
        obstacles=tuple(Obstacle(centre=(x, y), radius=r) for x, y, r in obstacles),
        hunt=HuntParameters(),
    )


ATTACKER = np.array([5.0, 11.0])
# On a circle of radius 0.7 around the attacker, 120° apart: a feasible start.
DEFENDERS = ATTACKER + 0.7 * np.array([[np.cos(a), np.sin(a)] for a in np.radians([-90.0, 30.0, 150.0])])


def capture_stage_scenario(seconds: float) -> Scenario:
    """The small scenario from the capture stage on (its defenders round the attacker as in DEFENDERS), ``seconds``
    long: a hunt whose every step solves the capture problem."""
    s = small_scenario()
    return dataclasses.replace(s, hunt=dataclasses.replace(s.hunt, time_limit=seconds),
                               attacker=dataclasses.replace(s.attacker, start=tuple(ATTACKER)),
                               defenders=tuple(dataclasses.replace(d, start=tuple(p))
                                               for d, p in zip(s.defenders, DEFENDERS)))


@pytest.fixture
def scenario() -> Scenario:
    return small_scenario()


def problem_at(scenario: Scenario, horizon: int, attacker=ATTACKER, defenders=DEFENDERS) -> CaptureProblem:
    return CaptureProblem.at_state(scenario, attacker, defenders, horizon)

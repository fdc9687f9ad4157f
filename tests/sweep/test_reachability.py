"""Unreachable hunts (mpc_hunt/sweep/reachability.py): lost whatever the defenders do."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mpc_hunt.control.controller import Command, Observation
from mpc_hunt.world.geometry import norm
from mpc_hunt.sweep.random_scenario import ScenarioRanges, sweep_scenario
from mpc_hunt.sweep.reachability import arrival_steps, comfortable, edge_race_lost, reachable, undisturbed_path
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario
from mpc_hunt.sim.simulator import simulate


class Pursuit:
    """Every defender straight at the attacker at full speed: the most any defender can close in."""

    def __init__(self, scenario: Scenario):
        self.speeds = scenario.defender_max_speeds

    def command(self, obs: Observation) -> Command:
        towards = obs.attacker - obs.defenders
        n = len(obs.defenders)
        velocities = towards / norm(towards)[:, None] * self.speeds[:, None]
        return Command(velocities, np.zeros(n, dtype=bool), np.full((n, 2), np.nan))

    def describe(self) -> dict:
        return {"controller": "pursuit"}


def _leaving(*starts: tuple[float, float], obstacles: tuple[Obstacle, ...] = ()) -> Scenario:
    """The attacker 2 m from the arena's right edge, heading out at 0.03 m/s: it leaves after 66.7 s."""
    return Scenario(name="leaving", defenders=tuple(Defender(start=s, max_speed=0.08) for s in starts),
                    attacker=Attacker(start=(18.0, 10.0), nominal_velocity=(0.03, 0.0), max_speed=0.03,
                                      perception_radius=1.0),
                    obstacles=obstacles, hunt=HuntParameters(), arena=(0.0, 0.0, 20.0, 20.0))


def test_the_undisturbed_path_ends_where_the_attacker_leaves():
    path = np.array(list(undisturbed_path(_leaving((1.0, 1.0), (1.0, 19.0), (2.0, 10.0)))))
    assert len(path) == 668 and path[-1][0] > 20.0 >= path[-2][0]
    np.testing.assert_allclose(path[:, 1], 10.0)


def test_a_defender_that_can_come_within_r_agg_in_time_makes_the_hunt_reachable():
    # The attacker leaves at (20.0, 10.0) after 66.7 s; a defender covers 5.34 m by then.
    far = [(1.0, 1.0), (1.0, 19.0)]
    assert not reachable(_leaving(*far, (13.0, 10.0)))        # 7 m − R_agg = 6 m: too far
    assert reachable(_leaving(*far, (14.5, 10.0)))            # 5.5 m − R_agg = 4.5 m: in time


def test_r_hunt_counts_when_it_exceeds_r_agg():
    scenario = _leaving((1.0, 1.0), (1.0, 19.0), (13.0, 10.0))
    wide = dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, hunt_radius=2.0))
    assert reachable(wide)                                     # 7 m − R_hunt = 5 m: in time


def test_comfortable_needs_three_defenders_in_time_with_twenty_seconds_to_spare():
    # The attacker leaves after 66.7 s: a comfortable defender meets its path (within R_agg) by 46.7 s.
    near = [(18.5, 11.5), (18.5, 8.5)]            # 0.58 m beyond R_agg: on the path within 8 s
    in_time, late = (19.5, 14.0), (19.5, 15.0)    # meet the path at about 37.5 s and 50 s
    assert comfortable(_leaving(*near, in_time))
    assert not comfortable(_leaving(*near, late)) and reachable(_leaving(*near, late))
    assert not comfortable(_leaving(*near, (1.0, 1.0))) and reachable(_leaving(*near, (1.0, 1.0)))


NEAR_OBSTACLE = (Obstacle(centre=(16.0, 12.0), radius=0.5),)


def test_with_two_defenders_both_must_be_in_time():
    assert comfortable(_leaving((18.5, 11.5), (18.5, 8.5), obstacles=NEAR_OBSTACLE))
    assert not comfortable(_leaving((18.5, 11.5), (1.0, 1.0), obstacles=NEAR_OBSTACLE))


def test_with_two_defenders_an_obstacle_must_be_within_the_attackers_reach():
    # The time limit is 600 s: the attacker covers at most 18 m. With two robots an obstacle must be a member.
    near = [(18.5, 11.5), (18.5, 8.5)]
    assert reachable(_leaving(*near, obstacles=NEAR_OBSTACLE)) and comfortable(_leaving(*near, obstacles=NEAR_OBSTACLE))
    in_reach = (Obstacle(centre=(0.5, 10.0), radius=0.5),)      # surface 17 m away: 16.5 m beyond R_hunt
    out_of_reach = (Obstacle(centre=(0.5, 1.0), radius=0.5),)   # surface 19.2 m away
    assert reachable(_leaving(*near, obstacles=in_reach))
    assert not reachable(_leaving(*near, obstacles=out_of_reach))
    assert not comfortable(_leaving(*near, obstacles=out_of_reach))
    assert not reachable(_leaving(*near))                       # no obstacle at all
    assert reachable(_leaving(*near, (3.0, 3.0), obstacles=out_of_reach))   # three robots need none



def test_the_attacker_runs_free_until_the_first_defender_can_meet_it():
    # Heading +y at 0.03 m/s from (10, 10); both defenders wait ahead at y = 19.5 and can first meet its path
    # (within R_agg) after 77.3 s, at (10, 12.3). The obstacle's surface is 5 m beyond R_hunt from the start,
    # within 0.03 m/s × 300 s = 9 m, but 7.3 m beyond it from (10, 12.3), out of 0.03 m/s × 222.7 s = 6.7 m.
    scenario = Scenario(name="ahead", defenders=(Defender(start=(10.0, 19.5), max_speed=0.08),
                                                 Defender(start=(11.0, 19.5), max_speed=0.08)),
                        attacker=Attacker(start=(10.0, 10.0), nominal_velocity=(0.0, 0.03), max_speed=0.03,
                                          perception_radius=1.0),
                        obstacles=(Obstacle(centre=(10.0, 4.0), radius=0.5),),
                        hunt=HuntParameters(time_limit=300.0), arena=(0.0, 0.0, 20.0, 20.0))
    assert np.any(arrival_steps(scenario)[0] >= 0)
    assert not reachable(scenario)
    nearer = dataclasses.replace(scenario, obstacles=(Obstacle(centre=(10.0, 5.0), radius=0.5),))   # 6.3 m
    assert reachable(nearer)


UNREACHABLE = [i for i in range(40) if not reachable(sweep_scenario(2, i, ScenarioRanges()))]
NOBODY_IN_TIME = [i for i in UNREACHABLE if not np.any(arrival_steps(sweep_scenario(2, i, ScenarioRanges()))[0] >= 0)]


def test_some_random_hunts_are_unreachable():
    assert 2 <= len(UNREACHABLE) <= 20


@pytest.mark.parametrize("index", NOBODY_IN_TIME[:4])
def test_on_an_unreachable_hunt_pursuit_never_disturbs_the_attacker(index):
    """Defenders flying straight at the attacker never enter R_agg (where no obstacle is wanting):
    its path is the undisturbed one."""
    scenario = sweep_scenario(2, index, ScenarioRanges())
    result = simulate(scenario, Pursuit(scenario))
    assert not result.captured and result.termination in ("attacker_escaped", "time_limit")
    np.testing.assert_array_equal(result.attacker, np.array(list(undisturbed_path(scenario))))
    assert result.min_attacker_distance > scenario.attacker.perception_radius


def _standing(attacker: tuple[float, float], *starts: tuple[float, float]) -> Scenario:
    """An attacker at 0.03 m/s among defenders at 0.08 m/s in the 20 m arena."""
    return Scenario(name="race", defenders=tuple(Defender(start=s, max_speed=0.08) for s in starts),
                    attacker=Attacker(start=attacker, nominal_velocity=(0.0, 0.03), max_speed=0.03,
                                      perception_radius=1.0),
                    hunt=HuntParameters(), arena=(0.0, 0.0, 20.0, 20.0))


def test_an_attacker_next_to_an_edge_wins_the_race_to_it_and_one_ringed_in_the_middle_does_not():
    # 0.5 m from the right edge, it reaches (20, 10) in 16.7 s; the nearest defender, 4 m inside, needs
    # (4.5 − R_hunt) / 0.08 = 50 s to come within R_hunt of that point.
    assert edge_race_lost(_standing((19.5, 10.0), (15.5, 10.0), (15.0, 14.0), (15.0, 6.0)))
    # At the centre it needs 333 s to any edge; a defender 1.5 m from it needs at most 175 s to any edge point.
    ring = _standing((10.0, 10.0), (11.5, 10.0), (9.25, 11.3), (9.25, 8.7))
    assert not edge_race_lost(ring)
    assert not edge_race_lost(dataclasses.replace(ring, arena=None))
    # The race is decided at the edge point nearest the attacker's way out: one defender standing there is enough.
    assert not edge_race_lost(_standing((19.5, 10.0), (19.9, 10.0), (19.9, 8.5), (19.9, 11.5)))

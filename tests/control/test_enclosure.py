"""The enclose controller's reference (mpc_hunt/control/enclosure.py): each phase on a hand-made state."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mpc_hunt.control.controller import Observation
from mpc_hunt.control import enclosure as E
from mpc_hunt.control.enclosure import Enclosure
from mpc_hunt.world.attacker import velocity
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario

R = 1.0            # R_agg
V_A = 0.03         # the attacker's top speed, heading +x
GATHER = R + E.CLEARANCE
N = 10


def _scenario(*starts, obstacles=()) -> Scenario:
    return Scenario(name="hand-made", defenders=tuple(Defender(start=s, max_speed=0.08) for s in starts),
                    attacker=Attacker(start=(10.0, 10.0), nominal_velocity=(V_A, 0.0), max_speed=V_A,
                                      perception_radius=R),
                    obstacles=obstacles, hunt=HuntParameters(), arena=(0.0, 0.0, 20.0, 20.0))


def _observe(scenario: Scenario, defenders, attacker=(10.0, 10.0), time=0.0) -> Observation:
    return Observation(time, np.array(attacker, dtype=float), None, np.array(defenders, dtype=float))


def _on_circle(centre, radius, degrees):
    return [(centre[0] + radius * math.cos(math.radians(d)), centre[1] + radius * math.sin(math.radians(d)))
            for d in degrees]


def test_gathering_the_first_place_faces_the_escape_direction_outside_r_agg():
    starts = [(15.0, 10.5), (5.0, 14.0), (5.0, 6.0)]
    enclosure = Enclosure(_scenario(*starts), N)
    ref = enclosure.reference(_observe(enclosure.scenario, starts))
    assert enclosure.phase == "gather"
    goals = ref.defenders[-1]
    # every place at step N lies on the gathering circle round the attacker's predicted position (or on the way)
    predicted = np.array([10.0 + N * 0.1 * V_A, 10.0])
    assert np.all(norm(goals - predicted) >= GATHER - 1e-9)
    # the attacker should keep its course: its reference is its undisturbed path
    np.testing.assert_allclose(ref.attacker[:, 0], 10.0 + V_A * 0.1 * np.arange(1, N + 1), atol=1e-12)
    np.testing.assert_allclose(ref.attacker[:, 1], 10.0, atol=1e-12)
    # the nearest defender, ahead of the attacker, heads for the place on its escape direction (bearing 0°)
    way = ref.defenders[-1][0] - starts[0]
    to_place = predicted + [GATHER, 0.0] - starts[0]
    assert np.dot(way, to_place) / norm(way) / norm(to_place) > 0.9999


def test_a_defender_standing_on_the_escape_side_holds_the_attacker_inside_r_agg():
    starts = [_on_circle((10.0, 10.0), GATHER, [0])[0], (2.0, 18.0), (2.0, 2.0)]
    enclosure = Enclosure(_scenario(*starts), N)
    ref = enclosure.reference(_observe(enclosure.scenario, starts))
    assert enclosure.phase == "gather"
    np.testing.assert_allclose(ref.attacker, np.tile([10.0, 10.0], (N, 1)))     # held where it is
    reach = N * 0.08 * 0.1                                                       # in front, going in at full speed
    np.testing.assert_allclose(ref.defenders[-1][0], [10.0 + GATHER - reach, 10.0], atol=1e-12)
    # moved off the escape side, it no longer holds: the attacker's reference is its course again
    aside = [_on_circle((10.0, 10.0), GATHER, [90])[0], (2.0, 18.0), (2.0, 2.0)]
    ref = Enclosure(_scenario(*aside), N).reference(_observe(enclosure.scenario, aside))
    assert ref.attacker[-1][0] > 10.0 + 0.9 * V_A * N * 0.1


def test_the_holding_defender_keeps_holding_as_it_steps_in():
    """No switch to chatter on: nearer than its place on the circle, the escape-side defender still holds."""
    for distance in (GATHER, GATHER - 0.26, 0.95 * R, 0.9 * R):
        starts = [(10.0 + distance, 10.0), (2.0, 18.0), (2.0, 2.0)]
        scenario = _scenario(*starts)
        ref = Enclosure(scenario, N).reference(_observe(scenario, starts))
        np.testing.assert_allclose(ref.attacker, np.tile([10.0, 10.0], (N, 1)))
        assert ref.defenders[0][0][0] <= 10.0 + max(distance, E.BLOCK * R) + 1e-12     # never sent back out


@pytest.mark.parametrize("turn", [0.0, 40.0, 97.0])
def test_three_defenders_round_the_attacker_close_the_circle_whichever_places_they_took(turn):
    starts = _on_circle((10.0, 10.0), GATHER, [turn, turn + 120.0, turn + 240.0])
    enclosure = Enclosure(_scenario(*starts), N)
    ref = enclosure.reference(_observe(enclosure.scenario, starts))
    assert enclosure.phase == "close"
    radii = norm(ref.defenders[-1] - np.array([10.0, 10.0]))
    assert np.all(radii < GATHER - 0.5 * 0.08 * 0.1 * (N - 1))                     # shrinking
    np.testing.assert_allclose(ref.attacker, np.tile([10.0, 10.0], (N, 1)))       # no latecomer: no drift


def test_three_defenders_on_one_side_keep_gathering():
    starts = _on_circle((10.0, 10.0), GATHER, [0.0, 60.0, 120.0])                # a 240° gap behind
    enclosure = Enclosure(_scenario(*starts), N)
    enclosure.reference(_observe(enclosure.scenario, starts))
    assert enclosure.phase == "gather"


def test_the_closing_circle_shrinks_to_half_r_hunt_and_no_further():
    starts = _on_circle((10.0, 10.0), GATHER, [0.0, 120.0, 240.0])
    scenario = _scenario(*starts)
    enclosure = Enclosure(scenario, N)
    for _ in range(2000):
        ref = enclosure.reference(_observe(scenario, starts))
        starts = ref.defenders[0]                                                # as if each place were reached
    np.testing.assert_allclose(norm(ref.defenders[-1] - np.array([10.0, 10.0])), 0.5 * scenario.hunt.hunt_radius)


def test_the_closing_circle_carries_the_attacker_towards_a_latecomer():
    starts = _on_circle((10.0, 10.0), GATHER, [0.0, 120.0, 240.0]) + [(10.0, 2.0)]
    scenario = _scenario(*starts)
    enclosure = Enclosure(scenario, N)
    ref = enclosure.reference(_observe(scenario, starts))
    assert enclosure.phase == "close"
    step = E.DRIFT * V_A * scenario.hunt.time_step
    np.testing.assert_allclose(ref.attacker[-1], [10.0, 10.0 - N * step], atol=1e-12)    # towards (10, 2)
    np.testing.assert_allclose(enclosure.circle.centre, [10.0, 10.0 - step], atol=1e-12)


def test_with_two_defenders_the_nearest_obstacle_anchors_the_circle():
    wall = Obstacle(centre=(10.0, 7.0), radius=1.0)
    starts = _on_circle((10.0, 10.0), GATHER, [30.0, 150.0])
    scenario = _scenario(*starts, obstacles=(wall,))
    enclosure = Enclosure(scenario, N)
    ref = enclosure.reference(_observe(scenario, starts))
    assert enclosure.phase == "herd"
    anchor = np.array([10.0, 7.0 + 1.0 + scenario.hunt.safety_distance + E.ANCHOR_GAP])
    np.testing.assert_allclose(ref.attacker, np.tile(anchor, (N, 1)))
    # the two defenders go in behind the attacker, seen from the obstacle
    assert np.all(ref.defenders[-1][:, 1] > 10.0) and np.all(norm(ref.defenders[-1] - [10.0, 10.0]) < GATHER - 0.05)


def test_the_predicted_attacker_steps_by_eq_2_with_the_defenders_held():
    """predicted_path: p_{k+1} = p_k + T v(p_k) (Eq. 2, the model's velocity with the defenders where they stand),
    here with a defender within R_agg pushing the attacker sideways towards an obstacle's field."""
    starts = [(10.3, 9.6), (5.0, 14.0), (5.0, 6.0)]
    scenario = _scenario(*starts, obstacles=(Obstacle(centre=(11.0, 11.2), radius=0.5),))
    P = np.array(starts)
    p, T = np.array([10.0, 10.0]), scenario.hunt.time_step
    expected = []
    for _ in range(N):
        p = p + T * velocity(scenario, p, P)
        expected.append(p)
    path = Enclosure(scenario, N)._predicted(np.array([10.0, 10.0]), P)
    assert np.array_equal(path, np.array(expected))
    assert abs(path[-1, 1] - 10.0) > 1e-3  # the push turned it: both coordinates are predicted

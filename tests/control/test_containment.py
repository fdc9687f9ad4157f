"""The contain controller's reference (mpc_hunt/control/containment.py): observed, co-moving, model-free."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mpc_hunt.control.containment import CONTAIN_WEIGHTS, Containment, around, contain_places
from mpc_hunt.control.observed import VELOCITY_WINDOW
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.spec import make_controller
from mpc_hunt.world.belief import Belief, believed
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario

N = 8
RING = [(10.25, 10.0), (9.875, 10.216506), (9.875, 9.783494)]   # R_hunt / 2 round (10, 10), 120° apart: at their places


def _scenario(**attacker) -> Scenario:
    return Scenario(name="ring", defenders=tuple(Defender(start=p, max_speed=0.08) for p in RING),
                    attacker=Attacker(start=(10.0, 10.0), nominal_velocity=(0.03, 0.0), max_speed=0.03,
                                      perception_radius=1.0, **attacker),
                    hunt=HuntParameters(), arena=(0.0, 0.0, 20.0, 20.0))


def _observations(velocity, steps: int = VELOCITY_WINDOW + 1):
    """The attacker seen moving at ``velocity`` for ``steps`` steps, the defenders standing on the ring."""
    T, p = 0.1, np.array([10.0, 10.0]) - steps * 0.1 * np.asarray(velocity)
    previous = None
    for k in range(steps + 1):
        yield Observation(k * T, p.copy(), previous, np.array(RING))
        previous, p = p.copy(), p + T * np.asarray(velocity)


def _last_reference(builder: Containment, velocity):
    for obs in _observations(velocity):
        reference = builder.reference(obs)
    return obs, reference


def test_the_velocity_is_the_mean_of_the_last_observed_steps_capped_at_v_a():
    builder = Containment(_scenario(), N)
    obs = list(_observations((0.02, -0.01)))
    for o in obs:
        v = builder.observed.update(o)
    np.testing.assert_allclose(v, [0.02, -0.01], atol=1e-12)
    fast = Containment(_scenario(), N)
    for o in _observations((0.3, 0.0)):
        v = fast.observed.update(o)
    np.testing.assert_allclose(v, [0.03, 0.0], atol=1e-12)


def test_the_places_move_with_the_attackers_observed_velocity_and_so_does_its_reference():
    still_obs, still = _last_reference(Containment(_scenario(), N), (0.0, 0.0))
    moving_obs, moving = _last_reference(Containment(_scenario(), N), (0.02, 0.0))
    k = np.arange(1, N + 1)[:, None]
    np.testing.assert_allclose(moving.attacker, moving_obs.attacker + 0.1 * k * np.array([0.02, 0.0]), atol=1e-12)
    np.testing.assert_allclose(still.attacker, np.repeat(still_obs.attacker[None], N, axis=0), atol=1e-12)
    # Enclosed and standing at their places, each place rides on the attacker: step k's is 0.1·k·0.02 m along x.
    np.testing.assert_allclose(still.defenders[-1], RING, atol=1e-5)
    shift = moving.defenders - still.defenders
    np.testing.assert_allclose(shift[..., 0], np.repeat(0.1 * k * 0.02, 3, axis=1), atol=1e-9)
    np.testing.assert_allclose(shift[..., 1], 0.0, atol=1e-9)


def test_the_reference_is_the_same_whatever_the_believed_intent_or_reaction():
    world = _scenario()
    references = []
    for belief in (Belief(), Belief(eta=3.0), Belief(intent_heading=90.0)):
        builder = Containment(believed(world, belief, np.random.default_rng(1)), N)
        references.append(_last_reference(builder, (0.01, 0.01))[1])
    for other in references[1:]:
        np.testing.assert_array_equal(other.defenders, references[0].defenders)
        np.testing.assert_array_equal(other.attacker, references[0].attacker)


def test_a_far_defender_goes_straight_to_a_far_side_place_where_the_way_clears_the_tightest_ring():
    centre = np.array([10.0, 10.0])
    far = np.array([10.0, 16.0])
    # Its place 3 m out at bearing 0 (east): the straight way passes 3.2 m from the centre, clear of a 1 m ring.
    np.testing.assert_allclose(around(far, *centre, 0.0, 3.0, 1.0, 0.008), [13.0, 10.0])
    # The place due south (through the centre): it goes round the 1 m ring, to its tangent side.
    detour = np.array(around(far, *centre, -np.pi / 2, 3.0, 1.0, 0.008))
    assert norm(detour - centre) == pytest.approx(1.0) and abs(detour[0] - 10.0) > 0.5


def test_contain_plans_with_no_term_on_the_predicted_attacker():
    assert CONTAIN_WEIGHTS.attacker == 0.0 and CONTAIN_WEIGHTS.edge > 0
    controller = make_controller("contain", _scenario(), formulation="rti", backend="hpipm", horizon=5)
    obs = next(iter(_observations((0.0, 0.0), steps=1)))
    command = controller.command(dataclasses.replace(obs, previous_attacker=None))
    assert command.solution.success and np.all(norm(command.velocities) <= 0.08 + 1e-9)
    assert controller.describe()["controller"] == "contain"


def test_an_enclosed_attackers_places_ride_on_its_drift_along_both_axes():
    """contain_places with the attacker enclosed: a mover whose straight way clears the tightest ring (1 m, the
    other mover's) is at its place on its circle carried by the drift, step by step, in x and in y."""
    scenario = dataclasses.replace(_scenario(), defenders=(Defender(start=(13.0, 10.5), max_speed=50.0),
                                                           Defender(start=(5.0, 5.0), max_speed=50.0)))
    k = np.arange(1, N + 1)[:, None]
    drift = k * np.array([0.01, -0.02])
    places = contain_places(np.array([[13.0, 10.5], [5.0, 5.0]]), np.array([0, 1]), np.array([[10.0, 10.0]] * 2),
                            np.array([0.0, np.pi]), np.array([3.0, 1.0]), True, drift, scenario.defender_max_speeds,
                            scenario.obstacle_centres, scenario.obstacle_radii, scenario.packed)
    np.testing.assert_allclose(places[:, 0], np.array([13.0, 10.0]) + drift, atol=1e-12)


@pytest.mark.parametrize("speed", [0.08, 50.0])
def test_a_place_is_out_of_r_safe_and_within_k_steps_of_top_speed(speed):
    """One mover whose place (3 m east of the circle's centre) falls inside an obstacle: every place is moved out
    to R_safe of it (once the reach allows the place itself) and none is farther than k steps at top speed."""
    obstacle = Obstacle(centre=(13.05, 10.0), radius=0.2)
    scenario = dataclasses.replace(_scenario(), obstacles=(obstacle,),
                                   defenders=(Defender(start=(13.0, 11.5), max_speed=speed),))
    P = np.array([[13.0, 11.5]])
    places = contain_places(P, np.array([0]), np.array([[10.0, 10.0]]), np.array([0.0]), np.array([3.0]), False,
                            np.zeros((N, 2)), scenario.defender_max_speeds, scenario.obstacle_centres,
                            scenario.obstacle_radii, scenario.packed)
    reach = speed * scenario.hunt.time_step * np.arange(1, N + 1)
    assert np.all(norm(places[:, 0] - P[0]) <= reach + 1e-12)
    clearance = norm(places[:, 0] - obstacle.centre) - obstacle.radius - scenario.hunt.safety_distance
    if speed > 1:    # the place itself is reached: it lies on R_safe, not in the obstacle
        assert np.all(clearance >= -1e-12) and clearance[-1] == pytest.approx(0.0, abs=1e-12)

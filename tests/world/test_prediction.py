"""Tests of trajectory prediction (Eqs. 7–8, docs/model.md, E8) and the approach law (Eq. 6, docs/model.md, E3)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from mpc_hunt.control.controller import Observation
from mpc_hunt.control.strategy import approach_commands
from mpc_hunt.world.approach import approach_velocity
from mpc_hunt.world.prediction import intercept_point, intercept_time
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario
from mpc_hunt.world.scenario_io import builtin_scenario

from strategies import FAST, angles, floats, points, polar


def gap(t, p_a, v_a, p_d, speed):
    """|p_a + v_a t − p_d| − s_d t: positive while the defender cannot yet be where the attacker is."""
    t = np.asarray(t, dtype=float)
    pos = p_a[None, :] + t[:, None] * v_a[None, :]
    return np.linalg.norm(pos - p_d[None, :], axis=1) - speed * t


@st.composite
def chases(draw, speeds, apart: float):
    """(p_a, p_d, v_speed, v_a): an attacker at p_a and a defender at p_d more than ``apart`` from it, the
    attacker's velocity v_a of speed v_speed (drawn from ``speeds``) at any heading."""
    p_a, p_d = draw(points), draw(points)
    assume(np.linalg.norm(p_a - p_d) > apart)
    v_speed = draw(speeds)
    return p_a, p_d, v_speed, polar(v_speed, draw(angles))


# --- intercept_time / intercept_point -----------------------------------------------------------

@FAST
@given(chase=chases(floats(0.0, 1.0), apart=1e-3), ratio=floats(1.05, 20.0))
def test_faster_defender_always_intercepts_with_equal_arrival_times(chase, ratio):
    p_a, p_d, v_speed, v_a = chase
    speed = max(v_speed * ratio, 1e-3)
    t = intercept_time(p_a, v_a, p_d, speed)
    assert t is not None and t >= 0
    p = intercept_point(p_a, v_a, p_d, speed)
    assert p is not None
    scale = max(1.0, speed * t)
    # Eq. 8 read with speeds: both arrive at p' at time t.
    assert math.isclose(float(np.linalg.norm(p - p_d)), speed * t, rel_tol=1e-7, abs_tol=1e-9 * scale)
    if v_speed > 1e-6:
        t_attacker = float(np.linalg.norm(p - p_a)) / float(np.linalg.norm(v_a))
        t_defender = float(np.linalg.norm(p - p_d)) / speed
        assert math.isclose(t_attacker, t_defender, rel_tol=1e-6, abs_tol=1e-9 * scale)
    # Eq. 7: p' lies ahead of the attacker on its line of motion.
    step = p - p_a
    assert abs(step[0] * v_a[1] - step[1] * v_a[0]) <= 1e-9 * scale * max(1.0, v_speed)
    assert float(step @ v_a) >= -1e-12
    np.testing.assert_allclose(p, p_a + t * v_a, rtol=1e-12, atol=1e-12)


@FAST
@given(chase=chases(floats(0.0, 2.0), apart=1e-2), speed=floats(0.05, 1.0))
def test_intercept_is_the_earliest_meeting_time(chase, speed):
    """Brute force: the gap |p_a + v t − p_d| − s t stays positive before t* (any speeds)."""
    p_a, p_d, v_speed, v_a = chase
    t = intercept_time(p_a, v_a, p_d, speed)
    if t is None:
        # No intercept: the defender can never be where the attacker is (scan a long horizon).
        horizon = 10.0 * (np.linalg.norm(p_a - p_d) + 1.0) / speed
        grid = np.linspace(0.0, horizon, 20001)
        assert np.all(gap(grid, p_a, v_a, p_d, speed) > -1e-9)
        return
    assert t >= 0
    assert abs(gap([t], p_a, v_a, p_d, speed)[0]) <= 1e-7 * max(1.0, speed * t)
    # Every scanned time before t* leaves a non-negative gap (no earlier meeting), up to rounding.
    grid = np.linspace(0.0, t, 4001)[:-1]
    g = gap(grid, p_a, v_a, p_d, speed)
    assert np.all(g > -1e-7 * max(1.0, speed * t))
    # Where the gap crosses zero cleanly (not tangentially, which makes the scan ill-conditioned),
    # the first scanned time with a non-positive gap agrees with t* to within the grid step.
    p = p_a + t * v_a
    slope = float((p - p_d) @ v_a) / max(float(np.linalg.norm(p - p_d)), 1e-300) - speed
    if abs(slope) < 1e-3 * (speed + v_speed):
        return
    fine = np.linspace(0.0, 2.0 * t + 1.0, 40001)
    gf = gap(fine, p_a, v_a, p_d, speed)
    assert np.any(gf <= 0)
    first = fine[np.argmax(gf <= 0)]
    step = fine[1] - fine[0]
    assert t - step - 1e-9 * max(1.0, t) <= first <= t + step + 1e-9 * max(1.0, t)


def test_attacker_faster_with_two_meeting_times_returns_the_earlier():
    # |10 − 2t| = t at t = 10/3 and t = 10.
    p_a, v_a, p_d = np.array([10.0, 0.0]), np.array([-2.0, 0.0]), np.zeros(2)
    assert intercept_time(p_a, v_a, p_d, 1.0) == pytest.approx(10.0 / 3.0, rel=1e-12)
    np.testing.assert_allclose(intercept_point(p_a, v_a, p_d, 1.0), [10.0 / 3.0, 0.0], rtol=1e-12)


def test_attacker_faster_moving_directly_away_has_no_intercept():
    p_a, v_a, p_d = np.array([5.0, 0.0]), np.array([2.0, 0.0]), np.zeros(2)
    assert intercept_time(p_a, v_a, p_d, 1.0) is None
    assert intercept_point(p_a, v_a, p_d, 1.0) is None


def test_attacker_faster_passing_too_far_has_no_intercept():
    # |(−10 + 2t, 10)|² = t² has no real root.
    assert intercept_time(np.array([-10.0, 10.0]), np.array([2.0, 0.0]), np.zeros(2), 1.0) is None


@pytest.mark.parametrize("v_a, expected", [
    ([-1.0, 0.0], 5.0),                    # head on: meet half way
    ([-0.6, 0.8], 100.0 / 12.0),           # oblique approach: t = |w|² / (−2 w·v)
    ([1.0, 0.0], None),                    # moving away at the same speed
    ([0.0, 1.0], None),                    # crossing at the same speed: never caught
])
def test_equal_speeds(v_a, expected):
    p_a, p_d = np.array([10.0, 0.0]), np.zeros(2)
    v_a = np.array(v_a)
    t = intercept_time(p_a, v_a, p_d, 1.0)
    if expected is None:
        assert t is None
        assert intercept_point(p_a, v_a, p_d, 1.0) is None
    else:
        assert t == pytest.approx(expected, rel=1e-12)
        p = intercept_point(p_a, v_a, p_d, 1.0)
        assert np.linalg.norm(p - p_d) == pytest.approx(t, rel=1e-12)


@FAST
@given(chase=chases(floats(0.01, 1.0), apart=1e-2))
def test_equal_speeds_intercept_exists_iff_attacker_approaches(chase):
    p_a, p_d, v_speed, v_a = chase
    w = p_a - p_d
    closing = float(w @ v_a)
    assume(abs(closing) > 1e-6 * np.linalg.norm(w) * v_speed)
    speed = float(np.linalg.norm(v_a))
    t = intercept_time(p_a, v_a, p_d, speed)
    if closing < 0:
        assert t is not None
        assert t == pytest.approx(float(w @ w) / (-2.0 * closing), rel=1e-9)
    else:
        assert t is None


@FAST
@given(p_a=points, p_d=points, speed=floats(1e-3, 5.0))
def test_stationary_attacker_is_intercepted_at_its_own_position(p_a, p_d, speed):
    assume(np.linalg.norm(p_a - p_d) > 1e-6)
    t = intercept_time(p_a, np.zeros(2), p_d, speed)
    assert t == pytest.approx(float(np.linalg.norm(p_a - p_d)) / speed, rel=1e-12)
    np.testing.assert_array_equal(intercept_point(p_a, np.zeros(2), p_d, speed), p_a)


def test_defender_already_on_the_attacker_meets_at_time_zero():
    p = np.array([3.0, -2.0])
    assert intercept_time(p, np.array([0.5, 0.5]), p.copy(), 0.1) == 0.0
    np.testing.assert_array_equal(intercept_point(p, np.array([0.5, 0.5]), p.copy(), 0.1), p)


# --- approach_target / approach_velocity (Eq. 6) -----------------------------------------------

def _approach_target(p_a, v_a, p_d, speed, prediction):
    """The approaching stage's target p'_di (its intercept output) for one defender at ``p_d``."""
    scenario = _open_scenario()
    scenario = dataclasses.replace(scenario, defenders=(dataclasses.replace(scenario.defenders[0], max_speed=speed),))
    obs = Observation(0.1, np.asarray(p_a), np.asarray(p_a) - 0.1 * np.asarray(v_a), np.asarray(p_d)[None])
    return approach_commands(scenario, obs, np.array([True]), prediction)[1][0]


def test_approach_target_without_prediction_is_attacker_position():
    p_a, v_a, p_d = np.array([1.0, 14.0]), np.array([0.02, -0.02]), np.array([1.0, 1.0])
    out = _approach_target(p_a, v_a, p_d, 0.08, prediction=False)
    np.testing.assert_array_equal(out, p_a)
    # With prediction the target differs: the predicted intercept.
    predicted = _approach_target(p_a, v_a, p_d, 0.08, prediction=True)
    np.testing.assert_allclose(predicted, intercept_point(p_a, v_a, p_d, 0.08), rtol=1e-12)
    assert np.linalg.norm(predicted - p_a) > 0.1


def test_approach_target_falls_back_to_attacker_position_without_intercept():
    p_a, v_a, p_d = np.array([5.0, 0.0]), np.array([2.0, 0.0]), np.zeros(2)
    assert intercept_point(p_a, v_a, p_d, 1.0) is None
    np.testing.assert_array_equal(_approach_target(p_a, v_a, p_d, 1.0, prediction=True), p_a)


def _open_scenario(omega: float = 0.5) -> Scenario:
    return Scenario(name="approach-test",
                    defenders=(Defender((0.0, 0.0), 0.08),),
                    attacker=Attacker((10.0, 10.0), (0.2, -0.2), 0.03, 1.0),
                    hunt=HuntParameters(omega=omega))


OBSTACLES = builtin_scenario("paper-obstacles")


@FAST
@given(p_d=points, target=points,
       others=st.lists(st.tuples(floats(-1, 1), floats(-1, 1)), max_size=3),
       speed=floats(1e-3, 1.0), near_obstacle=st.booleans())
def test_approach_velocity_never_exceeds_speed(p_d, target, others, speed, near_obstacle):
    if near_obstacle:  # put the defender within reach of an obstacle (possibly inside it)
        p_d = OBSTACLES.obstacle_centres[0] + p_d / 25.0
    others = np.array([p_d + np.array(o) * 0.5 for o in others]).reshape(-1, 2)
    u = approach_velocity(OBSTACLES, p_d, target, speed, others)
    assert np.all(np.isfinite(u))
    assert float(np.linalg.norm(u)) <= speed * (1 + 1e-12)


@FAST
@given(p_d=points, offset_len=floats(1e-3, 30.0), angle=angles, speed=floats(1e-3, 1.0),
       omega=floats(0.05, 1.0))
def test_approach_velocity_points_toward_target_when_nothing_is_near(p_d, offset_len, angle, speed,
                                                                      omega):
    scenario = _open_scenario(omega)
    target = p_d + polar(offset_len, angle)
    others = np.array([p_d + [5.0, 5.0]])  # far beyond 2 × min_separation
    u = approach_velocity(scenario, p_d, target, speed, others)
    d = target - p_d
    n = float(np.linalg.norm(u))
    assert n > 0
    # E3: towards the intercept point, not away from it.
    assert float(u @ d) > 0
    assert abs(u[0] * d[1] - u[1] * d[0]) <= 1e-9 * n * np.linalg.norm(d)
    assert n == pytest.approx(min(speed, omega * float(np.linalg.norm(d))), rel=1e-9)


def test_approach_velocity_on_paper_obstacle_map_far_from_obstacles_heads_to_target():
    u = approach_velocity(OBSTACLES, np.array([1.0, 1.0]), np.array([1.0, 14.0]), 0.08, np.zeros((0, 2)))
    np.testing.assert_allclose(u, [0.0, 0.08], atol=1e-12)


def test_approach_velocity_turns_away_from_nearby_obstacle():
    # Obstacle [5, 5] of radius 0.5; defender 0.3 m below its surface, target straight to the right.
    p_d = np.array([5.0, 4.2])
    u = approach_velocity(OBSTACLES, p_d, np.array([15.0, 4.2]), 0.08, np.zeros((0, 2)))
    assert u[0] > 0
    assert u[1] < 0


def test_approach_velocity_keeps_away_from_other_defenders():
    scenario = _open_scenario()
    # Another defender 0.2 m to the right, within 2 × min_separation = 0.4 m; target straight up.
    u = approach_velocity(scenario, np.zeros(2), np.array([0.0, 10.0]), 0.08, np.array([[0.2, 0.0]]))
    assert u[0] < 0
    # Outside that range it has no influence.
    u = approach_velocity(scenario, np.zeros(2), np.array([0.0, 10.0]), 0.08, np.array([[0.5, 0.0]]))
    np.testing.assert_allclose(u, [0.0, 0.08], atol=1e-15)


def test_approach_velocity_uses_scenario_obstacles_only():
    scenario = Scenario(name="one-obstacle", defenders=(Defender((0.0, 0.0), 0.08),),
                        attacker=Attacker((10.0, 10.0), (0.2, -0.2), 0.03, 1.0),
                        obstacles=(Obstacle((0.0, 1.5), 1.0),))
    # Surface 0.5 m above the defender; target far to the left: pushed down, moving left.
    u = approach_velocity(scenario, np.zeros(2), np.array([-10.0, 0.0]), 0.08, np.zeros((0, 2)))
    assert u[0] < 0 and u[1] < 0
    assert np.linalg.norm(u) == pytest.approx(0.08, rel=1e-12)

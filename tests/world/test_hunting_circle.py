"""Tests of the hunting circle (Eqs. 4–5, 10–12, docs/model.md, E5, E7) and the geometry helpers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from mpc_hunt.world.geometry import encloses, norm, saturate, unit
from mpc_hunt.world.hunting_circle import MIN_MEMBERS, desired_velocity, members, success_test

from strategies import FAST, angles, floats, points, polar

NO_CENTRES, NO_RADII = np.zeros((0, 2)), np.zeros(0)
R_HUNT, TOL = 0.5, 0.25


def ring(centre, radius, n, phase=0.0):
    return np.array([centre + polar(radius, phase + 2 * math.pi * k / n) for k in range(n)])


# --- geometry helpers ---------------------------------------------------------------------------

@FAST
@given(v=points, cap=floats(1e-3, 10.0))
def test_saturate_caps_norm_and_keeps_direction(v, cap):
    out = saturate(v, cap)
    assert float(norm(out)) <= cap * (1 + 1e-12)
    if float(norm(v)) <= cap:
        np.testing.assert_array_equal(out, v)
    else:
        np.testing.assert_allclose(unit(out), unit(v), atol=1e-12)


@FAST
@given(angle=angles, exponent=floats(150.0, 308.0), cap=floats(1e-3, 10.0))
def test_saturate_caps_a_vector_whose_square_overflows_in_its_direction(angle, exponent, cap):
    """Beyond about 1e154 a component's square overflows; the vector still saturates to ``cap``, not to 0."""
    v = polar(10.0 ** exponent, angle)
    out = saturate(np.array([v, [0.01 * cap, 0.0]]), np.array([cap, cap]))
    assert float(norm(out[0])) == pytest.approx(cap, rel=1e-12)
    np.testing.assert_allclose(out[0] / cap, np.array([math.cos(angle), math.sin(angle)]), atol=1e-12)
    np.testing.assert_array_equal(out[1], [0.01 * cap, 0.0])          # the other rows as before, to the bit


def test_unit_leaves_zero_vector_zero():
    np.testing.assert_array_equal(unit(np.zeros(2)), np.zeros(2))
    np.testing.assert_allclose(unit(np.array([3.0, 4.0])), [0.6, 0.8])


# --- encloses -----------------------------------------------------------------------------------

@FAST
@given(centre=points, radius=floats(1e-2, 1e3), n=st.integers(3, 12), phase=angles)
def test_centroid_of_regular_polygon_is_enclosed(centre, radius, n, phase):
    anchors = ring(centre, radius, n, phase)
    assert encloses(centre, anchors)
    assert encloses(anchors.mean(axis=0), anchors)


@FAST
@given(tri=st.lists(points, min_size=3, max_size=3), perm=st.permutations(range(3)))
def test_centroid_of_triangle_is_enclosed_in_any_order(tri, perm):
    a = np.array(tri)
    area = 0.5 * abs((a[1, 0] - a[0, 0]) * (a[2, 1] - a[0, 1]) - (a[2, 0] - a[0, 0]) * (a[1, 1] - a[0, 1]))
    assume(area > 1.0)
    assert encloses(a.mean(axis=0), a[list(perm)])


@FAST
@given(anchors=st.lists(points, min_size=3, max_size=10), side=st.sampled_from("LRBT"),
       margin=floats(1e-3, 100.0), along=floats(0.0, 1.0))
def test_point_outside_bounding_box_is_not_enclosed(anchors, side, margin, along):
    a = np.array(anchors)
    lo, hi = a.min(axis=0), a.max(axis=0)
    x = lo[0] + along * (hi[0] - lo[0])
    y = lo[1] + along * (hi[1] - lo[1])
    point = {"L": (lo[0] - margin, y), "R": (hi[0] + margin, y),
             "B": (x, lo[1] - margin), "T": (x, hi[1] + margin)}[side]
    assert not encloses(np.array(point), a)


@FAST
@given(anchors=st.lists(points, min_size=0, max_size=2), point=points)
def test_fewer_than_three_anchors_never_enclose(anchors, point):
    assert not encloses(point, np.array(anchors, dtype=float).reshape(-1, 2))


def test_fewer_than_three_anchors_around_the_point():
    assert not encloses(np.zeros(2), np.array([[1.0, 0.0], [-1.0, 0.0]]))
    assert encloses(np.zeros(2), np.array([[1.0, 0.0], [-1.0, 0.1], [-1.0, -0.1]]))


def test_enclosure_is_strict():
    tri = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    assert not encloses(np.array([1.0, 0.0]), tri)    # on an edge
    assert not encloses(np.array([0.0, 0.0]), tri)    # on a vertex
    assert encloses(np.array([0.5, 0.5]), tri)
    assert not encloses(np.array([1.5, 1.5]), tri)    # outside, inside the bounding box


# --- success test (Eqs. 4–5, E7) ----------------------------------------------------------------

def test_three_defenders_equally_spaced_at_0_3_hold():
    p_a = np.array([4.0, 7.0])
    status = success_test(p_a, ring(p_a, 0.3, 3, 0.4), NO_CENTRES, NO_RADII, R_HUNT, TOL)
    assert status.holds
    assert status.enclosed
    assert status.member_count == 3
    assert status.radius == pytest.approx(0.3, rel=1e-12)
    assert status.centre_offset == pytest.approx(0.0, abs=1e-12)


def test_radius_beyond_hunt_radius_fails():
    p_a = np.array([4.0, 7.0])
    status = success_test(p_a, ring(p_a, 0.6, 3), NO_CENTRES, NO_RADII, R_HUNT, TOL)
    assert not status.holds
    assert status.enclosed
    assert status.radius == pytest.approx(0.6, rel=1e-12)


def test_three_defenders_on_one_side_fail():
    p_a = np.array([0.0, 0.0])
    defenders = np.array([polar(0.3, a) for a in (0.0, math.pi / 6, math.pi / 3)])
    status = success_test(p_a, defenders, NO_CENTRES, NO_RADII, R_HUNT, TOL)
    assert not status.enclosed
    assert not status.holds
    assert status.radius == pytest.approx(0.3)


def test_attacker_off_the_centre_fails_even_when_enclosed():
    # Enclosed, all within R_hunt, but 0.15 m from the members' centroid.
    defenders = ring(np.zeros(2), 0.3, 3, math.pi / 2)
    p_a = np.array([0.0, 0.15])
    status = success_test(p_a, defenders, NO_CENTRES, NO_RADII, R_HUNT, 0.1)
    assert status.enclosed
    assert status.radius <= R_HUNT
    assert status.centre_offset == pytest.approx(0.15, rel=1e-9)
    assert not status.holds
    assert success_test(p_a, defenders, NO_CENTRES, NO_RADII, R_HUNT, 0.25).holds


@FAST
@given(p_a=points, radius=floats(0.01, R_HUNT * 0.999), phase=angles)
def test_equally_spaced_trio_within_hunt_radius_holds(p_a, radius, phase):
    status = success_test(p_a, ring(p_a, radius, 3, phase), NO_CENTRES, NO_RADII, R_HUNT, TOL)
    assert status.holds
    assert status.radius == pytest.approx(radius, rel=1e-9)


@FAST
@given(p_a=points, radius=floats(R_HUNT * 1.001, 5.0), phase=angles, n=st.integers(3, 6))
def test_ring_beyond_hunt_radius_never_holds(p_a, radius, phase, n):
    status = success_test(p_a, ring(p_a, radius, n, phase), NO_CENTRES, NO_RADII, R_HUNT, TOL)
    assert not status.holds
    assert status.radius == pytest.approx(radius, rel=1e-9)


def _two_robots_and_obstacle():
    p_a = np.array([0.0, 0.0])
    defenders = np.array([polar(0.3, math.radians(30)), polar(0.3, math.radians(150))])
    centres = np.array([[0.0, -1.3]])     # radius 1: surface 0.3 m below the attacker
    return p_a, defenders, centres


def test_obstacle_surface_within_hunt_radius_stands_in_for_a_robot():
    p_a, defenders, centres = _two_robots_and_obstacle()
    status = success_test(p_a, defenders, centres, np.array([1.0]), R_HUNT, TOL)
    assert status.member_count == 3
    assert status.radius == pytest.approx(0.3, rel=1e-9)
    assert status.enclosed
    assert status.holds


def test_same_obstacle_measured_to_its_centre_could_not_hold():
    p_a, defenders, centres = _two_robots_and_obstacle()
    # The obstacle's centre as a point member (radius 0): 1.3 m > R_hunt.
    status = success_test(p_a, defenders, centres, np.array([0.0]), R_HUNT, TOL)
    assert status.radius == pytest.approx(1.3, rel=1e-9)
    assert not status.holds
    # Or the centre standing in as a robot.
    status = success_test(p_a, np.vstack([defenders, centres]), NO_CENTRES, NO_RADII, R_HUNT, TOL)
    assert not status.holds


def test_far_obstacle_does_not_complete_two_robots():
    p_a, defenders, _ = _two_robots_and_obstacle()
    status = success_test(p_a, defenders, np.array([[0.0, -3.0]]), np.array([1.0]), R_HUNT, TOL)
    assert status.member_count == 3          # recruited, but 2 m from its surface
    assert status.radius == pytest.approx(2.0, rel=1e-9)
    assert not status.holds


def test_two_robots_without_obstacles_never_hold():
    p_a = np.zeros(2)
    status = success_test(p_a, np.array([[0.2, 0.0], [-0.2, 0.0]]), NO_CENTRES, NO_RADII, R_HUNT, TOL)
    assert status.member_count == 2
    assert not status.holds


# --- members (E5, E7) ---------------------------------------------------------------------------

def test_members_recruit_nearest_obstacles_by_surface_when_fewer_than_three_robots():
    p_a = np.zeros(2)
    # Gaps to the surface: A = 1.0, B = 1.9, C = 2.5; distances to the centres: A = 4, B = 2, C = 3.
    centres = np.array([[4.0, 0.0], [0.0, 2.0], [-3.0, 0.0]])
    radii = np.array([3.0, 0.1, 0.5])
    m = members(p_a, np.array([[0.0, -0.3]]), centres, radii, 0.5)
    assert m.obstacle_indices == (0, 1)
    assert len(m.anchors) == MIN_MEMBERS
    np.testing.assert_allclose(m.anchors, [[0.0, -0.3], [1.0, 0.0], [0.0, 1.9]], atol=1e-12)
    np.testing.assert_allclose(m.distances, [0.3, 1.0, 1.9], atol=1e-12)
    np.testing.assert_allclose(m.centre, m.anchors.mean(axis=0))


def test_members_with_no_robots_recruit_three_obstacles():
    centres = np.array([[0.0, 5.0], [0.0, -5.0], [5.0, 0.0], [-9.0, 0.0]])
    m = members(np.zeros(2), np.zeros((0, 2)), centres, np.ones(4), 0.5)
    assert m.obstacle_indices == (0, 1, 2)
    np.testing.assert_allclose(m.distances, [4.0, 4.0, 4.0])


def test_members_with_three_robots_add_only_obstacles_in_range():
    p_a = np.zeros(2)
    robots = ring(p_a, 0.3, 3)
    centres = np.array([[0.0, 1.4], [0.0, -1.6], [3.0, 3.0]])   # gaps 0.4, 0.6, ~3.24
    m = members(p_a, robots, centres, np.ones(3), 0.5)
    assert m.obstacle_indices == (0,)
    np.testing.assert_allclose(m.anchors[:3], robots)
    np.testing.assert_allclose(m.anchors[3], [0.0, 0.4], atol=1e-12)
    np.testing.assert_allclose(m.distances, [0.3, 0.3, 0.3, 0.4], atol=1e-12)


def test_members_keep_all_obstacles_in_range_beyond_three():
    p_a = np.zeros(2)
    centres = np.array([[0.0, 1.2], [0.0, -1.3], [1.4, 0.0], [10.0, 10.0]])
    m = members(p_a, np.array([[-0.3, 0.0]]), centres, np.ones(4), 0.5)
    assert m.obstacle_indices == (0, 1, 2)


def test_members_when_too_few_obstacles_exist():
    m = members(np.zeros(2), np.array([[0.3, 0.0]]), np.array([[0.0, 5.0]]), np.array([1.0]), 0.5)
    assert m.obstacle_indices == (0,)
    assert len(m.anchors) == 2


def test_attacker_inside_obstacle_has_zero_distance_to_it():
    m = members(np.zeros(2), ring(np.zeros(2), 0.3, 3), np.array([[0.5, 0.0]]), np.array([1.0]), 0.5)
    assert m.obstacle_indices == (0,)
    assert m.distances[-1] == 0.0


# --- desired velocity (Eq. 12) ------------------------------------------------------------------

@FAST
@given(p_a=points, target=points, v_max=floats(1e-3, 1.0), r_hunt=floats(0.05, 2.0))
def test_desired_velocity_points_to_target_and_respects_max_speed(p_a, target, v_max, r_hunt):
    u = desired_velocity(p_a, target, v_max, r_hunt)
    d = target - p_a
    dist = float(np.linalg.norm(d))
    speed = float(np.linalg.norm(u))
    assert speed <= v_max * (1 + 1e-12)
    if dist == 0:
        np.testing.assert_array_equal(u, np.zeros(2))
        return
    assert float(u @ d) >= 0
    assert abs(u[0] * d[1] - u[1] * d[0]) <= 1e-9 * max(speed, 1e-300) * dist + 1e-300
    if dist >= r_hunt * (1 + 1e-9):
        assert speed == pytest.approx(v_max, rel=1e-9)     # full speed outside R_hunt
    else:
        assert speed == pytest.approx(dist * v_max / r_hunt, rel=1e-9)  # proportional inside


def test_desired_velocity_examples():
    np.testing.assert_allclose(desired_velocity([0, 0], [10, 0], 0.03, 0.5), [0.03, 0.0])
    np.testing.assert_allclose(desired_velocity([0, 0], [0, -0.25], 0.03, 0.5), [0.0, -0.015])
    np.testing.assert_array_equal(desired_velocity([1, 1], [1, 1], 0.03, 0.5), [0.0, 0.0])

"""The attacker's dominance region (mpc_hunt/world/reachable_set.py): Apollonius limits, obstacles, the edge."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt.world.reachable_set import (defender_reach, dominance, edge_distance, obstacle_block,
                                          ray_directions)

coordinate = st.floats(-10.0, 10.0, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(attacker=st.tuples(coordinate, coordinate), defender=st.tuples(coordinate, coordinate),
       ratio=st.floats(0.1, 0.95), reach=st.floats(0.0, 1.0), angle=st.floats(0.0, 2 * np.pi))
def test_the_limit_is_where_the_attacker_and_the_defender_arrive_together(attacker, defender, ratio, reach, angle):
    p_a, p_d = np.array(attacker), np.array([defender])
    u = np.array([[np.cos(angle), np.sin(angle)]])
    s = float(defender_reach(p_a, u, p_d, np.array([ratio]), reach)[0, 0])
    gap = float(np.hypot(*(p_a - p_d[0])))
    if gap <= reach:                                   # already within reach: the attacker gets nowhere first
        assert s <= 1e-9
        return
    meet = p_a + s * u[0]
    # The attacker's time s / v_a equals the defender's (|meet − p_d| − reach) / v_d (v_a = ratio · v_d).
    assert abs(s / ratio - (np.hypot(*(meet - p_d[0])) - reach)) <= 1e-8 * max(1.0, s / ratio)
    before = p_a + 0.5 * s * u[0]                      # half-way, the attacker is there first
    assert 0.5 * s / ratio < np.hypot(*(before - p_d[0])) - reach + 1e-9


def test_a_defender_straight_ahead_meets_the_attacker_where_their_times_agree():
    # Attacker at 0 running +x at v_a = 0.5 v_d towards a defender 3 m ahead: they meet at s with s/0.5 = 3 − s.
    s = defender_reach(np.zeros(2), np.array([[1.0, 0.0]]), np.array([[3.0, 0.0]]), np.array([0.5]), 0.0)
    np.testing.assert_allclose(s, [[1.0]], atol=1e-12)


def test_an_obstacle_blocks_a_ray_at_its_surface_and_no_other():
    rays = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0]])
    blocked = obstacle_block(np.zeros(2), rays, np.array([[5.0, 0.0]]), np.array([1.0]))
    np.testing.assert_allclose(blocked, [4.0, np.inf, np.inf])


def test_the_edge_is_the_nearest_wall_along_each_ray():
    rays = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, -1.0], [np.sqrt(0.5), np.sqrt(0.5)]])
    edge = edge_distance(np.array([2.0, 5.0]), rays, (0.0, 0.0, 20.0, 10.0))
    np.testing.assert_allclose(edge, [18.0, 2.0, 5.0, 5.0 * np.sqrt(2)])
    assert np.all(np.isinf(edge_distance(np.zeros(2), rays, None)))


def test_the_attacker_escapes_along_the_rays_nobody_closes_before_the_edge():
    # Attacker 2 m from the left wall, a defender 1 m to its left: it cannot get out that way, but can to the right.
    rays = ray_directions(4)                           # +x, +y, −x, −y
    region = dominance(np.array([2.0, 10.0]), np.array([[1.0, 10.0]]), np.array([0.08]), 0.04, np.empty((0, 2)),
                       np.empty(0), (0.0, 0.0, 20.0, 20.0), rays=rays)
    assert not region.escapes[2] and region.defended[2] < 1.0
    far = dominance(np.array([2.0, 10.0]), np.array([[19.0, 10.0]]), np.array([0.08]), 0.04, np.empty((0, 2)),
                    np.empty(0), (0.0, 0.0, 20.0, 20.0), rays=rays)
    assert far.escapes[2]

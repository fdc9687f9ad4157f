"""The safety-distance filter keeps an approaching defender out of R_safe (mpc_hunt/world/safety.py)."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from mpc_hunt.world.geometry import norm
from mpc_hunt.world.safety import keep_safety_distance
from strategies import FAST, angles, floats, polar

T, SPEED, R_SAFE = 0.1, 0.08, 0.1
CENTRES = np.array([[0.0, 0.0], [1.3, 0.2]])     # surfaces 0.2 m apart: both safety distances touch
RADII = np.array([0.5, 0.6])

velocities = st.tuples(floats(min_value=0.0, max_value=SPEED), angles).map(lambda s: polar(*s))


def _clearances(p: np.ndarray) -> np.ndarray:
    return norm(p - CENTRES) - RADII


@FAST
@given(angles, floats(min_value=0.0, max_value=0.3), velocities)
def test_a_step_that_starts_outside_r_safe_never_ends_inside(angle, beyond, v):
    p = CENTRES[0] + polar(RADII[0] + R_SAFE + beyond, angle)
    if np.any(_clearances(p) < R_SAFE):       # inside the other obstacle's safety distance: not this test's start
        return
    out = keep_safety_distance(p, v, CENTRES, RADII, R_SAFE, T, SPEED)
    assert np.all(_clearances(p + T * out) >= R_SAFE - 1e-12)
    assert norm(out) <= SPEED + 1e-12
    if np.all(_clearances(p + T * v) >= R_SAFE):
        assert out is v                        # a step that keeps R_safe is left as it is


@FAST
@given(angles, floats(min_value=0.0, max_value=0.1), velocities)
def test_a_defender_already_inside_r_safe_never_comes_closer(angle, depth, v):
    p = CENTRES[0] + polar(RADII[0] + depth, angle)
    now = _clearances(p)
    out = keep_safety_distance(p, v, CENTRES, RADII, R_SAFE, T, SPEED)
    assert np.all(_clearances(p + T * out) >= np.minimum(R_SAFE, now) - 1e-12)


def test_far_from_obstacles_the_command_is_untouched():
    p, v = np.array([5.0, 5.0]), np.array([-SPEED, 0.0])
    assert keep_safety_distance(p, v, CENTRES, RADII, R_SAFE, T, SPEED) is v
    assert keep_safety_distance(p, v, np.empty((0, 2)), np.empty(0), R_SAFE, T, SPEED) is v


def test_heading_into_r_safe_the_defender_slides_along_the_obstacle():
    p = np.array([-(RADII[0] + R_SAFE), 0.0])                 # on R_safe, left of the first obstacle
    v = np.array([SPEED * 0.6, SPEED * 0.8])                  # inwards and up
    out = keep_safety_distance(p, v, CENTRES[:1], RADII[:1], R_SAFE, T, SPEED)
    assert abs(out[0]) < 1e-10 and out[1] == v[1]             # the inward part goes, the sideways part stays
    assert _clearances(p + T * out)[0] >= R_SAFE

"""Tests of the artificial potential field (mpc_hunt/world/field.py, docs/model.md, E1, E2, E6)."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt.world import packed
from mpc_hunt.world.attacker import resultant_of
from mpc_hunt.world.field import FIELD_FLOOR, nominal_intent, obstacle_repulsion, repulsion

FAST = settings(deadline=None, max_examples=150)
# Finite floats without subnormals (whose products underflow and defeat relative tolerances).
floats = functools.partial(st.floats, allow_nan=False, allow_infinity=False, allow_subnormal=False)

angles = floats(min_value=-math.pi, max_value=math.pi).map(lambda x: round(x, 12))
radii = floats(min_value=0.1, max_value=10.0)
etas = floats(min_value=0.01, max_value=10.0)
# Rounded so that no subnormal coordinates (underflowing norms) are generated.
coords = floats(min_value=-50.0, max_value=50.0, allow_nan=False, allow_infinity=False).map(
    lambda x: round(x, 9))
points = st.tuples(coords, coords).map(np.array)


def polar(length: float, angle: float) -> np.ndarray:
    return np.array([length * math.cos(angle), length * math.sin(angle)])


def expected_magnitude(d: float, radius: float, eta: float) -> float:
    """|H| = η (R³/|r|³ − 1) |r| inside R, written out independently of the module."""
    return eta * (radius**3 / d**3 - 1.0) * d if d < radius else 0.0


# --- repulsion H (Eq. 2, docs/model.md, E1) ----------------------------------------------------

@FAST
@given(radius=radii, eta=etas, frac=floats(min_value=0.01, max_value=0.999), angle=angles)
def test_repulsion_points_along_r_inside_radius(radius, eta, frac, angle):
    r = polar(frac * radius, angle)
    h = repulsion(r, radius, eta)
    assert h.shape == (2,)
    # Along r (away from the source when r = p_target - p_source): positive dot, zero cross product.
    assert float(h @ r) > 0.0
    cross = h[0] * r[1] - h[1] * r[0]
    assert abs(cross) <= 1e-9 * np.linalg.norm(h) * np.linalg.norm(r)


@FAST
@given(radius=radii, eta=etas, excess=floats(min_value=1e-6, max_value=100.0), angle=angles)
def test_repulsion_is_zero_outside_radius(radius, eta, excess, angle):
    r = polar(radius * (1.0 + excess), angle)
    np.testing.assert_array_equal(repulsion(r, radius, eta), np.zeros(2))


@pytest.mark.parametrize("r, radius", [([1.0, 0.0], 1.0), ([0.0, -2.0], 2.0), ([3.0, 4.0], 5.0)])
def test_repulsion_is_zero_exactly_at_radius(r, radius):
    np.testing.assert_array_equal(repulsion(np.array(r), radius, 1.0), np.zeros(2))


@pytest.mark.parametrize("radius, eta", [(1.0, 1.0), (2.5, 0.3)])
def test_repulsion_is_continuous_at_radius(radius, eta):
    # Values just inside R tend to 0 (no jump at |r| = R): |H| ≈ 3 η R ε for |r| = R (1 − ε).
    mags = []
    for eps in (1e-2, 1e-4, 1e-6, 1e-8):
        m = float(np.linalg.norm(repulsion(np.array([radius * (1 - eps), 0.0]), radius, eta)))
        assert 0.0 < m <= 4.0 * eta * radius * eps
        mags.append(m)
    assert mags == sorted(mags, reverse=True)


@FAST
@given(radius=radii, eta=etas, frac=floats(min_value=0.0, max_value=1.0), angle=angles)
def test_repulsion_magnitude_matches_formula(radius, eta, frac, angle):
    r = polar(FIELD_FLOOR * 1.001 + frac * (0.9999 * radius - FIELD_FLOOR * 1.001), angle)
    d = math.hypot(r[0], r[1])
    got = float(np.linalg.norm(repulsion(r, radius, eta)))
    assert math.isclose(got, expected_magnitude(d, radius, eta), rel_tol=1e-9)


@FAST
@given(radius=radii, eta=etas,
       f1=floats(min_value=0.0, max_value=1.0), f2=floats(min_value=0.0, max_value=1.0),
       a1=angles, a2=angles)
def test_repulsion_magnitude_decreases_with_distance(radius, eta, f1, f2, a1, a2):
    lo, hi = sorted((f1, f2))
    floor = max(FIELD_FLOOR, 1e-3 * radius)
    d1 = floor + lo * (0.999 * radius - floor)
    d2 = floor + hi * (0.999 * radius - floor)
    if d2 - d1 < 1e-9 * radius:
        return
    m1 = float(np.linalg.norm(repulsion(polar(d1, a1), radius, eta)))
    m2 = float(np.linalg.norm(repulsion(polar(d2, a2), radius, eta)))
    assert m1 > m2 > 0.0


@FAST
@given(radius=radii, eta=etas, k=floats(min_value=0.0, max_value=10.0),
       frac=floats(min_value=0.0, max_value=1.5), angle=angles)
def test_repulsion_is_linear_in_eta(radius, eta, k, frac, angle):
    r = polar(frac * radius, angle)
    np.testing.assert_allclose(repulsion(r, radius, k * eta), k * repulsion(r, radius, eta),
                               rtol=1e-12, atol=0)


def test_repulsion_is_finite_at_and_near_zero():
    radius, eta = 1.0, 1.0
    cap = eta * radius**3 / FIELD_FLOOR**2  # the magnitude at the floor distance bounds everything
    for d in (0.0, 1e-300, 1e-12, 1e-6, FIELD_FLOOR / 2, FIELD_FLOOR):
        h = repulsion(np.array([d, 0.0]), radius, eta)
        assert np.all(np.isfinite(h))
        assert np.linalg.norm(h) <= cap
    assert np.all(np.isfinite(repulsion(np.zeros(2), radius, eta)))
    # Just at the floor the push is huge compared with any robot speed.
    assert np.linalg.norm(repulsion(np.array([FIELD_FLOOR, 0.0]), radius, eta)) > 1e5


@pytest.mark.parametrize("d", [1e-9, 1e-6, FIELD_FLOOR / 2])
def test_repulsion_below_floor_stays_at_least_floor_value(d):
    radius, eta = 1.0, 1.0
    at_floor = float(np.linalg.norm(repulsion(np.array([FIELD_FLOOR, 0.0]), radius, eta)))
    below = float(np.linalg.norm(repulsion(np.array([d, 0.0]), radius, eta)))
    assert below >= at_floor * (1 - 1e-12)


def test_repulsion_batches_over_leading_axes():
    rs = np.array([[[0.5, 0.0], [0.0, 2.0]], [[-0.2, 0.1], [0.9, -0.3]]])
    out = repulsion(rs, 1.0, 1.5)
    assert out.shape == rs.shape
    for idx in np.ndindex(rs.shape[:-1]):
        np.testing.assert_allclose(out[idx], repulsion(rs[idx], 1.0, 1.5), rtol=1e-15)
    np.testing.assert_allclose(out[0, 0], [1.5 * (8 - 1) * 0.5, 0.0])
    np.testing.assert_array_equal(out[0, 1], [0.0, 0.0])


# --- obstacles measured from the surface (docs/model.md, E2) -----------------------------------

def test_obstacle_of_radius_one_still_pushes_point_half_a_metre_from_its_surface():
    centres, rad = np.array([[0.0, 0.0]]), np.array([1.0])
    p = np.array([1.5, 0.0])
    push = obstacle_repulsion(p, centres, rad, 1.0, 1.0)
    # Offset from the surface is 0.5: H = 1 * (1/0.125 - 1) * 0.5 = 3.5 along +x.
    np.testing.assert_allclose(push, [3.5, 0.0], rtol=1e-12)
    # Measured from the centre, the same point would feel nothing (|r| = 1.5 ≥ R = 1).
    np.testing.assert_array_equal(repulsion(p - centres[0], 1.0, 1.0), np.zeros(2))


def test_obstacle_beyond_protective_distance_from_surface_does_not_push():
    centres, rad = np.array([[2.0, 3.0]]), np.array([1.0])
    np.testing.assert_array_equal(obstacle_repulsion(np.array([2.0, 5.5]), centres, rad, 1.0, 1.0),
                                  np.zeros(2))
    # ... but a larger protective distance reaches it.
    assert obstacle_repulsion(np.array([2.0, 5.5]), centres, rad, 2.0, 1.0)[1] > 0


@FAST
@given(centre=points, radius=floats(min_value=0.05, max_value=5.0),
       gap=floats(min_value=2 * FIELD_FLOOR, max_value=20.0), angle=angles)
def test_an_obstacle_field_is_measured_from_its_surface_outward(centre, radius, gap, angle):
    # H of the offset from the surface point nearest p: |offset| = |p − c| − r, along p − c.
    p = centre + polar(radius + gap, angle)
    v = p - centre
    dc = np.linalg.norm(v)
    offset = v / dc * (dc - radius)
    np.testing.assert_allclose(obstacle_repulsion(p, centre[None, :], np.array([radius]), 3.0, 1.0),
                               repulsion(offset, 3.0, 1.0), rtol=1e-9, atol=1e-12)


@FAST
@given(centre=points, radius=floats(min_value=0.05, max_value=5.0),
       depth=floats(min_value=0.01, max_value=1.0), angle=angles,
       protect=floats(min_value=0.1, max_value=3.0))
def test_obstacle_pushes_outward_from_inside(centre, radius, depth, angle, protect):
    # A point strictly inside the obstacle (not at its centre) is pushed out along centre -> point.
    p = centre + polar(radius * (1.0 - depth * 0.99), angle)
    outward = p - centre
    push = obstacle_repulsion(p, centre[None, :], np.array([radius]), protect, 1.0)
    assert np.all(np.isfinite(push))
    assert float(push @ outward) > 0
    cross = push[0] * outward[1] - push[1] * outward[0]
    assert abs(cross) <= 1e-9 * np.linalg.norm(push) * np.linalg.norm(outward)
    # Offset length is the floor: the push is the (huge) floor value of H.
    np.testing.assert_allclose(push, repulsion(FIELD_FLOOR * outward / np.linalg.norm(outward), protect, 1.0),
                               rtol=1e-9)


def test_obstacle_repulsion_sums_obstacles_and_handles_none():
    p = np.array([0.0, 0.0])
    # Two identical obstacles placed symmetrically cancel.
    sym = obstacle_repulsion(p, np.array([[1.2, 0.0], [-1.2, 0.0]]), np.array([0.5, 0.5]), 1.0, 1.0)
    np.testing.assert_allclose(sym, [0.0, 0.0], atol=1e-12)
    # Sum of the individual pushes.
    centres = np.array([[1.2, 0.0], [0.0, 1.6]])
    rad = np.array([0.5, 1.0])
    total = obstacle_repulsion(p, centres, rad, 1.0, 1.0)
    parts = sum(obstacle_repulsion(p, centres[i:i + 1], rad[i:i + 1], 1.0, 1.0) for i in range(2))
    np.testing.assert_allclose(total, parts, rtol=1e-12)
    # Hand values: first obstacle's surface is 0.7 m away along -x from p.
    h1 = (1 / 0.7**3 - 1) * 0.7
    h2 = (1 / 0.6**3 - 1) * 0.6
    np.testing.assert_allclose(total, [-h1, -h2], rtol=1e-12)
    np.testing.assert_array_equal(obstacle_repulsion(p, np.zeros((0, 2)), np.zeros(0), 1.0, 1.0),
                                  np.zeros(2))


# --- nominal intent (docs/model.md, E6) --------------------------------------------------------

def test_nominal_intent_caps_paper_vector_keeping_direction():
    v = nominal_intent(np.array([0.2, -0.2]), 0.03)
    np.testing.assert_allclose(v, 0.03 * np.array([1.0, -1.0]) / math.sqrt(2), rtol=1e-12)
    assert math.isclose(float(np.linalg.norm(v)), 0.03, rel_tol=1e-12)


@FAST
@given(v=points, cap=floats(min_value=1e-3, max_value=10.0))
def test_nominal_intent_never_exceeds_cap_and_keeps_direction(v, cap):
    out = nominal_intent(v, cap)
    n_in, n_out = float(np.linalg.norm(v)), float(np.linalg.norm(out))
    assert n_out <= cap * (1 + 1e-12)
    if n_in <= cap:
        np.testing.assert_array_equal(out, v)
    else:
        assert math.isclose(n_out, cap, rel_tol=1e-9)
        np.testing.assert_allclose(out / n_out, v / n_in, atol=1e-12)


# --- the attacker's resultant (Eq. 9 with its nominal intent) ----------------------------------

def _resultant(p_a, defenders, centres, rad, *, nominal=(0.01, 0.0), k_d=1.0, k_o=1.0,
               perception=1.0, protect=1.0, eta=1.0):
    prm = np.zeros(packed.SIZE)
    prm[[packed.NOMINAL_X, packed.NOMINAL_Y]] = nominal
    prm[packed.K_D], prm[packed.K_O], prm[packed.R_AGG], prm[packed.PROTECTIVE], prm[packed.ETA] = (
        k_d, k_o, perception, protect, eta)
    return np.array(resultant_of(np.asarray(p_a, float), np.asarray(defenders, float).reshape(-1, 2),
                                 np.asarray(centres, float).reshape(-1, 2), np.asarray(rad, float), prm))


def test_resultant_is_nominal_when_nothing_is_near():
    out = _resultant([3.0, 4.0], [[10.0, 10.0], [3.0, 5.5]], [[0.0, 0.0]], [1.0],
                     nominal=[0.02, -0.01])
    np.testing.assert_array_equal(out, [0.02, -0.01])
    out = _resultant([3.0, 4.0], np.zeros((0, 2)), np.zeros((0, 2)), [], nominal=[0.02, -0.01])
    np.testing.assert_array_equal(out, [0.02, -0.01])


def test_resultant_adds_weighted_defender_push():
    # Defender 0.5 m to the left: H = (1/0.125 - 1) * 0.5 = 3.5 to the right, times k_d = 2.
    out = _resultant([3.0, 4.0], [[2.5, 4.0]], np.zeros((0, 2)), [], nominal=[0.01, 0.02], k_d=2.0)
    np.testing.assert_allclose(out, [0.01 + 7.0, 0.02], rtol=1e-12)
    out = _resultant([3.0, 4.0], [[2.5, 4.0]], np.zeros((0, 2)), [], nominal=[0.01, 0.02], k_d=0.0)
    np.testing.assert_allclose(out, [0.01, 0.02])


def test_resultant_adds_weighted_obstacle_push_measured_from_surface():
    # Obstacle of radius 1 centred 1.5 m above: surface 0.5 m away, push 3.5 downward, times k_o.
    out = _resultant([3.0, 4.0], np.zeros((0, 2)), [[3.0, 5.5]], [1.0], nominal=[0.0, 0.0], k_o=0.5)
    np.testing.assert_allclose(out, [0.0, -1.75], rtol=1e-12)


def test_resultant_uses_perception_radius_for_defenders_and_protective_distance_for_obstacles():
    # Defender 1.2 m away: outside R_agg = 1, inside R_agg = 1.5.
    assert np.allclose(_resultant([0, 0], [[1.2, 0]], np.zeros((0, 2)), [], nominal=[0, 0]), 0)
    assert _resultant([0, 0], [[1.2, 0]], np.zeros((0, 2)), [], nominal=[0, 0],
                      perception=1.5)[0] < 0
    # Obstacle surface 1.2 m away: only a protective distance above 1.2 reaches it.
    assert np.allclose(_resultant([0, 0], np.zeros((0, 2)), [[0, 2.2]], [1.0], nominal=[0, 0],
                                  perception=5.0), 0)
    assert _resultant([0, 0], np.zeros((0, 2)), [[0, 2.2]], [1.0], nominal=[0, 0],
                      protect=1.5)[1] < 0


def test_resultant_combines_all_three_terms():
    p_a = [0.0, 0.0]
    defenders = [[0.5, 0.0], [0.0, -0.8], [5.0, 5.0]]
    centres, rad = [[-1.6, 0.0]], [1.0]
    k_d, k_o, nominal = 0.7, 1.3, [0.01, -0.02]
    hd1 = (1 / 0.5**3 - 1) * 0.5   # pushes -x
    hd2 = (1 / 0.8**3 - 1) * 0.8   # pushes +y
    ho = (1 / 0.6**3 - 1) * 0.6    # surface 0.6 m to the left: pushes +x
    expected = np.array([0.01 - k_d * hd1 + k_o * ho, -0.02 + k_d * hd2])
    out = _resultant(p_a, defenders, centres, rad, nominal=nominal, k_d=k_d, k_o=k_o)
    np.testing.assert_allclose(out, expected, rtol=1e-12)


@FAST
@given(p_a=points, offsets=st.lists(st.tuples(floats(-2, 2), floats(-2, 2)), max_size=4),
       k_d=floats(0, 5), k_o=floats(0, 5), nominal=st.tuples(floats(-1, 1), floats(-1, 1)),
       obs=st.lists(st.tuples(floats(-3, 3), floats(-3, 3), floats(0.1, 1.0)), max_size=3))
def test_resultant_matches_loop_over_sources(p_a, offsets, k_d, k_o, nominal, obs):
    defenders = np.array([p_a + np.array(o) for o in offsets]).reshape(-1, 2)
    centres = np.array([p_a + np.array(o[:2]) for o in obs]).reshape(-1, 2)
    rad = np.array([o[2] for o in obs])
    expected = np.array(nominal, dtype=float)
    for d in defenders:
        expected = expected + k_d * repulsion(p_a - d, 1.0, 1.0)
    for c, rr in zip(centres, rad):
        expected = expected + k_o * obstacle_repulsion(p_a, c[None, :], np.array([rr]), 1.0, 1.0)
    out = _resultant(p_a, defenders, centres, rad, nominal=nominal, k_d=k_d, k_o=k_o)
    np.testing.assert_allclose(out, expected, rtol=1e-9, atol=1e-9)

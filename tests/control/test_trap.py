"""The trap controller's reference (mpc_hunt/control/trap.py): the attacker's dominance region shrunk, edge first."""

from __future__ import annotations

import numpy as np

from mpc_hunt.control.controller import Observation
from mpc_hunt.control.spec import make_controller
from mpc_hunt.control.trap import Trap
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario

N = 10


def _world(defenders, start, obstacles=()) -> Scenario:
    return Scenario(name="trap", defenders=tuple(Defender(start=p, max_speed=0.08) for p in defenders),
                    attacker=Attacker(start=start, nominal_velocity=(0.0, 0.04), max_speed=0.04,
                                      perception_radius=1.0),
                    obstacles=obstacles, hunt=HuntParameters(), arena=(0.0, 0.0, 20.0, 20.0))


def _headings(s: Scenario) -> np.ndarray:
    return Trap(s, N).headings(np.array(s.attacker.start), s.defender_starts, s.defender_max_speeds)


def test_the_defender_nearest_an_open_edge_closes_it_before_it_closes_in():
    # The attacker 2.5 m from the left edge, one defender 3 m above it, the rest far right: the way out is left,
    # and that defender cuts it (down and to the left), not straight at the attacker.
    s = _world([(2.5, 13.0), (15.0, 5.0), (15.0, 15.0), (18.0, 10.0)], (2.5, 10.0))
    first = _headings(s)[0]
    assert first[0] < -0.2 and first[1] < -0.8


def test_an_obstacle_closes_the_directions_behind_it_so_the_defenders_cover_the_others():
    # Two defenders left and right of the attacker, an obstacle just below it: they bend upwards, where it could
    # still go; with the obstacle gone the picture is symmetric and they come straight in.
    obstacle = Obstacle(centre=(10.0, 8.2), radius=1.0)
    bent = _headings(_world([(7.0, 10.0), (13.0, 10.0)], (10.0, 10.0), (obstacle,)))
    assert np.all(bent[:, 1] > 0.08)
    straight = _headings(_world([(7.0, 10.0), (13.0, 10.0)], (10.0, 10.0)))
    assert np.all(np.abs(straight[:, 1]) < 1e-3)


def test_shrinking_the_places_run_at_top_speed_down_the_gradient():
    s = _world([(2.5, 13.0), (15.0, 5.0), (15.0, 15.0), (18.0, 10.0)], (2.5, 10.0))
    trap = Trap(s, N)
    reference = trap.reference(Observation(0.0, np.array(s.attacker.start), None, s.defender_starts))
    assert trap.phase == "shrink"
    steps = norm(np.diff(np.concatenate([s.defender_starts[None], reference.defenders]), axis=0))
    np.testing.assert_allclose(steps, 0.08 * 0.1, atol=1e-12)


def test_once_enclosed_with_no_way_out_the_ring_closes_with_the_members_centroid_on_the_attacker():
    ring = [(10.0 + 2.0 * np.cos(a), 10.0 + 2.0 * np.sin(a)) for a in np.radians([90.0, 210.0, 330.0])]
    s = _world(ring, (10.0, 10.0))
    trap = Trap(s, N)
    reference = trap.reference(Observation(0.0, np.array([10.0, 10.0]), None, s.defender_starts))
    assert trap.phase == "close"
    np.testing.assert_allclose(reference.defenders.mean(axis=1), np.full((N, 2), 10.0), atol=1e-12)
    radii = norm(reference.defenders - 10.0)
    np.testing.assert_allclose(radii[-1], 2.0 - 0.08 * N * 0.1, atol=1e-9)     # the nearest mover's distance, at top speed


def test_an_attacker_enclosed_near_the_edge_is_closed_on_once_its_region_no_longer_reaches_the_edge():
    # The attacker 1.05 m from the right edge, four movers on a ring of 0.95 m round it (one between it and the
    # edge): no point of the edge is the attacker's before a defender's, so the ring closes. (A region required
    # to stay a metre inside the edge could not be closed here: the team stood still on this ring for 120 s.)
    p_a = np.array([18.95, 13.46])
    ring = [tuple(p_a + 0.95 * np.array([np.cos(a), np.sin(a)])) for a in np.radians([-63.0, -153.0, 27.0, 117.0])]
    s = _world(ring, tuple(p_a))
    trap = Trap(s, N)
    reference = trap.reference(Observation(0.0, p_a, None, s.defender_starts))
    assert trap.phase == "close"
    assert np.all(norm(reference.defenders[-1] - p_a) < 0.95 - 0.05)


def test_the_trap_controller_plans_every_defender_inside_the_time_step():
    s = _world([(2.5, 13.0), (15.0, 5.0), (15.0, 15.0), (18.0, 10.0)], (2.5, 10.0))
    controller = make_controller("trap", s, formulation="rti", backend="hpipm", horizon=N)
    command = controller.command(Observation(0.0, np.array(s.attacker.start), None, s.defender_starts))
    assert command.solution.success and command.capture_stage.all()
    assert np.all(norm(command.velocities) <= 0.08 + 1e-9)
    assert controller.describe()["controller"] == "trap"


def test_movers_near_the_attacker_before_the_ring_can_close_spread_round_it():
    # Three defenders 1 m from the attacker, all on one side (not enclosing): each heads for its place in an even
    # spread on the 2.5 m circle (NEAR R_hunt), going round, rather than pressing in from that side.
    side = [(10.0 + np.cos(a), 10.0 + np.sin(a)) for a in np.radians([-20.0, 0.0, 20.0])]
    s = _world(side, (10.0, 10.0))
    trap = Trap(s, N)
    reference = trap.reference(Observation(0.0, np.array([10.0, 10.0]), None, s.defender_starts))
    assert trap.phase == "shrink"
    last = reference.defenders[-1] - 10.0
    np.testing.assert_allclose(norm(last), 1.08, atol=1e-3)                 # outwards at top speed, to the circle
    turned = np.degrees(np.arctan2(last[:, 1], last[:, 0])) - np.array([-20.0, 0.0, 20.0])
    assert turned[0] < -0.1 and abs(turned[1]) < 1e-6 and turned[2] > 0.1  # the outer two go round, apart


def test_near_the_arena_edge_the_spread_fits_inside_it_with_a_place_on_the_edge_side():
    # The attacker 0.8 m from the left edge, three movers 0.7 m from it to its right (not enclosing it): the spread's
    # circle shrinks to the edge's distance less R_safe, so that no place is pushed onto the edge and one mover goes
    # between the attacker and the way out (on the 2.5 m circle that place would lie beyond the edge).
    p_a = np.array([0.8, 10.0])
    side = [tuple(p_a + 0.7 * np.array([np.cos(a), np.sin(a)])) for a in np.radians([-80.0, 0.0, 80.0])]
    s = _world(side, tuple(p_a))
    trap = Trap(s, 200)                       # 20 s: long enough for every mover to reach its place
    reference = trap.reference(Observation(0.0, p_a, None, s.defender_starts))
    assert trap.phase == "shrink"
    last = reference.defenders[-1]
    radius = p_a[0] - s.hunt.safety_distance
    np.testing.assert_allclose(norm(last - p_a), radius, atol=1e-9)
    assert np.min(last[:, 0]) < p_a[0] - 0.5 * radius        # a place between the attacker and the edge


def _herding(defenders, p_a, velocity, obstacle, phase="herd", horizon=N):
    """A two-robot trap herding towards ``obstacle``, the attacker seen moving at ``velocity`` one step ago."""
    s = _world(defenders, tuple(p_a), (obstacle,))
    trap = Trap(s, horizon)
    trap.phase = phase
    p_a = np.asarray(p_a, dtype=float)
    previous = p_a - np.asarray(velocity, dtype=float) * s.hunt.time_step
    reference = trap.reference(Observation(0.0, p_a, previous, s.defender_starts))
    return s, trap, reference


def test_the_herd_pushes_past_the_attackers_drift_towards_the_obstacle():
    # The obstacle 4 m north of the attacker, which drifts east: the movers take places behind it turned past that
    # drift (their mean bearing from it south-east, so they push north-west); seen standing still, due south.
    north = Obstacle(centre=(10.0, 15.0), radius=1.0)
    movers = [(10.0 + 0.25 * np.cos(a), 10.0 + 0.25 * np.sin(a)) for a in np.radians([-140.0, -40.0])]

    def behind(velocity):
        _, trap, reference = _herding(movers, (10.0, 10.0), velocity, north, horizon=400)
        assert trap.phase == "herd"
        offsets = reference.defenders[-1] - reference.attacker[-1]
        mean = (offsets / norm(offsets)[:, None]).sum(axis=0)
        return np.degrees(np.arctan2(mean[1], mean[0]))

    np.testing.assert_allclose(behind((0.0, 0.0)), -90.0, atol=1e-6)
    np.testing.assert_allclose(behind((0.04, 0.0)), -30.0, atol=1e-6)      # turned the most the herd turns, 60°


def test_a_far_mover_herds_towards_where_it_meets_the_attacker():
    # A mover 8 m south of an attacker running east: its places lead the attacker (its intercept), not the spot
    # where it stands now.
    north = Obstacle(centre=(10.0, 15.0), radius=1.0)
    s, _, reference = _herding([(10.0, 2.0), (2.0, 2.0)], (10.0, 10.0), (0.04, 0.0), north)
    step = reference.defenders[0, 0] - np.array([10.0, 2.0])
    assert step[0] > 0.2 * np.hypot(*step)


def test_closing_on_an_obstacle_holds_within_its_band_and_herds_beyond_it():
    # The obstacle's surface 0.85 m from the attacker (R_hunt + 0.35 m): herding stays herding, closing stays
    # closing (inside twice the band); at 0.65 m herding turns to closing.
    movers = [(10.0 + 0.3 * np.cos(a), 10.0 + 0.3 * np.sin(a)) for a in np.radians([-150.0, -30.0])]
    for gap, before, after in ((0.85, "herd", "herd"), (0.85, "close", "close"), (0.65, "herd", "close"),
                               (1.1, "close", "herd")):
        obstacle = Obstacle(centre=(10.0, 10.0 + gap + 1.0), radius=1.0)
        _, trap, _ = _herding(movers, (10.0, 10.0), (0.0, 0.0), obstacle, phase=before)
        assert trap.phase == after, (gap, before)


def test_closing_on_an_obstacle_the_movers_keep_pushing_within_the_centre_tolerance():
    # Two movers closing on an attacker 0.7 m from an obstacle's surface (inside the band that counts it): the
    # members' centroid (the movers and the obstacle's nearest point) is moved only to within half the centre
    # tolerance of the attacker, so the movers stand nearer it, behind, than an exact centring would put them
    # (0.41 m).
    obstacle = Obstacle(centre=(10.0, 11.7), radius=1.0)
    movers = [(10.0 + 0.3 * np.cos(a), 10.0 + 0.3 * np.sin(a)) for a in np.radians([-150.0, -30.0])]
    s, trap, reference = _herding(movers, (10.0, 10.0), (0.0, 0.0), obstacle, phase="close")
    assert trap.phase == "close"
    last = reference.defenders[-1]
    centroid = (last.sum(axis=0) + np.array([10.0, 10.7])) / 3
    np.testing.assert_allclose(norm(centroid - 10.0), 0.5 * s.hunt.centre_tolerance, atol=1e-9)
    assert np.all(norm(last - 10.0) < 0.3)


def test_closing_on_an_obstacle_still_out_of_reach_the_ring_presses_nearer_than_half_r_hunt():
    # Two movers 0.3 m from an attacker whose nearest obstacle surface is 0.55 m away (beyond R_hunt: the success
    # test cannot hold yet): over 2 s the ring closes towards the capture problem's least attacker distance plus
    # the press clearance, 0.15 m (0.157 m: the centring takes it back to half the centre tolerance), not to
    # R_hunt / 2. With the surface 0.3 m away (inside PRESS_FROM R_hunt) it stops at R_hunt / 2.
    movers = [(10.0 + 0.3 * np.cos(a), 10.0 + 0.3 * np.sin(a)) for a in np.radians([-150.0, -30.0])]
    for gap in (0.55, 0.3):
        obstacle = Obstacle(centre=(10.0, 10.0 + gap + 1.0), radius=1.0)
        s, trap, reference = _herding(movers, (10.0, 10.0), (0.0, 0.0), obstacle, phase="close", horizon=20)
        assert trap.phase == "close"
        distances = norm(reference.defenders[-1] - 10.0)
        if gap > 0.5:
            assert np.all((distances > 0.15) & (distances < 0.16))
        else:
            np.testing.assert_allclose(distances, 0.5 * s.hunt.hunt_radius, atol=1e-9)

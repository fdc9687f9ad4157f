"""Attacker behaviours (mpc_hunt/world/behaviours/): each rule decides the move on a state built for it."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt.errors import ScenarioError
from mpc_hunt.world import attacker as apf
from mpc_hunt.world.behaviours import BEHAVIOURS, make_behaviour
from mpc_hunt.world.packed import DEFAULT_SENSING
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario
from mpc_hunt.world.scenario_io import dumps_scenario, loads_scenario

V_A = 0.03
CENTRE = np.array([10.0, 10.0])


def _world(behaviour: str, *, intent=(V_A, 0.0), obstacles=(), arena=(0.0, 0.0, 20.0, 20.0), **attacker) -> Scenario:
    """An attacker at (10, 10) heading +x at 0.03 m/s; the defenders' starts do not matter to a behaviour."""
    return Scenario(name="behaviour", defenders=(Defender(start=(1.0, 1.0), max_speed=0.08),),
                    attacker=Attacker(start=tuple(CENTRE), nominal_velocity=intent, max_speed=V_A,
                                      perception_radius=1.0, behaviour=behaviour, **attacker),
                    obstacles=obstacles, hunt=HuntParameters(), arena=arena)


def _velocity(behaviour: str, defenders, **options) -> np.ndarray:
    s = _world(behaviour, **options)
    return make_behaviour(s, np.random.default_rng(0)).velocity(CENTRE, np.array(defenders, dtype=float))


def _bearing(v: np.ndarray) -> float:
    return math.degrees(math.atan2(v[1], v[0]))


def test_flee_runs_at_full_speed_away_weighted_by_inverse_square_distance():
    # Defenders 1 m east and 2 m north: Σ r/|r|³ = (−1, 0)/1 + (0, −2)/8 = (−1, −0.25).
    v = _velocity("flee", [[11.0, 10.0], [10.0, 12.0]])
    assert norm(v) == pytest.approx(V_A, rel=1e-12)
    np.testing.assert_allclose(v / norm(v), np.array([-1.0, -0.25]) / math.hypot(1.0, 0.25), atol=1e-12)


def test_gap_runs_along_the_widest_gap_unless_its_intent_lies_inside_it_with_the_margin():
    three = [[11.0, 10.0], [10.0, 11.0], [9.0, 10.0]]          # east, north, west: the widest gap is the south half
    assert _bearing(_velocity("gap", three)) == pytest.approx(-90.0, abs=1e-9)     # intent east: into a defender
    inside = (V_A * math.cos(math.radians(-120)), V_A * math.sin(math.radians(-120)))   # 60° into the gap
    assert _bearing(_velocity("gap", three, intent=inside)) == pytest.approx(-120.0, abs=1e-9)
    edge = (V_A * math.cos(math.radians(-160)), V_A * math.sin(math.radians(-160)))     # 20° in: under the margin
    assert _bearing(_velocity("gap", three, intent=edge)) == pytest.approx(-90.0, abs=1e-9)
    assert norm(_velocity("gap", three)) == pytest.approx(V_A, rel=1e-12)


def test_voronoi_heads_for_its_cells_centroid_bounded_by_the_arena():
    # One defender 1 m east: the cell is the 6 m sensing square cut at x = 10.5 and, by the arena, at y = 11:
    # [7, 10.5] × [7, 11], centroid (8.75, 9): the direction (−1.25, −1), not flee's (−1, 0).
    v = _velocity("voronoi", [[11.0, 10.0]], arena=(0.0, 0.0, 20.0, 11.0))
    np.testing.assert_allclose(v / norm(v), np.array([-1.25, -1.0]) / math.hypot(1.25, 1.0), atol=1e-12)
    assert norm(v) == pytest.approx(V_A, rel=1e-12)


def test_noisy_is_the_papers_attacker_plus_a_bounded_draw_from_the_passed_in_generator():
    defenders = np.array([[10.6, 10.0], [9.5, 10.5]])
    paper = apf.velocity(_world("apf"), CENTRE, defenders)
    still = _velocity("noisy", defenders, disturbance=0.0)
    np.testing.assert_array_equal(still, paper)
    s = _world("noisy", disturbance=0.5)
    draws = [make_behaviour(s, np.random.default_rng(k)).velocity(CENTRE, defenders) for k in range(50)]
    assert len({tuple(d) for d in draws}) == 50
    assert max(norm(d - paper) for d in draws) <= 0.5 * V_A + 1e-12      # the cap only shortens the sum
    again = make_behaviour(s, np.random.default_rng(3)).velocity(CENTRE, defenders)
    np.testing.assert_array_equal(again, draws[3])


def test_apf_is_the_papers_attacker():
    defenders = np.array([[10.6, 10.0], [9.5, 10.5]])
    np.testing.assert_array_equal(_velocity("apf", defenders), apf.velocity(_world("apf"), CENTRE, defenders))


@pytest.mark.parametrize("behaviour", sorted(BEHAVIOURS))
def test_with_nobody_sensed_every_behaviour_follows_the_papers_undisturbed_intent(behaviour):
    far = [[10.0 + DEFAULT_SENSING + 0.1, 10.0]]
    options = {"disturbance": 0.0} if behaviour == "noisy" else {}
    np.testing.assert_array_equal(_velocity(behaviour, far, **options),
                                  apf.velocity(_world("apf"), CENTRE, np.empty((0, 2))))


def test_the_sensing_radius_decides_who_is_sensed():
    near = [[12.0, 10.0]]                                       # 2 m east
    assert _velocity("flee", near)[0] < 0                       # within the default 3 m: flees west
    assert _velocity("flee", near, sensing_radius=1.5)[0] > 0  # beyond 1.5 m: keeps its intent east


@settings(deadline=None, max_examples=60)
@given(behaviour=st.sampled_from(sorted(BEHAVIOURS)),
       offsets=st.lists(st.tuples(st.floats(-4, 4), st.floats(-4, 4)), min_size=1, max_size=5),
       heading=st.floats(-math.pi, math.pi))
def test_every_behaviour_moves_at_most_v_a_and_never_steps_into_an_obstacle(behaviour, offsets, heading):
    # An obstacle whose surface is 1 mm ahead of the attacker along its intent.
    ahead = np.array([math.cos(heading), math.sin(heading)])
    obstacle = Obstacle(centre=tuple(CENTRE + 0.501 * ahead), radius=0.5)
    s = _world(behaviour, intent=tuple(V_A * ahead), obstacles=(obstacle,))
    defenders = CENTRE + np.array(offsets)
    defenders = defenders[norm(defenders - CENTRE) > 1e-3]
    v = make_behaviour(s, np.random.default_rng(0)).velocity(CENTRE, defenders)
    assert np.all(np.isfinite(v)) and norm(v) <= V_A * (1 + 1e-12)
    assert norm(CENTRE + s.hunt.time_step * v - np.array(obstacle.centre)) > obstacle.radius


def test_a_scenario_names_its_attackers_behaviour_and_parameters_in_toml():
    s = _world("gap", sensing_radius=2.5)
    again = loads_scenario(dumps_scenario(s))
    assert again == s and again.attacker.behaviour == "gap" and again.attacker.sensing_radius == 2.5
    assert _world("apf").attacker.behaviour == "apf"


@pytest.mark.parametrize("options, message", [
    ({"behaviour": "sneaky"}, "attacker.behaviour: unknown 'sneaky' (available: apf, flee, gap, voronoi, noisy, "
                                "learned, minimax, ppo)"),
    ({"behaviour": "apf", "sensing_radius": 2.0}, "attacker.sensing_radius: the apf attacker senses at its "
                                                  "perception_radius"),
    ({"behaviour": "gap", "sensing_radius": -1.0}, "attacker.sensing_radius: must be positive"),
    ({"behaviour": "gap", "disturbance": 0.5}, "attacker.disturbance: only the noisy attacker takes one"),
    ({"behaviour": "noisy", "disturbance": 1e9}, "attacker.disturbance: 1000000000.0 is beyond the limit"),
])
def test_a_bad_behaviour_or_parameter_names_the_field(options, message):
    behaviour = options.pop("behaviour")
    with pytest.raises(ScenarioError, match=f"^{message}".replace("(", r"\(").replace(")", r"\)")):
        _world(behaviour, **options)


def test_the_paper_scenarios_keep_the_papers_attacker():
    from mpc_hunt.world.scenario_io import builtin_names, builtin_scenario
    assert {builtin_scenario(n).attacker.behaviour for n in builtin_names()} == {"apf"}
    assert dataclasses.replace(builtin_scenario("paper-open").attacker, behaviour="flee").behaviour == "flee"


@settings(max_examples=300, deadline=None)
@given(clearance=st.floats(1e-3, 0.9), bearing=st.floats(0.0, 2 * math.pi), wish=st.floats(0.0, 2 * math.pi),
       speed=st.floats(0.001, 0.0792), radius=st.floats(0.3, 1.2))
def test_no_steered_evader_moves_towards_an_obstacle_within_0_9_m_of_its_surface(clearance, bearing, wish, speed,
                                                                                   radius):
    # The obstacles' field (Eq. 3, k_o = η = 1, 1 m protective distance) outweighs any wish of at most the sweeps'
    # fastest attacker (0.99 × 0.08 m/s) within 0.9 m of a surface, so flee, gap, voronoi, learned and minimax
    # (every behaviour built on `wished`) never come within R_hunt = 0.5 m of an obstacle: one can never be a member
    # of their hunting circle (docs/model.md, E13).
    from mpc_hunt.world.behaviours.base import wished
    s = dataclasses.replace(_world("gap", obstacles=(Obstacle(centre=(0.0, 0.0), radius=radius),)),
                            attacker=dataclasses.replace(_world("gap").attacker, max_speed=speed))
    outward = np.array([math.cos(bearing), math.sin(bearing)])
    p = (radius + clearance) * outward
    v = np.array(wished(p, speed * math.cos(wish), speed * math.sin(wish), s.obstacle_centres, s.obstacle_radii,
                        s.packed))
    assert float(v @ outward) >= -1e-12

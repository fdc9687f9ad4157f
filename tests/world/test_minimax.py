"""The minimax attacker (mpc_hunt/world/behaviours/minimax.py): its plan decides its move on constructed states."""

from __future__ import annotations

import numpy as np

from mpc_hunt.world.behaviours import make_behaviour
from mpc_hunt.world.behaviours.flee import flee_direction
from mpc_hunt.world.behaviours.minimax import best_heading
from mpc_hunt.world.reachable_set import obstacle_block
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario


def _world(defenders, start=(10.0, 10.0), obstacles=()) -> Scenario:
    return Scenario(name="minimax", defenders=tuple(Defender(start=p, max_speed=0.08) for p in defenders),
                    attacker=Attacker(start=start, nominal_velocity=(0.0, 0.04), max_speed=0.04,
                                      perception_radius=1.0, behaviour="minimax"),
                    obstacles=obstacles, hunt=HuntParameters(), arena=(0.0, 0.0, 20.0, 20.0))


def _move(scenario: Scenario) -> np.ndarray:
    behaviour = make_behaviour(scenario, np.random.default_rng(0))
    return behaviour.velocity(np.array(scenario.attacker.start), scenario.defender_starts)


def test_it_runs_for_the_edge_that_no_defender_can_close_not_away_from_the_nearest():
    # 3 m from the bottom edge, one defender 1.5 m below it: fleeing would go up (+y), 7+ m from the top edge;
    # the left edge, 3 m away, is open (the other defenders are far right), so minimax runs left.
    s = _world([(3.0, 1.5), (18.0, 3.0), (18.0, 17.0)], start=(3.0, 3.0))
    v = _move(s)
    assert v[0] < -0.035 and abs(v[1]) < 0.02
    away = flee_direction(np.array([3.0, 3.0]), np.array([[3.0, 1.5]]))
    assert away[1] > 0 and abs(away[0]) < 1e-12      # the flee rule's heading, for contrast


def test_with_every_edge_closed_it_takes_the_opening_the_defenders_close_last():
    # Defenders 1.5 m to its left, right and above, nobody below: every edge is 10 m away and closed (each
    # defender reaches any edge point long before the attacker), and the bottom one is closed last.
    s = _world([(8.5, 10.0), (11.5, 10.0), (10.0, 11.5)])
    heading = best_heading(s, np.array([10.0, 10.0]), s.defender_starts)
    np.testing.assert_allclose(heading, [0.0, -1.0], atol=1e-9)


def test_an_obstacle_before_the_edge_closes_that_way():
    # The open left edge is behind an obstacle: minimax does not plan through it.
    obstacle = Obstacle(centre=(1.5, 3.0), radius=1.0)
    s = _world([(3.0, 1.5), (18.0, 3.0), (18.0, 17.0)], start=(3.0, 3.0), obstacles=(obstacle,))
    heading = best_heading(s, np.array([3.0, 3.0]), s.defender_starts)
    assert heading[0] < 0 and np.isinf(obstacle_block(np.array([3.0, 3.0]), heading[None], s.obstacle_centres,
                                                      s.obstacle_radii)[0])
    open_field = best_heading(_world([(3.0, 1.5), (18.0, 3.0), (18.0, 17.0)], start=(3.0, 3.0)), np.array([3.0, 3.0]),
                              s.defender_starts)
    assert np.isfinite(obstacle_block(np.array([3.0, 3.0]), open_field[None], s.obstacle_centres, s.obstacle_radii)[0])


def test_with_nobody_sensed_it_follows_its_intent():
    s = _world([(19.0, 19.0)])
    np.testing.assert_allclose(_move(s), [0.0, 0.04], atol=1e-12)


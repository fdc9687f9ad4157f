"""The PPO agents' training environments (mpc_hunt/envs/learning.py) give the hunts the shipped agents play."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from conftest import small_scenario
from mpc_hunt import simulate
from mpc_hunt.control.ppo_team import TEAM_POLICY, PpoTeam, shielded
from mpc_hunt.envs.learning import AttackerViewEnv, TeamHunts
from mpc_hunt.errors import MpcHuntError, OptionError
from mpc_hunt.sweep.random_scenario import ScenarioRanges, random_scenario
from mpc_hunt.control.ppo_team import TEAM_VIEW
from mpc_hunt.world.agent_view import ATTACKER_VIEW, attacker_view
from mpc_hunt.world.behaviours import with_behaviour
from mpc_hunt.world.behaviours.ppo import ATTACKER_POLICY, PpoAttacker
from mpc_hunt.control.voronoi import VoronoiController


def _hunt(seed: int, limit: float = 40.0, defenders: int = 3):
    s = random_scenario(np.random.default_rng(seed), ScenarioRanges(n_defenders=(defenders, defenders)), name="env")
    return dataclasses.replace(s, hunt=dataclasses.replace(s.hunt, time_limit=limit))


def test_a_given_hunt_with_nothing_to_decide_is_one_clear_error():
    env = AttackerViewEnv(controller="voronoi", teams=(3,))
    with pytest.raises(MpcHuntError, match="sensing radius"):
        env.reset(seed=0, options={"scenario": _hunt(5, limit=5.0)})


@pytest.mark.slow
def test_the_attacker_view_env_passes_gymnasiums_checker():
    env = AttackerViewEnv(controller="voronoi", teams=(2, 4))
    check_env(env)
    view, _ = env.reset(seed=3)
    assert view.shape == (ATTACKER_VIEW,)


@pytest.mark.parametrize("bad", [0, -1, 2.5, True, 10**6])
def test_a_bad_decision_step_is_refused_naming_it(bad):
    with pytest.raises(OptionError, match="decision_steps"):
        AttackerViewEnv(controller="voronoi", decision_steps=bad)


@pytest.mark.slow
def test_the_ppo_attacker_plays_the_hunt_its_environment_gives():
    """The shipped network through the behaviour in the simulator, and through the training environment: the same
    attacker path to the bit (its view, its decision steps, its velocity)."""
    scenario = _hunt(3, limit=300.0)          # sensed from 28 s on: its decisions start then
    env = AttackerViewEnv(controller="voronoi", teams=(3,))
    view, _ = env.reset(seed=0, options={"scenario": scenario})
    net, done = ATTACKER_POLICY.network(), False
    while not done:
        view, _, terminated, truncated, _ = env.step(net.action(view))
        done = terminated or truncated
    trail = np.array(env.env.episode.trail)
    result = simulate(scenario, VoronoiController(scenario), behaviour=PpoAttacker(scenario, np.random.default_rng(0)))
    assert len(trail) == len(result.attacker) and np.array_equal(trail, result.attacker)
    assert env.env.episode.termination == result.termination


def test_the_ppo_team_plays_the_hunt_its_training_gives():
    """The shipped network through the controller in the simulator, and through TeamHunts: the same defenders'
    paths to the bit (their views, the decision steps, the shield)."""
    scenario = with_behaviour(_hunt(7), "flee")
    hunts = TeamHunts(1, ("flee",), seed=0)
    env = hunts.envs[0]["flee"]
    env.reset(seed=0, options={"scenario": scenario})
    hunts.start(0, env)
    net, views, ended = TEAM_POLICY.network(), hunts.views(0), False
    paths = [env.episode.defenders.copy()]
    while not ended:
        before = env.episode.step_count
        views, _, dones, _ = hunts.step(np.array([net.action(v) for v in views]))
        ended = bool(dones[0])
        if not ended:
            paths.append(env.episode.defenders.copy())
        assert env.episode.step_count - before in (0, net.decision_steps) or ended
    result = simulate(scenario, PpoTeam(scenario), rng=np.random.default_rng(0))
    # TeamHunts starts the next hunt at the end; the decisions before it match the simulator's at every 5th step
    sampled = result.defenders[::net.decision_steps][:len(paths)]
    assert np.array_equal(np.array(paths), sampled)


def test_team_hunts_give_a_row_per_agent_and_restart_a_finished_hunt():
    hunts = TeamHunts(2, ("apf", "gap"), defenders=3, decision_steps=50, seed=1)
    views = hunts.reset()
    assert views.shape == (6, TEAM_VIEW) and hunts.agents == 6
    for k, env in enumerate(hunts.playing):
        env.episode.step_count = env.episode.max_steps - 1          # the next decision ends both hunts
    views, rewards, dones, infos = hunts.step(np.zeros((6, 2)))
    assert dones.all() and [i["termination"] for i in infos] == ["time_limit", "time_limit"]
    assert np.all(rewards[:3] == rewards[0]) and views.shape == (6, TEAM_VIEW)
    assert all(v.shape == (3, TEAM_VIEW) for v in hunts.terminal_views)
    assert all(env.episode.step_count == 0 for env in hunts.playing)       # new hunts


def test_the_attacker_view_is_the_same_length_for_any_team_and_obstacles():
    for seed, defenders in ((1, 1), (2, 5)):
        s = random_scenario(np.random.default_rng(seed), ScenarioRanges(n_defenders=(defenders, defenders)))
        view = attacker_view(s, np.array(s.attacker.start), s.defender_starts, np.zeros_like(s.defender_starts),
                             30.0)
        assert view.shape == (ATTACKER_VIEW,)
    s = small_scenario()
    assert attacker_view(s, np.array(s.attacker.start), s.defender_starts,
                         np.zeros_like(s.defender_starts), 3.0).shape == (ATTACKER_VIEW,)


def test_a_view_puts_the_nearest_robot_and_obstacle_first_and_flags_empty_slots():
    from mpc_hunt.world.agent_view import LENGTH, defender_views
    s = small_scenario(obstacles=((30.0, 0.0, 1.0), (0.0, 4.0, 0.5)))
    p_a = np.zeros(2)
    p_d = np.array([[3.0, 0.0], [0.0, -1.0], [-2.0, 0.0]])
    view = attacker_view(s, p_a, p_d, np.zeros_like(p_d), 10.0)
    assert view[7 + 10 + 4] == 1 and attacker_view(s, p_a, p_d, np.zeros_like(p_d), 2.5)[7 + 10 + 4] == 0
    slots = view[7:7 + 25].reshape(5, 5)
    assert np.allclose(slots[:3, :2] * LENGTH, [[0.0, -1.0], [-2.0, 0.0], [3.0, 0.0]])
    assert slots[:3, 4].tolist() == [1, 1, 1] and not slots[3:].any()
    obstacles = view[32:].reshape(3, 5)
    assert np.allclose(obstacles[0, :2] * LENGTH, [0.0, 4.0]) and obstacles[2].tolist() == [0] * 5
    mine = defender_views(s, p_a, np.zeros(2), p_d, np.zeros_like(p_d))[2]
    mates = mine[18:38].reshape(4, 5)
    assert np.allclose(mates[:2, :2] * LENGTH, [[2.0, -1.0], [5.0, 0.0]]) and not mates[2:].any()


def test_a_defenders_view_gives_the_attackers_margins_then_its_own():
    from mpc_hunt.world.agent_view import LENGTH, defender_views
    import dataclasses
    s = dataclasses.replace(small_scenario(), arena=(-2.0, -3.0, 12.0, 11.0))
    x_min, y_min, x_max, y_max = s.arena
    p_a, p_d = np.array([x_min + 1.0, y_min + 2.0]), np.array([[x_max - 0.5, y_max - 1.5], [0.0, 0.0], [1.0, 1.0]])
    view = defender_views(s, p_a, np.zeros(2), p_d, np.zeros_like(p_d))[0]
    np.testing.assert_allclose(view[9:13] * LENGTH, [1.0, x_max - x_min - 1.0, 2.0, y_max - y_min - 2.0])
    np.testing.assert_allclose(view[13:17] * LENGTH, [x_max - x_min - 0.5, 0.5, y_max - y_min - 1.5, 1.5])


def test_the_team_is_shielded_from_obstacles_and_a_stopped_robot_stays():
    from mpc_hunt.control.ppo_team import shielded
    s = small_scenario(obstacles=((3.0, 3.0, 1.0),))
    safe = s.hunt.safety_distance
    p_d = np.array([[4.0 + safe + 0.001, 3.0], [8.0, 8.0], [-5.0, 5.0]])
    wished = np.array([[-1.0, 0.0], [1.0, 0.0], [1.0, 0.0]])
    v = shielded(s, p_d, wished, np.array([True, True, False]))
    assert abs(v[0, 0]) < 1e-12                         # the step into R_safe is taken off
    assert np.allclose(v[1], [s.defenders[1].max_speed, 0.0]) and not v[2].any()


def _squeezed(s, wall_x: float):
    """Robot 0 just right of ``wall_x`` (an obstacle's R_safe or the arena's edge), asked straight down onto robot
    1, which stands too close below and to its right: the separation row alone turns robot 0 left, over the wall."""
    p_d = np.array([[wall_x + 0.001, 3.0], [wall_x + 0.101, 2.9], [15.0, 15.0]])
    wished = np.array([[0.0, -0.08], [0.0, 0.0], [0.0, 0.0]])
    return shielded(s, p_d, wished, np.array([True, True, False])), p_d


def test_the_team_shield_keeps_r_safe_when_the_separation_filter_turns_a_robot_towards_an_obstacle():
    s = small_scenario(obstacles=((3.0, 3.0, 1.0),))
    v, p_d = _squeezed(s, 4.0 + s.hunt.safety_distance)
    after = p_d + s.hunt.time_step * v
    assert np.hypot(*(after[0] - [3.0, 3.0])) >= 1.0 + s.hunt.safety_distance      # 3 mm inside without the rows
    assert np.hypot(*(after[0] - after[1])) >= np.hypot(*(p_d[0] - p_d[1])) - 1e-12  # and no closer to robot 1


def test_the_team_shield_keeps_a_robot_in_the_arena_when_the_separation_filter_turns_it_outwards():
    s = dataclasses.replace(small_scenario(obstacles=()), arena=(0.0, 0.0, 20.0, 20.0))
    v, p_d = _squeezed(s, 0.0)
    assert p_d[0, 0] + s.hunt.time_step * v[0, 0] >= 0.0                            # 3 mm out without the rows


def _network(tmp_path, bias=(0.0, 0.0)):
    """A team network of zeros but for its last bias: every correction is ``bias``."""
    arrays = {"side": np.array("defender"), "decision_steps": np.array(5), "clip": np.array(10.0),
              "epsilon": np.array(1e-8), "obs_mean": np.zeros(TEAM_VIEW), "obs_var": np.ones(TEAM_VIEW),
              "w0": np.zeros((4, TEAM_VIEW)), "b0": np.zeros(4), "w1": np.zeros((2, 4)), "b1": np.array(bias)}
    path = tmp_path / "team.npz"
    with open(path, "wb") as f:
        np.savez(f, **arrays)
    return str(path)


@pytest.mark.slow
def test_with_no_correction_the_ppo_team_is_the_voronoi_baseline(tmp_path):
    scenario = with_behaviour(_hunt(9, limit=300.0), "gap")
    ours = simulate(scenario, PpoTeam(scenario, policy=_network(tmp_path)), rng=np.random.default_rng(0))
    theirs = simulate(scenario, VoronoiController(scenario), rng=np.random.default_rng(0))
    # the shield, applied again to the baseline's shielded commands, moves last bits only: 4e-14 m over this hunt
    assert ours.termination == theirs.termination == "captured" and ours.defenders.shape == theirs.defenders.shape
    assert np.abs(ours.defenders - theirs.defenders).max() < 1e-9


def test_the_correction_is_added_to_the_baseline_at_its_scale(tmp_path):
    from mpc_hunt.control.controller import Observation
    from mpc_hunt.control.ppo_team import RESIDUAL
    scenario = small_scenario(obstacles=())
    P = np.array([[4.0, 4.0], [16.0, 4.0], [10.0, 17.0]])
    obs = Observation(0.0, np.array([10.0, 10.0]), None, P)
    base = VoronoiController(scenario).command(obs).velocities
    push = PpoTeam(scenario, policy=_network(tmp_path, bias=(0.0, -0.3))).command(obs).velocities
    top = scenario.defender_max_speeds.max()
    from mpc_hunt.world.geometry import saturate
    assert np.allclose(push, saturate(base + RESIDUAL * top * np.array([0.0, -0.3]), top), atol=1e-12)
    assert not np.allclose(push, base)


@pytest.mark.parametrize("bad", [np.array([np.nan, 0.0]), np.zeros(3), np.zeros((1, 2)), "east"])
def test_an_illegal_attacker_action_is_refused_before_anything_moves(bad):
    from mpc_hunt.errors import ActionError
    env = AttackerViewEnv(controller="voronoi", teams=(3,))
    env.reset(seed=0, options={"scenario": _hunt(3, limit=300.0)})
    before = (env.env.episode.step_count, env.env.episode.attacker.copy())
    with pytest.raises(ActionError):
        env.step(bad)
    assert env.env.episode.step_count == before[0] and np.array_equal(env.env.episode.attacker, before[1])
    view, *_ = env.step(np.array([1e300, -1e300]))          # huge: clipped to the box, then the top speed
    assert np.all(np.isfinite(view))


@pytest.mark.parametrize("bad", [np.vstack([np.zeros((3, 2)), np.full((3, 2), np.nan)]), np.zeros((5, 2)), "east"])
def test_illegal_team_actions_are_refused_before_any_hunt_moves(bad):
    from mpc_hunt.errors import ActionError
    hunts = TeamHunts(2, ("apf",), defenders=3, seed=1)
    hunts.reset()
    before = [(env.episode.step_count, env.episode.defenders.copy()) for env in hunts.playing]
    with pytest.raises(ActionError, match="a correction"):
        hunts.step(bad)
    assert all(env.episode.step_count == n and np.array_equal(env.episode.defenders, p)
               for env, (n, p) in zip(hunts.playing, before))
    views, rewards, *_ = hunts.step(np.full((6, 2), 1e300))        # huge: clipped to [-1, 1]
    assert np.all(np.isfinite(views)) and np.all(np.isfinite(rewards))

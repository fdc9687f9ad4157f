"""The hunt environments, checked as their ecosystems check them, and what they promise beyond that."""

from __future__ import annotations

import dataclasses

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from pettingzoo.test import parallel_api_test, parallel_seed_test

from conftest import small_scenario
from mpc_hunt import builtin_scenario, simulate
from mpc_hunt.envs import AttackerEnv, ControllerPolicy, DefenderEnv, HuntParallelEnv, PolicyAttacker
from mpc_hunt.envs.episode import Episode
from mpc_hunt.envs.observation import field_names
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.world.behaviours import make_behaviour

SHORT = small_scenario()       # three defenders round an attacker, no obstacle: a capture within a minute or so


def _short(scenario, limit=3.0):
    return dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, time_limit=limit))


@pytest.mark.parametrize("name", ["mpc_hunt/Attacker-v0", "mpc_hunt/Defenders-v0"])
def test_the_gymnasium_environments_pass_the_checker_with_no_arguments(name):
    check_env(gym.make(name).unwrapped)
    frame = gym.make(name, render_mode="rgb_array")
    frame.reset(seed=0)
    image = frame.render()
    assert image.ndim == 3 and image.shape[2] == 3 and image.dtype == np.uint8 and image.std() > 0


def test_the_parallel_environment_passes_pettingzoo_api_and_seed_tests():
    parallel_api_test(HuntParallelEnv(), num_cycles=20)
    parallel_seed_test(HuntParallelEnv)


def test_a_seed_gives_the_same_hunt_and_another_seed_another():
    first, again, other = (AttackerEnv(controller="voronoi").reset(seed=s)[0] for s in (3, 3, 4))
    np.testing.assert_array_equal(first, again)
    assert not np.array_equal(first, other)
    runs = []
    for _ in range(2):                          # after a seeded reset, unseeded ones go on with its stream
        env = HuntParallelEnv()
        runs.append([env.reset(seed=5)[0]["attacker"]] + [env.reset()[0]["attacker"] for _ in range(2)])
    np.testing.assert_array_equal(np.array(runs[0]), np.array(runs[1]))
    assert not np.array_equal(runs[0][0], runs[0][1])


def test_the_observation_is_the_state_in_physical_units_field_by_field():
    scenario = small_scenario(obstacles=((11.0, 6.0, 0.4),))
    env = DefenderEnv(scenario)
    observation, _ = env.reset(seed=0)
    fields = dict(zip(field_names(3, 1), observation))
    assert fields["time"] == 0.0 and (fields["attacker_x"], fields["attacker_y"]) == tuple(scenario.attacker.start)
    assert (fields["defender_2_x"], fields["defender_2_y"]) == tuple(scenario.defenders[2].start)
    assert (fields["obstacle_0_x"], fields["obstacle_0_y"], fields["obstacle_0_radius"]) == (11.0, 6.0, 0.4)
    velocity = np.array([[0.05, 0.0], [0.0, 1.0], [0.0, 0.0]])          # the second asks for more than it can
    observation, *_ = env.step(velocity)
    fields = dict(zip(field_names(3, 1), observation))
    assert fields["time"] == pytest.approx(0.1) and fields["defender_0_vx"] == pytest.approx(0.05)
    assert np.hypot(fields["defender_1_vx"], fields["defender_1_vy"]) == pytest.approx(scenario.defenders[1].max_speed)
    assert np.hypot(fields["attacker_vx"], fields["attacker_vy"]) <= scenario.attacker.max_speed + 1e-12


def test_a_hunt_ends_terminated_by_a_capture_and_truncated_by_the_time_limit():
    env = AttackerEnv(SHORT, controller="voronoi")
    env.reset(seed=0)
    total, done = 0.0, False
    while not done:
        _, reward, terminated, truncated, info = env.step(np.zeros(2))        # the attacker stands still
        total += reward
        done = terminated or truncated
    assert terminated and not truncated and info["termination"] == "captured"
    assert -2.0 < total < 0.0                        # −1 for the capture, shaping at most ±1
    env = AttackerEnv(_short(SHORT), controller="voronoi")
    env.reset(seed=0)
    for _ in range(29):
        assert env.step(np.zeros(2))[3] is False
    _, reward, terminated, truncated, info = env.step(np.zeros(2))
    assert truncated and not terminated and info["termination"] == "time_limit" and reward > 0.5


def test_rewards_are_zero_sum_and_the_shaping_is_a_potential_difference():
    """Φ = the defenders' mean distance to the attacker / 20 m (the scenario has no arena), computed here apart."""
    env = HuntParallelEnv(SHORT)
    env.reset(seed=0)
    episode = env.episode

    def phi():
        return np.mean(np.hypot(*(episode.defenders - episode.attacker).T)) / 20.0

    before = phi()
    actions = {a: np.array([0.0, 0.05]) if a == "attacker" else np.zeros(2) for a in env.agents}
    _, rewards, *_ = env.step(actions)
    assert rewards["attacker"] == pytest.approx(phi() - before, rel=1e-12) and rewards["attacker"] > 0
    assert all(rewards[a] == -rewards["attacker"] for a in rewards if a != "attacker")


def test_a_non_finite_state_ends_the_hunt_with_a_status_not_a_traceback():
    """A non-finite action is refused (tests/envs/test_boundary.py); a state can still become one (a failing
    behaviour or controller): the hunt ends with a status."""
    env = DefenderEnv(SHORT)
    env.reset(seed=0)
    env.episode.attacker[:] = np.nan
    _, reward, terminated, _, info = env.step(np.zeros((3, 2)))
    assert terminated and info["termination"] == "non_finite_state" and reward == 0.0
    with pytest.raises(MpcHuntError, match="call reset"):
        HuntParallelEnv(SHORT).step({})


def test_the_attacker_never_enters_an_obstacle_whatever_its_action():
    scenario = small_scenario(obstacles=((10.6, 10.0, 0.4),))       # just east of the attacker's start
    env = AttackerEnv(scenario, controller="voronoi")
    env.reset(seed=0)
    for _ in range(100):                                            # 0.3 m at v_a: past the surface 0.2 m away
        env.step(np.array([1.0, 0.0]))                              # straight at the obstacle, too fast
        assert np.hypot(*(env.episode.attacker - [10.6, 10.0])) > 0.4


def test_the_projects_controller_is_a_policy_and_a_policy_an_attacker_of_the_simulator():
    scenario = _short(builtin_scenario("paper-open"), 20.0)
    env = DefenderEnv(scenario)
    policy = ControllerPolicy(env, "voronoi")
    observation, _ = env.reset(seed=0)
    played = [observation]
    for _ in range(50):
        observation, *_ = env.step(policy(observation))
        played.append(observation)
    hunt = simulate(scenario, policy.controller.__class__(scenario), until=lambda o: o.time > 5.0 - 1e-9)
    defenders = np.array([o[7:7 + 12].reshape(3, 4)[:, :2] for o in played])
    np.testing.assert_allclose(defenders[:51], hunt.defenders[:51], atol=1e-12)
    flee = make_behaviour(dataclasses.replace(scenario, attacker=dataclasses.replace(scenario.attacker,
                                                                                      behaviour="flee")), None)
    as_policy = PolicyAttacker(scenario, lambda o: flee.velocity(o[1:3], o[7:19].reshape(3, 4)[:, :2]))
    same = simulate(scenario, behaviour=as_policy, until=lambda o: o.time > 2.0 - 1e-9)
    assert same.attacker.shape[0] == 21 and np.all(np.isfinite(same.attacker))


def test_several_hunts_run_as_a_gymnasium_vector_environment():
    envs = gym.vector.SyncVectorEnv([lambda: AttackerEnv(_short(SHORT), controller="voronoi")] * 2)
    observations, _ = envs.reset(seed=[0, 1])
    assert observations.shape == (2, len(field_names(3, len(SHORT.obstacles))))
    observations, rewards, terminated, truncated, _ = envs.step(np.zeros((2, 2)))
    assert rewards.shape == (2,) and not terminated.any()
    envs.close()


def test_bad_settings_are_one_line_errors():
    with pytest.raises(MpcHuntError, match="render_mode"):
        AttackerEnv(render_mode="human")
    with pytest.raises(MpcHuntError, match="unknown behaviour"):
        DefenderEnv(attacker="teleport")
    with pytest.raises(MpcHuntError, match="options\\['scenario'\\]"):
        HuntParallelEnv().reset(seed=0, options={"scenario": dataclasses.replace(SHORT,
                                                                                  defenders=SHORT.defenders[:2])})
    assert isinstance(Episode(SHORT, 0).observation(), np.ndarray)

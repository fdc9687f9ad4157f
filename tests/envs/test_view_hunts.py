"""The PPO attacker's training hunts, many in one call: each is an AttackerViewEnv's, decision by decision."""

import numpy as np
import pytest

from mpc_hunt.envs.learning import AttackerViewEnv
from mpc_hunt.envs.view_hunts import AttackerViewHunts
from mpc_hunt.errors import ActionError, OptionError
from plays_alike import plays_alike


@pytest.mark.parametrize("controller, decisions", [("voronoi", 700), ("apf", 700)])
def test_each_hunt_plays_what_a_view_env_plays_through_its_ends_and_redraws(controller, decisions):
    B = 4
    hunts = AttackerViewHunts(B, controller=controller)
    envs = [AttackerViewEnv(controller=controller) for _ in range(B)]
    ends = plays_alike(hunts, envs, 11, decisions, lambda rng: rng.uniform(-1.5, 1.5, (B, 2)))  # clipped by both
    assert ends >= 1


def test_bad_arguments_and_actions_are_one_line_and_move_nothing():
    for bad in (0, -2, 1.5):
        with pytest.raises(OptionError, match="^num_envs: "):
            AttackerViewHunts(bad)
    with pytest.raises(OptionError, match="^teams: "):
        AttackerViewHunts(2, teams=())
    hunts = AttackerViewHunts(3, controller="voronoi")
    with pytest.raises(ActionError, match="^step: call reset"):
        hunts.step(np.zeros((3, 2)))
    hunts.reset(seed=2)
    before = hunts.slots.batch.p_a.copy(), hunts.slots.steps.copy()
    actions = np.zeros((3, 2))
    actions[1, 0] = np.inf
    with pytest.raises(ActionError, match=r"^actions\[1\]: not finite"):
        hunts.step(actions)
    np.testing.assert_array_equal(before[0], hunts.slots.batch.p_a)
    np.testing.assert_array_equal(before[1], hunts.slots.steps)


def test_the_attackers_training_runs_ppo_on_it():
    pytest.importorskip("stable_baselines3", reason="Stable-Baselines3 is the optional extra [learn]")
    import sys
    from pathlib import Path

    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecNormalize

    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
    from studies.train_ppo import attacker_vec_env

    venv = VecNormalize(attacker_vec_env(4, 3))
    model = PPO("MlpPolicy", venv, n_steps=16, batch_size=32, n_epochs=1, seed=0, device="cpu")
    model.learn(total_timesteps=64)
    assert model.num_timesteps >= 64

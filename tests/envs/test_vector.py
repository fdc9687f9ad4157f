"""The vectorised attacker environment: each hunt is an AttackerEnv's, step by step; bad input disturbs none."""

import numpy as np
import pytest

from mpc_hunt.envs import AttackerEnv
from mpc_hunt.envs.vector import MAX_ENVS, AttackerHunts
from mpc_hunt.errors import ActionError, OptionError
from mpc_hunt.sweep.random_scenario import ScenarioRanges
from plays_alike import plays_alike

SHORT = ScenarioRanges(time_limit=12.0)     # hunts end often: the resets are exercised


@pytest.mark.parametrize("controller", ["voronoi", "apf"])        # a batched rule, and one commanded hunt by hunt
def test_each_hunt_plays_what_an_attacker_env_plays_through_its_ends_and_resets(controller):
    B = 3
    hunts = AttackerHunts(B, ranges=SHORT, controller=controller)
    envs = [AttackerEnv(ranges=SHORT, controller=controller) for _ in range(B)]
    ends = plays_alike(hunts, envs, 20, 400, lambda rng: rng.uniform(-0.1, 0.1, (B, 2)))
    assert ends >= B


def test_a_bad_count_of_hunts_or_option_is_one_line_naming_it():
    for bad in (0, -1, MAX_ENVS + 1, 2.5, True, "3", None):
        with pytest.raises(OptionError, match="^num_envs: "):
            AttackerHunts(bad)
    for option, value in (("render_mode", "rgb_array"), ("controllers", "voronoi")):
        with pytest.raises(OptionError, match=f"^{option}: not an option of AttackerHunts"):
            AttackerHunts(2, **{option: value})
    with pytest.raises(OptionError, match="^defenders: "):            # AttackerEnv's own check
        AttackerHunts(2, defenders=0)


def test_a_step_before_reset_and_a_bad_action_for_one_hunt_move_nothing():
    hunts = AttackerHunts(4, ranges=SHORT, controller="voronoi")
    with pytest.raises(ActionError, match="^step: call reset"):
        hunts.step(np.zeros((4, 2)))
    hunts.reset(seed=1)
    hunts.step(np.full((4, 2), 0.01))
    before = (hunts.slots.batch.p_a.copy(), hunts.slots.batch.p_d.copy(), hunts.slots.steps.copy())
    actions = np.full((4, 2), 0.01)
    actions[2, 1] = np.nan
    with pytest.raises(ActionError, match=r"^actions\[2\]: not finite"):
        hunts.step(actions)
    with pytest.raises(ActionError, match=r"^actions: shape \(3, 2\)"):
        hunts.step(np.zeros((3, 2)))
    after = (hunts.slots.batch.p_a, hunts.slots.batch.p_d, hunts.slots.steps)
    for a, b in zip(before, after):
        np.testing.assert_array_equal(a, b)


def test_stable_baselines3_takes_it_as_a_vec_env_and_ppo_learns_on_it():
    pytest.importorskip("stable_baselines3", reason="Stable-Baselines3 is the optional extra [learn]")
    from stable_baselines3 import PPO

    from mpc_hunt.envs.sb3 import as_vec_env

    venv = as_vec_env(AttackerHunts(8, ranges=SHORT, controller="voronoi"))
    venv.seed(5)
    model = PPO("MlpPolicy", venv, n_steps=32, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.learn(total_timesteps=256)
    assert model.num_timesteps >= 256

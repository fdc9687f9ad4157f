"""Vectorised hunts handed to Stable-Baselines3 as its ``VecEnv`` (the optional extra ``[learn]``).

:func:`as_vec_env` wraps hunts stepped in one call (:class:`Vectorised`): SB3's ``step_async``/``step_wait`` call
its ``step`` once for every hunt, and its ``reset`` seeds hunt k with ``seed + k`` (``VecEnv.seed``), so PPO
steps ``num_envs`` hunts per call in one process. :func:`plain_vec_env` is the ``VecEnv`` base both it and the
team's training environment (studies/train_ppo.py) build on: one process, no wrapped environments to reach.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
from gymnasium import spaces

from mpc_hunt.errors import MpcHuntError


class Vectorised(Protocol):
    """Hunts stepped in one call: :class:`~mpc_hunt.envs.vector.AttackerHunts`,
    :class:`~mpc_hunt.envs.view_hunts.AttackerViewHunts`."""

    num_envs: int
    single_observation_space: spaces.Space
    single_action_space: spaces.Box

    def reset(self, seed: int | None = None) -> np.ndarray: ...

    def step(self, actions) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict]]: ...


def plain_vec_env() -> type:
    """SB3's ``VecEnv`` with what a single-process batch needs of it besides its own ``reset`` and ``step``: no
    attributes, methods or wrappers of sub-environments to reach. A one-line error saying how to install SB3
    without it."""
    try:
        from stable_baselines3.common.vec_env import VecEnv
    except ImportError:
        raise MpcHuntError('Stable-Baselines3 is needed: pip install "mpc-hunt[learn]"') from None

    class PlainVecEnv(VecEnv):
        actions: np.ndarray

        def step_async(self, actions):
            self.actions = actions

        def close(self):
            pass

        def get_attr(self, attr_name, indices=None):
            return [getattr(self, attr_name, None)] * len(self._get_indices(indices))

        def set_attr(self, attr_name, value, indices=None):
            pass

        def env_method(self, method_name, *args, indices=None, **kwargs):
            return [None] * len(self._get_indices(indices))

        def env_is_wrapped(self, wrapper_class, indices=None):
            return [False] * len(self._get_indices(indices))

    return PlainVecEnv


def as_vec_env(hunts: Vectorised):
    """``hunts`` as Stable-Baselines3's ``VecEnv`` (the module's docstring)."""

    class HuntsVecEnv(plain_vec_env()):  # type: ignore[misc]
        def __init__(self):
            super().__init__(hunts.num_envs, hunts.single_observation_space, hunts.single_action_space)
            self.actions = np.zeros((hunts.num_envs, 2))

        def reset(self):
            seed = self._seeds[0] if self._seeds and self._seeds[0] is not None else None
            self._reset_seeds()
            return hunts.reset(seed=seed)

        def step_wait(self):
            observations, rewards, dones, infos = hunts.step(self.actions)
            return observations, rewards.astype(np.float32), dones, infos

    return HuntsVecEnv()

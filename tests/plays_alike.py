"""Shared by the vectorised environments' tests: many hunts in one call against single environments, step by step."""

import numpy as np


def plays_alike(hunts, envs, seed: int, steps: int, actions) -> int:
    """``hunts`` (reset from ``seed``) and the single ``envs`` (env k reset from ``seed + k``) stepped with the same
    ``actions(rng)`` for ``steps`` steps: the same observations, rewards, ends, infos and terminal observations, an
    ended env reset as a vectorised one resets its hunt. The number of ends."""
    observations = hunts.reset(seed=seed)
    for k, env in enumerate(envs):
        np.testing.assert_array_equal(env.reset(seed=seed + k)[0], observations[k])
    rng, ends = np.random.default_rng(0), 0
    for _ in range(steps):
        chosen = actions(rng)
        observations, rewards, dones, infos = hunts.step(chosen)
        for k, env in enumerate(envs):
            o, r, terminated, truncated, info = env.step(chosen[k])
            assert dones[k] == (terminated or truncated) and rewards[k] == r
            assert infos[k]["termination"] == info["termination"]
            if dones[k]:
                ends += 1
                np.testing.assert_array_equal(infos[k]["terminal_observation"], o)
                o, _ = env.reset()
            np.testing.assert_array_equal(observations[k], o)
    return ends

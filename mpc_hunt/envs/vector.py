"""Many hunts of :class:`~mpc_hunt.envs.AttackerEnv` stepped at once: one call a step for all of them.

:class:`AttackerHunts` holds ``num_envs`` hunts as one batch of the engine (:mod:`mpc_hunt.sim.batch`): the
attackers' actions checked and applied (capped at v_a, kept out of every obstacle), the defenders commanded (a
batched controller's rule, ``voronoi`` say, in one call; any other hunt by hunt), the world stepped and judged,
the rewards and the observations computed, all for the batch at once. Hunt k plays exactly what an
``AttackerEnv`` with the same arguments plays after ``reset(seed=seed + k)`` and then ``reset()`` at each end
(a test compares them step by step). A hunt that ends is reset in the same call (Stable-Baselines3's
convention): its last observation is in ``infos[k]["terminal_observation"]`` and the observation returned is
its next hunt's first; the others go on untouched. :func:`mpc_hunt.envs.sb3.as_vec_env` hands it to
Stable-Baselines3 as a ``VecEnv``.

An illegal action for one hunt (not finite, the wrong shape) is an
:class:`~mpc_hunt.errors.ActionError` naming its row, raised before anything moves: no hunt is disturbed.
"""

from __future__ import annotations

import inspect

import numpy as np
from gymnasium import spaces

from mpc_hunt.arguments import out_of_range
from mpc_hunt.envs.actions import checked_action
from mpc_hunt.envs.attacker_env import AttackerEnv
from mpc_hunt.envs.base import checked_seed
from mpc_hunt.envs.observation import NO_ARENA
from mpc_hunt.envs.slots import HuntSlots
from mpc_hunt.errors import ActionError, OptionError
from mpc_hunt.world.packed import NOMINAL_X, NOMINAL_Y, T
from mpc_hunt.world.scenario import Scenario

MAX_ENVS = 16_384  # hunts side by side: about 36 kB each (its scenario, its controller, its rows), 600 MB in all


class AttackerHunts:
    """``num_envs`` attackers learning at once (the module's docstring); ``options`` are
    :class:`~mpc_hunt.envs.AttackerEnv`'s (but ``render_mode``), checked as it checks them."""

    def __init__(self, num_envs: int, **options):
        self.num_envs = checked_count(num_envs)
        allowed = set(inspect.signature(AttackerEnv).parameters) - {"render_mode"}
        unknown = sorted(set(options) - allowed)
        if unknown:
            raise OptionError(
                f"{unknown[0]}: not an option of AttackerHunts (its options: {', '.join(sorted(allowed))})"
            )
        one = AttackerEnv(**options)  # every option checked as AttackerEnv checks it, once
        B = self.num_envs
        hunts = self.hunts = one.hunts
        self.belief, self.controller_spec = one.belief, one.controller_spec
        self.single_action_space, self.single_observation_space = one.action_space, one.observation_space
        speed = hunts.attacker_speed
        self.actions_space = spaces.Box(-speed, speed, shape=(B, 2), dtype=np.float64)
        self._shape = (hunts.team, hunts.max_obstacles)
        self._static = np.zeros((B, 3 * hunts.max_obstacles + 4))  # each hunt's obstacles and arena, as observed
        self._rngs: list[np.random.Generator] = []
        self.slots: HuntSlots | None = None

    def reset(self, seed: int | None = None) -> np.ndarray:
        """Every hunt drawn anew, hunt k from the seed ``seed + k`` (fresh entropy without one): the observations
        (num_envs, D)."""
        self._rngs = slot_generators(checked_seed(seed), self.num_envs)  # as an AttackerEnv's reset(seed=seed + k)
        starts = [self._draw(k) for k in range(self.num_envs)]
        self.slots = HuntSlots(starts, *self._shape, self.controller_spec, self.belief)
        for k, (scenario, _) in enumerate(starts):
            self._static[k] = self._seen(scenario)
        return self._observe(self.slots)

    def step(self, actions) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict]]:
        """One step of every hunt with the attackers' ``actions`` (num_envs, 2): (observations, rewards, dones,
        infos), Stable-Baselines3's ``VecEnv.step_wait``."""
        if self.slots is None:
            raise ActionError("step: call reset() first")
        actions = checked_rows(actions, self.actions_space, self.single_action_space)
        slots, B = self.slots, self.num_envs
        rewards, ended, truncated = slots.advance(np.ones(B, dtype=bool), actions)
        observations = self._observe(slots)
        infos = slots.infos(ended, truncated, observations)
        if ended.any():
            for k in np.flatnonzero(ended).tolist():
                scenario, other = self._draw(k)
                slots.start(k, scenario, other)
                self._static[k] = self._seen(scenario)
            slots.rebuild()
            observations[ended] = self._observe(slots)[ended]
        return observations, rewards, ended, infos

    def _draw(self, k: int) -> tuple[Scenario, np.random.Generator]:
        """Hunt k's next scenario, and the generator its controller is built with, from hunt k's generator (as an
        AttackerEnv's reset draws them)."""
        world, other = self._rngs[k].spawn(2)
        return self.hunts.draw(world, None), other

    def _seen(self, s: Scenario) -> np.ndarray:
        """What the observation holds of ``s``'s obstacles and arena."""
        M = self._shape[1]
        static = np.zeros(3 * M + 4)
        for j, o in enumerate(s.obstacles[:M]):
            static[3 * j : 3 * j + 3] = (*o.centre, o.radius)
        static[3 * M :] = s.arena if s.arena is not None else NO_ARENA
        return static

    def _observe(self, slots: HuntSlots) -> np.ndarray:
        """The observations (:mod:`mpc_hunt.envs.observation`) of every hunt."""
        b, B, n = slots.batch, self.num_envs, self._shape[0]
        time = (slots.steps * b.prm[:, T])[:, None]
        defenders = np.concatenate([b.p_d, slots.v_d], axis=2).reshape(B, 4 * n)
        intent = b.prm[:, [NOMINAL_X, NOMINAL_Y]]
        return np.concatenate([time, b.p_a, slots.v_a, intent, defenders, self._static], axis=1)


def checked_count(num_envs) -> int:
    """``num_envs`` as a whole number from 1 to ``MAX_ENVS``, or an OptionError naming it."""
    if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)):
        raise OptionError(f"num_envs: a whole number from 1 to {MAX_ENVS}, got {type(num_envs).__name__}")
    why = out_of_range(int(num_envs), 1, MAX_ENVS)
    if why:
        raise OptionError(f"num_envs: {why}")
    return int(num_envs)


def slot_generators(seed: int | None, count: int) -> list[np.random.Generator]:
    """Each slot's generator: slot k's of ``seed + k`` (as an environment's ``reset(seed=seed + k)``), of fresh
    entropy without a seed."""
    sources = np.random.SeedSequence().spawn(count) if seed is None else range(seed, seed + count)
    return [np.random.default_rng(x) for x in sources]


def checked_rows(actions, space: spaces.Box, row: spaces.Box) -> np.ndarray:
    """``actions`` as ``space``'s finite floats, or an ActionError naming the first bad row (each of ``row``)."""
    what = "a velocity (vx, vy) in m/s per hunt, one row each"
    try:
        return checked_action(actions, space, "actions", what)
    except ActionError:
        rows = np.asarray(actions, dtype=object)
        if rows.shape == space.shape:
            for k, one in enumerate(rows):
                checked_action(one, row, f"actions[{k}]")
        raise

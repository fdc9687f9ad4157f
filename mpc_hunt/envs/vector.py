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
from mpc_hunt.control.controller import Observation
from mpc_hunt.envs.actions import checked_action
from mpc_hunt.envs.attacker_env import AttackerEnv
from mpc_hunt.envs.base import checked_seed
from mpc_hunt.envs.episode import NO_ARENA_DIAGONAL, OUTCOME
from mpc_hunt.envs.observation import NO_ARENA
from mpc_hunt.errors import ActionError, OptionError
from mpc_hunt.sim.batch import Batch
from mpc_hunt.sim.world_step import ENDS, NON_FINITE, RUNNING, step_batch
from mpc_hunt.world.behaviours.base import attacker_moves
from mpc_hunt.world.packed import NOMINAL_X, NOMINAL_Y, T
from mpc_hunt.world.scenario import Scenario

MAX_ENVS = 65_536  # hunts side by side: about 2 kB of arrays each


class AttackerHunts:
    """``num_envs`` attackers learning at once (the module's docstring); ``options`` are
    :class:`~mpc_hunt.envs.AttackerEnv`'s (but ``render_mode``), checked as it checks them."""

    def __init__(self, num_envs: int, **options):
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)):
            raise OptionError(f"num_envs: a whole number from 1 to {MAX_ENVS}, got {type(num_envs).__name__}")
        why = out_of_range(int(num_envs), 1, MAX_ENVS)
        if why:
            raise OptionError(f"num_envs: {why}")
        allowed = set(inspect.signature(AttackerEnv).parameters) - {"render_mode"}
        unknown = sorted(set(options) - allowed)
        if unknown:
            raise OptionError(
                f"{unknown[0]}: not an option of AttackerHunts (its options: {', '.join(sorted(allowed))})"
            )
        one = AttackerEnv(**options)  # every option checked as AttackerEnv checks it, once
        self.num_envs = B = int(num_envs)
        hunts = self.hunts = one.hunts
        self.belief, self.controller_spec = one.belief, one.controller_spec
        self.single_action_space, self.single_observation_space = one.action_space, one.observation_space
        speed = hunts.attacker_speed
        self.actions_space = spaces.Box(-speed, speed, shape=(B, 2), dtype=np.float64)
        n, M = hunts.team, hunts.max_obstacles
        self._static = np.zeros((B, 3 * M + 4))  # each hunt's obstacles and arena, as observed
        self._scale = np.ones(B)  # Φ's: the arena's diagonal
        self._rngs: list[np.random.Generator] = []
        self.batch: Batch | None = None
        self.controllers: list = [None] * B
        self.steps = np.zeros(B, dtype=np.int64)
        self.held, self.status = np.zeros(B, dtype=np.int64), np.zeros(B, dtype=np.int64)
        self._shape = (n, M)
        self._rule = None  # the batched controllers' rule, for the hunts of ``_batched``
        self._batched = np.zeros(B, dtype=bool)

    def reset(self, seed: int | None = None) -> np.ndarray:
        """Every hunt drawn anew, hunt k from the seed ``seed + k`` (fresh entropy without one): the observations
        (num_envs, D)."""
        seed = checked_seed(seed)
        sources = np.random.SeedSequence().spawn(self.num_envs) if seed is None else range(seed, seed + self.num_envs)
        self._rngs = [np.random.default_rng(x) for x in sources]  # as an AttackerEnv's reset(seed=seed + k)
        drawn = [self._draw(k) for k in range(self.num_envs)]
        n, M = self._shape
        self.batch = b = Batch([s for s, _ in drawn], [None] * self.num_envs, n, M)
        for k, (_, other) in enumerate(drawn):
            self._start(b, k, other)
        self._rebuild()
        return self._observe(b, np.zeros((self.num_envs, 2)), self._still())

    def step(self, actions) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict]]:
        """One step of every hunt with the attackers' ``actions`` (num_envs, 2): (observations, rewards, dones,
        infos), Stable-Baselines3's ``VecEnv.step_wait``."""
        if self.batch is None:
            raise ActionError("step: call reset() first")
        actions = self._checked(actions)
        b: Batch = self.batch
        B = self.num_envs
        running = np.ones(B, dtype=bool)
        out_v = self._still()
        capture, intercepts = np.zeros(out_v.shape[:2], dtype=bool), np.zeros_like(out_v)
        failed = self.steps[:, None] * b.prm[:, T, None] >= b.fails_at
        for k in np.flatnonzero(~self._batched).tolist():
            obs = Observation(self.steps[k] * float(b.prm[k, T]), b.p_a[k].copy(),
                              None if self.steps[k] == 0 else b.previous[k].copy(), b.p_d[k].copy(),
                              failed[k] if failed[k].any() else None)  # fmt: skip
            out_v[k] = self.controllers[k].command(obs).velocities
        if self._rule is not None:
            previous = np.where((self.steps == 0)[:, None], np.nan, b.previous)
            self._rule.commands(self._batched, b.p_a, previous, b.p_d, b.n, failed, out_v, capture, intercepts)
        attacker_v = np.zeros((B, 2))
        attacker_moves(running, actions, b.p_a, b.centres, b.radii, b.m, b.prm, attacker_v)
        before_a, before_d = b.p_a.copy(), b.p_d.copy()
        potential = self._potential(b)
        b.previous[:] = b.p_a
        step_batch(running, self.steps, b.p_a, b.p_d, b.n, out_v, attacker_v, b.fails_at, b.speeds, b.centres,
                   b.radii, b.m, b.prm, self.held, b.hold, self.status)  # fmt: skip
        self.steps += 1
        Tb = b.prm[:, T, None]
        v_a, v_d = (b.p_a - before_a) / Tb, (b.p_d - before_d) / Tb[:, :, None]
        truncated = (self.status == RUNNING) & (self.steps >= b.max_steps)
        ended = (self.status != RUNNING) | truncated
        shaping = np.where(self.status == NON_FINITE, 0.0, self._potential(b) - potential)
        observations = self._observe(b, v_a, v_d)
        rewards, infos = shaping, []
        for k in range(B):
            info = {"time": float(self.steps[k] * b.prm[k, T]), "termination": None, "scenario": b.scenarios[k].name}
            if ended[k]:
                how = "time_limit" if truncated[k] else ENDS[int(self.status[k])]
                rewards[k] += OUTCOME[how]
                info |= {"termination": how, "terminal_observation": observations[k].copy(),
                         "TimeLimit.truncated": bool(truncated[k])}  # fmt: skip
            infos.append(info)
        if ended.any():
            for k in np.flatnonzero(ended).tolist():
                scenario, other = self._draw(k)
                b.put(k, scenario)
                self._start(b, k, other)
            self._rebuild()
            observations[ended] = self._observe(b, np.zeros((B, 2)), self._still())[ended]
        return observations, rewards, ended, infos

    def _draw(self, k: int) -> tuple[Scenario, np.random.Generator]:
        """Hunt k's next scenario, and the generator its controller is built with, from hunt k's generator (as an
        AttackerEnv's reset draws them)."""
        world, other = self._rngs[k].spawn(2)
        return self.hunts.draw(world, None), other

    def _start(self, b: Batch, k: int, other: np.random.Generator) -> None:
        """Slot k's hunt at its start: its controller built on the belief, its counters, what it observes."""
        s = b.scenarios[k]
        controller = self.controller_spec.build(s, belief=self.belief, rng=other)
        self.steps[k], self.held[k], self.status[k] = 0, 0, RUNNING
        b.previous[k] = b.p_a[k]
        M = self._shape[1]
        static = np.zeros(3 * M + 4)
        for j, o in enumerate(s.obstacles[:M]):
            static[3 * j : 3 * j + 3] = (*o.centre, o.radius)
        static[3 * M :] = s.arena if s.arena is not None else NO_ARENA
        self._static[k] = static
        arena = s.arena
        self._scale[k] = (
            NO_ARENA_DIAGONAL if arena is None else float(np.hypot(arena[2] - arena[0], arena[3] - arena[1]))
        )
        self.controllers[k] = controller

    def _rebuild(self) -> None:
        """The batched controllers' rule, for the hunts they command (one spec, so one kind)."""
        self._batched = np.array([callable(getattr(type(c), "batched", None)) for c in self.controllers])
        mine = [c if batched else None for c, batched in zip(self.controllers, self._batched)]
        kinds = {type(c) for c in mine if c is not None}
        self._rule = getattr(kinds.pop(), "batched")(mine) if kinds else None

    def _still(self) -> np.ndarray:
        """Zero velocities for every defender of every hunt."""
        return np.zeros((self.num_envs, self._shape[0], 2))

    def _potential(self, b: Batch) -> np.ndarray:
        """Φ of :mod:`mpc_hunt.envs.episode` for every hunt."""
        distances = np.sqrt(np.sum((b.p_d - b.p_a[:, None, :]) ** 2, axis=-1))
        return distances.mean(axis=1) / self._scale

    def _observe(self, b: Batch, v_a: np.ndarray, v_d: np.ndarray) -> np.ndarray:
        """The observations (:mod:`mpc_hunt.envs.observation`) of every hunt."""
        B, n = self.num_envs, self._shape[0]
        time = (self.steps * b.prm[:, T])[:, None]
        defenders = np.concatenate([b.p_d, v_d], axis=2).reshape(B, 4 * n)
        intent = b.prm[:, [NOMINAL_X, NOMINAL_Y]]
        return np.concatenate([time, b.p_a, v_a, intent, defenders, self._static], axis=1)

    def _checked(self, actions) -> np.ndarray:
        """``actions`` as (num_envs, 2) finite floats, or an ActionError naming the first bad row."""
        what = "a velocity (vx, vy) in m/s per hunt, one row each"
        try:
            return checked_action(actions, self.actions_space, "actions", what)
        except ActionError:
            rows = np.asarray(actions, dtype=object)
            if rows.shape == (self.num_envs, 2):
                for k, row in enumerate(rows):
                    checked_action(row, self.single_action_space, f"actions[{k}]")
            raise

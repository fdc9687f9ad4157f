"""Many hunts of :class:`~mpc_hunt.envs.learning.AttackerViewEnv` at once: the PPO attacker's training hunts.

:class:`AttackerViewHunts` plays ``num_envs`` hunts of the view environment on the batched engine
(:class:`~mpc_hunt.envs.slots.HuntSlots`, teams of every size of ``teams`` in one batch): a step hands each hunt
its agent's action and runs the world's steps, all hunts together, until every hunt has reached its next
decision (it senses a defender and its action has been held ``decision_steps`` steps) or its end; a hunt that
ends is reset in the same call (Stable-Baselines3's convention: its last view in
``infos[k]["terminal_observation"]``), drawn and played to its first decision as the single environment's reset
does. Hunt k plays exactly what an ``AttackerViewEnv`` with the same arguments plays after
``reset(seed=seed + k)`` and ``reset()`` at each end (a test compares them step by step), so the networks it
trains play :mod:`mpc_hunt.world.behaviours.ppo` as before. :func:`mpc_hunt.envs.sb3.as_vec_env` hands it to
Stable-Baselines3; ``studies/train_ppo.py`` trains the attacker on it.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from mpc_hunt.compiled import kernel
from mpc_hunt.control.recommended import RECOMMENDED_CONTROLLER
from mpc_hunt.envs.base import checked_seed
from mpc_hunt.envs.learning import MAX_REDRAWS, AttackerViewEnv
from mpc_hunt.envs.slots import HuntSlots
from mpc_hunt.envs.vector import checked_count, checked_rows, slot_generators
from mpc_hunt.errors import ActionError, MpcHuntError
from mpc_hunt.world.agent_view import attacker_view
from mpc_hunt.world.behaviours.base import calm, near
from mpc_hunt.world.packed import SENSING, V_A, sensing_radius
from mpc_hunt.world.scenario import Scenario


@kernel
def sensing(p_a, p_d, n, prm) -> np.ndarray:
    """Does each hunt's attacker sense one of its defenders (within its sensing radius)?"""
    out = np.zeros(p_a.shape[0], dtype=np.bool_)
    for b in range(p_a.shape[0]):
        out[b] = near(p_a[b], p_d[b, : n[b]], prm[b, SENSING]).shape[0] > 0
    return out


@kernel
def calms(mask, p_a, centres, radii, m, prm, out) -> None:
    """``out[b]``: hunt b's undisturbed velocity (its intent and the obstacles' field), for each b of ``mask``."""
    for b in range(p_a.shape[0]):
        if mask[b]:
            out[b, 0], out[b, 1] = calm(p_a[b], centres[b, : m[b]], radii[b, : m[b]], prm[b])


class AttackerViewHunts:
    """``num_envs`` hunts of an AttackerViewEnv of ``controller``, ``teams`` and ``decision_steps`` at once (the
    module's docstring); the arguments checked as it checks them."""

    def __init__(
        self,
        num_envs: int,
        controller: str = RECOMMENDED_CONTROLLER,
        teams: tuple[int, ...] = (2, 3, 4, 5),
        decision_steps: int = 5,
    ):
        self.num_envs = checked_count(num_envs)
        one = AttackerViewEnv(controller, teams, decision_steps)  # every argument checked as it checks it
        self.decision_steps, self.envs = one.decision_steps, one.envs
        self.single_observation_space = one.observation_space
        self.single_action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float64)  # the view env's
        self.actions_space = spaces.Box(-1.0, 1.0, shape=(self.num_envs, 2), dtype=np.float64)
        self._shape = (max(e.hunts.team for e in self.envs), max(e.hunts.max_obstacles for e in self.envs))
        self._rngs: list[np.random.Generator] = []
        self.slots: HuntSlots | None = None

    def reset(self, seed: int | None = None) -> np.ndarray:
        """Every hunt drawn anew and played to its first decision, hunt k from the seed ``seed + k``: the views
        (num_envs, ATTACKER_VIEW)."""
        self._rngs = slot_generators(checked_seed(seed), self.num_envs)
        e = self.envs[0]
        self.slots = HuntSlots([self._draw(k) for k in range(self.num_envs)], *self._shape, e.controller_spec, e.belief)
        self._begin(np.ones(self.num_envs, dtype=bool), fresh=True)
        return self._views()

    def step(self, actions) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict]]:
        """Every hunt's next decision (``actions``: each agent's in [−1, 1]², clipped): (views, the rewards of the
        world's steps between summed, dones, infos), Stable-Baselines3's ``VecEnv.step_wait``."""
        slots, B = self._started(), self.num_envs
        actions = np.clip(checked_rows(actions, self.actions_space, self.single_action_space), -1.0, 1.0)
        rewards, ended, truncated = self._play(np.ones(B, dtype=bool), actions)
        views = self._views()
        infos = slots.infos(ended, truncated, views)
        if ended.any():
            self._begin(ended)
            views[ended] = self._views()[ended]
        return views, rewards, ended, infos

    def _started(self) -> HuntSlots:
        """The hunts, refused before the first reset."""
        if self.slots is None:
            raise ActionError("step: call reset() first")
        return self.slots

    def _draw(self, k: int) -> tuple[Scenario, np.random.Generator]:
        """Hunt k's next hunt as the view environment's reset draws it: a team, then the scenario and its
        controller's generator as that team's AttackerEnv draws them from the seed it is handed."""
        rng = self._rngs[k]
        env = self.envs[int(rng.integers(len(self.envs)))]
        world, other = np.random.default_rng(int(rng.integers(2**31))).spawn(2)
        return env.hunts.draw(world, None), other

    def _begin(self, mask: np.ndarray, fresh: bool = False) -> None:
        """The hunts of ``mask`` drawn anew (unless ``fresh``: drawn already) and played to their first decision;
        one that ends before it is drawn again, at most ``MAX_REDRAWS`` times."""
        slots = self._started()
        todo = mask.copy()
        for _ in range(MAX_REDRAWS):
            if not fresh:
                for k in np.flatnonzero(todo).tolist():
                    slots.start(k, *self._draw(k))
                slots.rebuild()
            fresh = False
            _, ended, _ = self._play(todo, None)
            todo = ended
            if not todo.any():
                return
        raise MpcHuntError(f"reset: {MAX_REDRAWS} hunts ended before the attacker sensed a defender")

    def _play(self, mask: np.ndarray, actions: np.ndarray | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The world's steps of the hunts of ``mask`` to their next decision, each holding its row of ``actions``
        (None: none yet, the first decision): (the summed rewards, which ended, which at the time limit)."""
        slots = self._started()
        b, B = slots.batch, self.num_envs
        held = np.where(mask, self.decision_steps if actions is not None else 0, 0)
        totals = np.zeros(B)
        ended, truncated = np.zeros(B, dtype=bool), np.zeros(B, dtype=bool)
        active = mask.copy()
        velocities = np.zeros((B, 2))
        while True:
            sensed = sensing(b.p_a, b.p_d, b.n, b.prm)
            held[active & ~sensed] = 0
            active &= ~sensed | (held > 0)  # a hunt that senses and holds nothing decides
            if not active.any():
                return totals, ended, truncated
            calms(active & ~sensed, b.p_a, b.centres, b.radii, b.m, b.prm, velocities)
            acting = active & sensed
            if actions is not None:
                velocities[acting] = b.prm[acting, V_A, None] * actions[acting]
            held[acting] -= 1
            rewards, now_ended, now_truncated = slots.advance(active, velocities)
            totals += rewards
            ended |= now_ended
            truncated |= now_truncated
            active &= ~now_ended

    def _views(self) -> np.ndarray:
        """Each hunt's attacker view (:func:`~mpc_hunt.world.agent_view.attacker_view`)."""
        b, slots = self._started().batch, self._started()
        return np.array([attacker_view(s, b.p_a[k], b.p_d[k, : b.n[k]], slots.v_d[k, : b.n[k]], sensing_radius(s))
                         for k, s in enumerate(b.scenarios)])  # fmt: skip

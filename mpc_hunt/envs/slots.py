"""The hunts of a vectorised environment, stepped together: each slot one AttackerEnv's hunt, on the batched engine.

:class:`HuntSlots` holds a batch of the engine (:mod:`mpc_hunt.sim.batch`) with, per slot, its hunt's controller,
step count, capture counter and the scale of its potential, and :meth:`HuntSlots.advance` takes the slots of a
mask one world step on with the attackers' velocities given: the defenders commanded (a batched controller's rule
in one call, any other slot by slot), the velocities applied as the world allows them (capped at v_a, kept out of
every obstacle), the world stepped and judged, and each slot's reward computed as
:class:`~mpc_hunt.envs.episode.Episode` computes it (the shaping Φ(s') − Φ(s), the end's ±1). The environments
(:mod:`mpc_hunt.envs.vector`) decide what the agent sees and when it is asked.
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.envs.episode import OUTCOME, mean_distances, potential_scale
from mpc_hunt.sim.batch import Batch, batched_groups
from mpc_hunt.sim.world_step import ENDS, NON_FINITE, RUNNING, step_batch
from mpc_hunt.world.behaviours.base import attacker_moves
from mpc_hunt.world.belief import Belief
from mpc_hunt.world.packed import T
from mpc_hunt.world.scenario import Scenario


class HuntSlots:
    """``starts`` (a scenario and the generator its controller is built with, per slot) as a batch padded to
    ``N`` defenders and ``M`` obstacles, the defenders commanded by ``spec`` on ``belief`` (the module's
    docstring)."""

    def __init__(
        self, starts: list[tuple[Scenario, np.random.Generator]], N: int, M: int, spec: ControllerSpec, belief: Belief
    ):
        B = len(starts)
        self.spec, self.belief = spec, belief
        self.batch = Batch([s for s, _ in starts], [None] * B, N, M)
        self.controllers: list = [None] * B
        self.steps = np.zeros(B, dtype=np.int64)
        self.held, self.status = np.zeros(B, dtype=np.int64), np.zeros(B, dtype=np.int64)
        self.scale = np.ones(B)  # Φ's: the arena's diagonal
        self.v_a, self.v_d = np.zeros((B, 2)), np.zeros((B, N, 2))  # velocities over the last step
        self.ends: list[str | None] = [None] * B  # how each slot's hunt ended (None while it runs)
        self._groups = batched_groups(self.controllers)  # the batched controllers' rules and their slots
        for k, (scenario, other) in enumerate(starts):
            self.start(k, scenario, other, put=False)
        self.rebuild()

    def start(self, k: int, scenario: Scenario, other: np.random.Generator, put: bool = True) -> None:
        """Slot k plays ``scenario`` from its start, its controller built with ``other`` (:meth:`rebuild` once
        every slot that starts is put)."""
        if put:
            self.batch.put(k, scenario)
        self.controllers[k] = self.spec.build(scenario, belief=self.belief, rng=other)
        self.steps[k], self.held[k], self.status[k], self.ends[k] = 0, 0, RUNNING, None
        self.v_a[k], self.v_d[k] = 0.0, 0.0
        self.scale[k] = potential_scale(scenario)

    def rebuild(self) -> None:
        """The batched controllers' rules, for the slots they command (:func:`~mpc_hunt.sim.batch.batched_groups`)."""
        self._groups = batched_groups(self.controllers)

    def advance(self, active: np.ndarray, velocities: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """One world step of the slots of ``active``, their attackers at ``velocities`` (B, 2; the other rows
        unread): (each slot's reward, 0 where not active; which ended; which of those at the time limit)."""
        b = self.batch
        B, N = len(self.controllers), b.p_d.shape[1]
        commands = np.zeros((B, N, 2))
        capture, intercepts = np.zeros((B, N), dtype=bool), np.zeros((B, N, 2))
        failed = self.steps[:, None] * b.prm[:, T, None] >= b.fails_at
        for k in np.flatnonzero(active & ~self._groups.batched).tolist():
            commands[k, : b.n[k]] = self.controllers[k].command(b.observation(k, int(self.steps[k]))).velocities
        previous = np.where((self.steps == 0)[:, None], np.nan, b.previous)
        for rule, mine in self._groups.groups:
            rule.commands(active & mine, b.p_a, previous, b.p_d, b.n, failed, commands, capture, intercepts)
        attacker_v = np.zeros((B, 2))
        attacker_moves(active, velocities, b.p_a, b.centres, b.radii, b.m, b.prm, attacker_v)
        before_a, before_d = b.p_a.copy(), b.p_d.copy()
        potential = mean_distances(b.p_a, b.p_d, b.n) / self.scale
        b.previous[active] = b.p_a[active]
        step_batch(active, self.steps, b.p_a, b.p_d, b.n, commands, attacker_v, b.fails_at, b.speeds, b.centres,
                   b.radii, b.m, b.prm, self.held, b.hold, self.status)  # fmt: skip
        self.steps[active] += 1
        period = b.prm[active, T, None]
        self.v_a[active] = (b.p_a[active] - before_a[active]) / period
        self.v_d[active] = (b.p_d[active] - before_d[active]) / period[:, :, None]
        truncated = active & (self.status == RUNNING) & (self.steps >= b.max_steps)
        ended = active & ((self.status != RUNNING) | truncated)
        shaping = np.where(self.status == NON_FINITE, 0.0, mean_distances(b.p_a, b.p_d, b.n) / self.scale - potential)
        rewards = np.where(active, shaping, 0.0)
        for k in np.flatnonzero(ended).tolist():
            how = "time_limit" if truncated[k] else ENDS[int(self.status[k])]
            self.ends[k] = how
            rewards[k] += OUTCOME[how]
        return rewards, ended, truncated

    def infos(self, ended: np.ndarray, truncated: np.ndarray, last: np.ndarray) -> list[dict]:
        """Each slot's info after a step (an environment's: its time, how it ended, its scenario), with, for one
        that ended, Stable-Baselines3's ``terminal_observation`` (its row of ``last``) and
        ``TimeLimit.truncated``."""
        infos = []
        for k in range(len(self.controllers)):
            info = {"time": float(self.steps[k] * self.batch.prm[k, T]), "termination": self.ends[k],
                    "scenario": self.batch.scenarios[k].name}  # fmt: skip
            if ended[k]:
                info |= {"terminal_observation": last[k].copy(), "TimeLimit.truncated": bool(truncated[k])}
            infos.append(info)
        return infos

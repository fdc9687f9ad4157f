"""A hunt as a PettingZoo ``ParallelEnv``: the attacker and every defender are agents, all acting at once.

Agents ``attacker`` and ``defender_0`` … ``defender_{n−1}``. Each observes the
whole state (:mod:`mpc_hunt.envs.observation`); the attacker's action is its
velocity within ± the fastest attacker the hunts hold, a defender's its own
velocity within ± the fastest defender's speed (the world caps each at its
robot's speed and keeps the attacker out of obstacles). ``step`` takes one action
per agent of ``agents``, each checked by :mod:`mpc_hunt.envs.actions`; a missing or an
unknown agent is an :class:`~mpc_hunt.errors.ActionError` naming it. The attacker receives
the reward of :mod:`mpc_hunt.envs.episode`, every defender its negative. When the
hunt ends every agent is done (``terminations`` for a capture, an escape or a
non-finite state; ``truncations`` at the time limit) and ``agents`` empties; a step
then is refused until a reset.
"""

from __future__ import annotations

import functools

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from mpc_hunt.envs.actions import checked_action
from mpc_hunt.envs.base import RENDER_MODES, check_render_mode, checked_seed
from mpc_hunt.envs.episode import Episode
from mpc_hunt.envs.hunts import Hunts
from mpc_hunt.envs.observation import observation_space
from mpc_hunt.errors import ActionError, MpcHuntError
from mpc_hunt.sweep.random_scenario import ScenarioRanges
from mpc_hunt.world.scenario import Scenario

ATTACKER = "attacker"


class HuntParallelEnv(ParallelEnv):
    """Every robot of a hunt as an agent (the module's docstring)."""

    metadata = {"name": "mpc_hunt_v0", "render_modes": RENDER_MODES, "render_fps": 10, "is_parallelizable": True}

    def __init__(
        self,
        scenario: Scenario | None = None,
        ranges: ScenarioRanges | None = None,
        defenders: int | None = None,
        render_mode: str | None = None,
    ):
        check_render_mode(render_mode)
        self.hunts, self.render_mode = Hunts(scenario, ranges, defenders), render_mode
        self.possible_agents = [ATTACKER] + [f"defender_{i}" for i in range(self.hunts.team)]
        self.agents: list[str] = []
        self.episode: Episode | None = None
        self.rng: np.random.Generator | None = None
        self._observation = observation_space(
            self.hunts.team,
            self.hunts.max_obstacles,
            max(self.hunts.attacker_speed, self.hunts.defender_speed),
            self.hunts.time_step,
        )

    @functools.cache
    def observation_space(self, agent: str) -> spaces.Box:
        return self._observation

    @functools.cache
    def action_space(self, agent: str) -> spaces.Box:
        speed = self.hunts.attacker_speed if agent == ATTACKER else self.hunts.defender_speed
        return spaces.Box(-speed, speed, shape=(2,), dtype=np.float64)

    def reset(self, seed: int | None = None, options: dict | None = None):
        given, seed = self.hunts.given(options), checked_seed(seed)  # before anything changes
        if seed is not None or self.rng is None:  # as Gymnasium's: an unseeded reset goes on with the stream
            self.rng = np.random.default_rng(seed)
        self.episode = Episode(self.hunts.draw(self.rng, given), self.hunts.max_obstacles)
        self.agents = list(self.possible_agents)
        observation = self.episode.observation()
        return {a: observation.copy() for a in self.agents}, {a: self.episode.info() for a in self.agents}

    def step(self, actions: dict):
        if self.episode is None:
            raise MpcHuntError("step: call reset() first")
        e = self.episode.running()
        checked = self._checked(actions)
        team = np.array([checked[a] for a in self.possible_agents[1:]])
        outcome = e.step(team, e.attacker_move(checked[ATTACKER]))
        observation = e.observation()
        agents = self.agents
        rewards = {a: outcome.reward if a == ATTACKER else -outcome.reward for a in agents}
        observations = {a: observation.copy() for a in agents}
        terminations = {a: outcome.terminated for a in agents}
        truncations = {a: outcome.truncated for a in agents}
        infos = {a: e.info() for a in agents}
        if outcome.terminated or outcome.truncated:
            self.agents = []
        return observations, rewards, terminations, truncations, infos

    def _checked(self, actions: dict) -> dict[str, np.ndarray]:
        """Every agent's action checked (:mod:`mpc_hunt.envs.actions`): one for each agent, no other."""
        if not isinstance(actions, dict):
            raise ActionError(
                f"actions: a dict of one action per agent ({', '.join(self.agents)}), got {type(actions).__name__}"
            )
        missing = [a for a in self.agents if a not in actions]
        unknown = [repr(a) for a in actions if a not in self.agents]
        wrong = ([f"no action for {', '.join(missing)}"] if missing else []) + (
            [f"unknown agent {', '.join(unknown)}"] if unknown else []
        )
        if wrong:
            raise ActionError(
                f"actions: {'; '.join(wrong)} (one action per agent of env.agents: {', '.join(self.agents)})"
            )
        return {a: checked_action(actions[a], self.action_space(a), f"actions[{a!r}]") for a in self.agents}

    def render(self):
        return self.episode.image() if self.render_mode == "rgb_array" and self.episode is not None else None

    def close(self) -> None:
        self.episode = None

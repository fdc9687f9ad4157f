"""What the Gymnasium environments share: the hunts, the episode, the spaces, seeding and rendering."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from mpc_hunt.envs.actions import checked_action
from mpc_hunt.envs.episode import Episode
from mpc_hunt.envs.hunts import Hunts
from mpc_hunt.envs.observation import observation_space
from mpc_hunt.errors import MpcHuntError, OptionError

RENDER_MODES = ["rgb_array"]


def check_render_mode(render_mode: object) -> None:
    if render_mode is not None and render_mode not in RENDER_MODES:
        raise OptionError(f"render_mode: one of {RENDER_MODES} or None, not {render_mode!r}")


def checked_seed(seed: object, where: str = "seed") -> int | None:
    """A seed of the environments (a reset's, :class:`~mpc_hunt.envs.learning.TeamHunts`'): None (fresh entropy) or
    a whole number of any size from 0, as NumPy's generators take; anything else an :class:`OptionError` naming
    ``where``, before anything changes."""
    if seed is None:
        return None
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise OptionError(f"{where}: a whole number from 0, or None, got {type(seed).__name__} {str(seed)[:40]!r}")
    value = int(seed)
    if value < 0:
        got = value if value.bit_length() <= 64 else "a negative number"
        raise OptionError(f"{where}: must not be negative (a whole number from 0, or None), got {got}")
    return value


class HuntEnv(gym.Env):
    """One side of a hunt as a Gymnasium environment; the other side is scripted (the subclass's)."""

    metadata = {"render_modes": RENDER_MODES, "render_fps": 10}
    action_space: spaces.Box  # each side's: a velocity, or one per defender

    def __init__(self, hunts: Hunts, render_mode: str | None = None):
        check_render_mode(render_mode)
        self.hunts, self.render_mode = hunts, render_mode
        self.observation_space = observation_space(
            hunts.team, hunts.max_obstacles, max(hunts.attacker_speed, hunts.defender_speed), hunts.time_step
        )
        self.episode: Episode | None = None

    def new_episode(self, seed: int | None, options: dict | None) -> np.random.Generator:
        """Seed (Gymnasium's ``np_random``), draw the hunt, start its episode; the generator for what else the
        reset draws (the other side's randomness)."""
        given = self.hunts.given(options)  # before anything changes
        super().reset(seed=checked_seed(seed))
        world, other = self.np_random.spawn(2)
        self.episode = Episode(self.hunts.draw(world, given), self.hunts.max_obstacles)
        return other

    @property
    def scenario(self):
        return None if self.episode is None else self.episode.scenario

    @property
    def current(self) -> Episode:
        """The episode of the last reset, ended or not: refused before the first reset."""
        if self.episode is None:
            raise MpcHuntError("call reset() first")
        return self.episode

    def started(self) -> Episode:
        """The running episode: a step before the first reset, or after the hunt has ended, is refused."""
        if self.episode is None:
            raise MpcHuntError("step: call reset() first")
        return self.episode.running()

    def checked(self, action) -> np.ndarray:
        """The agent's ``action`` checked against its space (:mod:`mpc_hunt.envs.actions`)."""
        return checked_action(action, self.action_space, "action")

    def info(self) -> dict:
        return self.current.info()

    def render(self):
        return self.episode.image() if self.render_mode == "rgb_array" and self.episode is not None else None

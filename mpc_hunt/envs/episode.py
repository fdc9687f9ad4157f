"""One hunt stepped by agents: the world's step of the simulator, the observation, the rewards, how it ends.

Rewards are the attacker's; the defenders share its negative (a zero-sum game).
At the end: −1 when the defenders capture it (the success test, Eqs. 4–5, held
for ``hold_time``), +1 when it leaves the arena or the time limit comes (the hunt
has failed, as the project's sweeps count it); 0 for a state that is no longer
finite (an error, not an outcome; the environments' checked actions and capped
velocities leave only a failing controller or behaviour to cause one). A hunt that
has ended takes no step until a reset, so its end is paid once. Each step adds the
potential-based shaping Φ(s') − Φ(s) with Φ = the defenders' mean distance to the
attacker / the arena's diagonal (20 m without an arena): encircling and closing in
is progress for the defenders long before a capture, and a potential difference
changes no optimal policy (Ng, Harada and Russell, ICML 1999); over a hunt it sums
to at most ±1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.control.controller import Observation
from mpc_hunt.envs.observation import observe
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.plots.state import state_image
from mpc_hunt.sim.world_step import moved, standing, steps
from mpc_hunt.world.behaviours.base import attacker_move
from mpc_hunt.world.geometry import length
from mpc_hunt.world.scenario import Scenario

OUTCOME = {"captured": -1.0, "attacker_escaped": 1.0, "time_limit": 1.0, "non_finite_state": 0.0}
NO_ARENA_DIAGONAL = 20.0  # m: Φ's scale for a scenario with no arena


def potential_scale(scenario: Scenario) -> float:
    """Φ's denominator: the arena's diagonal, ``NO_ARENA_DIAGONAL`` without an arena."""
    arena = scenario.arena
    return NO_ARENA_DIAGONAL if arena is None else float(np.hypot(arena[2] - arena[0], arena[3] - arena[1]))


@kernel
def mean_distances(p_a: np.ndarray, p_d: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Each hunt's defenders' mean distance to its attacker (hunt b's first ``n[b]`` rows of ``p_d``), summed in
    order: Φ's numerator, for one hunt (a batch of one) or many."""
    out = np.empty(p_a.shape[0])
    for b in range(p_a.shape[0]):
        total = 0.0
        for i in range(n[b]):
            total += length(p_d[b, i, 0] - p_a[b, 0], p_d[b, i, 1] - p_a[b, 1])
        out[b] = total / n[b]
    return out


@dataclass(frozen=True)
class Step:
    """What a step returns: the attacker's reward, whether the hunt ended (``terminated``: captured, escaped or
    not finite) or was cut at the time limit (``truncated``), and how (``termination``, None while it runs)."""

    reward: float
    terminated: bool
    truncated: bool
    termination: str | None


class Episode:
    """The state of one hunt of ``scenario`` and its step (the module's docstring)."""

    def __init__(self, scenario: Scenario, max_obstacles: int):
        self.scenario, self.max_obstacles = scenario, max_obstacles
        self.max_steps, self.hold_steps = steps(scenario)
        self.step_count, self.held = 0, 0
        self.termination: str | None = None
        self.attacker = np.array(scenario.attacker.start, dtype=float)
        self.defenders = scenario.defender_starts.copy()
        self.attacker_velocity = np.zeros(2)
        self.defender_velocities = np.zeros_like(self.defenders)
        self.previous_attacker: np.ndarray | None = None
        self.trail = [self.attacker.copy()]
        self.scale = potential_scale(scenario)
        self.potential = self._potential()

    @property
    def time(self) -> float:
        return self.step_count * self.scenario.hunt.time_step

    def observation(self) -> np.ndarray:
        return observe(
            self.scenario,
            self.time,
            self.attacker,
            self.attacker_velocity,
            self.defenders,
            self.defender_velocities,
            self.max_obstacles,
        )

    def controller_observation(self) -> Observation:
        """What a controller of the project is handed at this state (:mod:`mpc_hunt.control.controller`)."""
        stopped = self.scenario.failed(self.time)
        return Observation(
            self.time,
            self.attacker.copy(),
            self.previous_attacker,
            self.defenders.copy(),
            stopped if stopped.any() else None,
        )

    def attacker_move(self, action) -> np.ndarray:
        return attacker_move(self.scenario, self.attacker, action)

    def info(self) -> dict:
        """What an environment's ``info`` holds: the time, how the hunt ended (None while it runs), its name."""
        return {"time": self.time, "termination": self.termination, "scenario": self.scenario.name}

    def image(self) -> np.ndarray:
        """The state drawn (``render_mode="rgb_array"``): an (H, W, 3) uint8 array."""
        return state_image(self.scenario, self.time, self.attacker, self.defenders, self.trail)

    def _potential(self) -> float:
        """Φ of the module's docstring at the current state."""
        one = np.array([len(self.defenders)])
        return float(mean_distances(self.attacker[None], self.defenders[None], one)[0]) / self.scale

    @property
    def ended(self) -> bool:
        return self.termination is not None

    def running(self) -> "Episode":
        """This episode, unless it has ended: a step after the end is refused (its ±1 is paid once) until a reset."""
        if self.ended:
            raise MpcHuntError(f"step: the hunt has ended ({self.termination}); call reset() to start another")
        return self

    def step(self, defender_velocities, attacker_velocity: np.ndarray) -> Step:
        """One step of the world with these velocities (the defenders' capped at their speeds), while it runs."""
        self.running()
        before = self.potential
        stopped = self.scenario.failed(self.time)
        previous_a, previous_d = self.attacker, self.defenders
        self.previous_attacker = previous_a.copy()
        self.attacker, self.defenders = moved(
            self.scenario,
            previous_a,
            previous_d,
            np.asarray(defender_velocities, dtype=float).reshape(-1, 2),
            attacker_velocity,
            stopped,
        )
        T = self.scenario.hunt.time_step
        self.attacker_velocity = (self.attacker - previous_a) / T
        self.defender_velocities = (self.defenders - previous_d) / T
        self.step_count += 1
        self.trail.append(self.attacker.copy())
        ended, self.held = standing(self.scenario, self.attacker, self.defenders, self.held, self.hold_steps)
        truncated = ended is None and self.step_count >= self.max_steps
        self.termination = "time_limit" if truncated else ended
        self.potential = self._potential()
        shaping = 0.0 if ended == "non_finite_state" else self.potential - before
        reward = shaping + (OUTCOME[self.termination] if self.termination else 0.0)
        return Step(reward, ended is not None, truncated, self.termination)

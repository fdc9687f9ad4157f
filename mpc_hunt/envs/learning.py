"""The hunts the PPO agents train on, as they will play them: their views, their decision steps, their shield.

- :class:`AttackerViewEnv` (Gymnasium): the attacker of an :class:`~mpc_hunt.envs.AttackerEnv`
  against a controller, as :mod:`mpc_hunt.world.behaviours.ppo` moves it: while it senses no
  defender it follows its intent and the agent is not asked; while it senses one, the
  agent reads :func:`~mpc_hunt.world.agent_view.attacker_view` and its action a in [−1, 1]²
  (velocity v_a · a) is held for ``decision_steps`` of the world's steps, or until it senses
  nobody. A step returns at the next decision (or the hunt's end) with the rewards of the
  world's steps between summed. Each reset draws the team's size from ``teams`` (one
  AttackerEnv per size), so the policy meets every size the sweeps play, and plays the
  hunt to its first decision (a hunt that ends before it is replaced by another).
  ``reset(options={"scenario": s})`` plays ``s`` with its own team, whatever ``teams`` holds:
  the agent's view and action are the same for any team (``ATTACKER_VIEW`` numbers, a
  velocity), so no team size is drawn for it; one of a size not in ``teams`` gets an
  AttackerEnv of its own, built once.
- :class:`TeamHunts`: ``hunts`` hunts of :class:`~mpc_hunt.envs.DefenderEnv`, each defender an
  agent sharing one policy, as :mod:`mpc_hunt.control.ppo_team` plays it: the agent reads
  :func:`~mpc_hunt.control.ppo_team.team_views` and its action is a correction of the Voronoi
  baseline's velocity, held for ``decision_steps`` steps while the baseline is recomputed at
  each (:func:`~mpc_hunt.control.ppo_team.corrected`, the shield included); each reset draws
  the attacker's behaviour from ``attackers``. A finished
  hunt starts the next at once; its last views are kept for the learner
  (``terminal_views``). Stable-Baselines3 steps it through a ``VecEnv`` of one slot per
  defender (studies/train_ppo.py). Its arguments are checked when it is built, each refusal an
  :class:`~mpc_hunt.errors.OptionError` naming the argument: ``hunts`` a whole number from 1 to
  MAX_TEAM_HUNTS, ``attackers`` a tuple of distinct behaviour names, ``seed`` a whole number
  from 0 or None.

Playing a trained network through :mod:`mpc_hunt.world.behaviours.ppo` or
:mod:`mpc_hunt.control.ppo_team` gives the hunts these environments give it (a test checks).
"""

from __future__ import annotations

from typing import cast

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from mpc_hunt.arguments import out_of_range
from mpc_hunt.control.ppo_team import corrected, team_views
from mpc_hunt.control.recommended import RECOMMENDED_CONTROLLER
from mpc_hunt.control.voronoi import VoronoiController
from mpc_hunt.envs.actions import checked_action
from mpc_hunt.envs.attacker_env import AttackerEnv
from mpc_hunt.envs.base import checked_seed
from mpc_hunt.envs.defender_env import DefenderEnv
from mpc_hunt.errors import MpcHuntError, OptionError
from mpc_hunt.world.agent_view import ATTACKER_VIEW, attacker_view
from mpc_hunt.world.behaviours import BEHAVIOURS
from mpc_hunt.world.behaviours.base import sensed, undisturbed
from mpc_hunt.world.mlp import MAX_DECISION_STEPS
from mpc_hunt.world.packed import sensing_radius
from mpc_hunt.world.scenario import Scenario

BOUND = 1e3  # a view's numbers are within a few REACH; the Box says so loosely
MAX_REDRAWS = 100  # hunts a reset may draw before one reaches its first decision
# TeamHunts' hunts side by side: each holds a DefenderEnv per attacker (with the seven the training plays, about
# 30 kB and 12 ms to build and reset) and one process steps them all in turn: 10 000 take two minutes and 300 MB
# before the first step, far beyond the 4 the training plays (studies/train_ppo.py, TEAM_HUNTS).
MAX_TEAM_HUNTS = 10_000


def _decision_steps(value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 1 <= value <= MAX_DECISION_STEPS:
        raise OptionError(f"decision_steps: a whole number from 1 to {MAX_DECISION_STEPS}, got {value!r}")
    return int(value)


def _hunts(value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise OptionError(
            f"hunts: a whole number from 1 to {MAX_TEAM_HUNTS}, got {type(value).__name__} {repr(value)[:40]}"
        )
    why = out_of_range(int(value), 1, MAX_TEAM_HUNTS)
    if why:
        raise OptionError(f"hunts: {why}")
    return int(value)


def _attackers(value) -> tuple[str, ...]:
    """``attackers``: a tuple (or list) of distinct behaviour names, at least one."""
    known = f"behaviour names ({', '.join(BEHAVIOURS)})"
    if not isinstance(value, (tuple, list)):
        hint = f"; for one, give ({value!r},)" if isinstance(value, str) else ""
        raise OptionError(f"attackers: a tuple of {known}, got {type(value).__name__} {str(value)[:40]!r}{hint}")
    if not value:
        raise OptionError(f"attackers: empty; give at least one of the {known} (one is drawn per hunt)")
    unknown = [repr(name) for name in value if not isinstance(name, str) or name not in BEHAVIOURS]
    if unknown:
        raise OptionError(f"attackers: unknown behaviour {', '.join(unknown)[:200]}; give {known}")
    twice = sorted({name for name in value if value.count(name) > 1})
    if twice:
        raise OptionError(
            f"attackers: {', '.join(twice)} more than once; name each once (each hunt draws one, all alike)"
        )
    return tuple(value)


class AttackerViewEnv(gym.Env):
    """The attacker learning against ``controller`` on random hunts (the module's docstring)."""

    def __init__(
        self, controller: str = RECOMMENDED_CONTROLLER, teams: tuple[int, ...] = (2, 3, 4, 5), decision_steps: int = 5
    ):
        self.decision_steps = _decision_steps(decision_steps)
        if not teams or any(isinstance(t, bool) or not isinstance(t, (int, np.integer)) for t in teams):
            raise OptionError(f"teams: team sizes (whole numbers), got {teams!r}")
        self.envs = [AttackerEnv(defenders=int(t), controller=controller) for t in teams]
        self._controller, self.others = controller, dict[int, AttackerEnv]()  # for a given hunt of another team
        self.env = self.envs[0]
        self.observation_space = spaces.Box(-BOUND, BOUND, shape=(ATTACKER_VIEW,), dtype=np.float64)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float64)

    def _view(self) -> np.ndarray:
        e = self.env.current
        return attacker_view(e.scenario, e.attacker, e.defenders, e.defender_velocities, sensing_radius(e.scenario))

    def _sensing(self) -> bool:
        e = self.env.current
        return len(sensed(e.attacker, e.defenders, sensing_radius(e.scenario))) > 0

    def _run(self, action: np.ndarray | None) -> tuple[float, bool, bool, dict]:
        """The world's steps to the next decision (the module's docstring): the summed reward, how it ended."""
        held, total = (self.decision_steps if action is not None else 0), 0.0
        terminated = truncated = False
        info = self.env.info()
        while True:
            if not self._sensing():
                held, velocity = 0, undisturbed(self.env.scenario, self.env.current.attacker)
            elif held == 0:
                return total, False, False, info
            else:
                held, velocity = held - 1, self.env.scenario.attacker.max_speed * action
            _, reward, terminated, truncated, info = self.env.step(velocity)
            total += reward
            if terminated or truncated:
                return total, terminated, truncated, info

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=checked_seed(seed))
        scenario = options.get("scenario") if isinstance(options, dict) else None
        given = scenario is not None
        for _ in range(1 if given else MAX_REDRAWS):
            if not given:
                self.env = self.envs[int(self.np_random.integers(len(self.envs)))]
            else:  # its own team (the module's docstring); anything but a Scenario refused by the env's reset
                self.env = self._team_of(scenario) if isinstance(scenario, Scenario) else self.envs[0]
            _, info = self.env.reset(seed=int(self.np_random.integers(2**31)), options=options)
            _, terminated, truncated, info = self._run(None)
            if not (terminated or truncated):
                return self._view(), info
        raise MpcHuntError(
            "reset: options['scenario'] ends before the attacker senses a defender, so the agent has "
            "nothing to decide; give a hunt whose defenders come within its sensing radius"
            if given
            else f"reset: {MAX_REDRAWS} hunts ended before the attacker sensed a defender"
        )

    def _team_of(self, scenario: Scenario) -> AttackerEnv:
        """The AttackerEnv of ``scenario``'s team: ``teams``' one, else its own, built once."""
        team = len(scenario.defenders)
        env = next((e for e in self.envs if e.hunts.team == team), None) or self.others.get(team)
        if env is None:
            env = self.others[team] = AttackerEnv(defenders=team, controller=self._controller)
        return env

    def step(self, action):
        self.env.started()  # refused before the first reset, or after the hunt ended
        a = np.clip(checked_action(action, self.action_space, "action"), -1.0, 1.0)  # before anything moves
        total, terminated, truncated, info = self._run(a)
        return self._view(), total, terminated, truncated, info


class TeamHunts:
    """``hunts`` hunts of a team of ``defenders`` sharing one policy (the module's docstring)."""

    def __init__(
        self, hunts: int, attackers: tuple[str, ...], defenders: int = 3, decision_steps: int = 5, seed: int | None = 0
    ):
        self.decision_steps = _decision_steps(decision_steps)
        hunts, attackers, seed = _hunts(hunts), _attackers(attackers), checked_seed(seed)  # before any is built
        self.defenders = defenders
        self.envs = [
            {name: DefenderEnv(defenders=defenders, attacker=name) for name in attackers} for _ in range(hunts)
        ]
        self.rng = np.random.default_rng(seed)
        self.playing: list[DefenderEnv | None] = [None] * hunts
        self.bases: list[VoronoiController | None] = [None] * hunts
        self.next_base: list[np.ndarray | None] = [None] * hunts  # the base at each hunt's state, once
        self.terminal_views: list[np.ndarray | None] = [None] * hunts

    @property
    def agents(self) -> int:
        return len(self.envs) * self.defenders

    def _start(self, k: int) -> None:
        names = list(self.envs[k])
        env = self.envs[k][names[int(self.rng.integers(len(names)))]]
        env.reset(seed=int(self.rng.integers(2**31)))
        self.start(k, env)

    def start(self, k: int, env: DefenderEnv) -> None:
        """Hunt ``k`` goes on as ``env``'s (reset, its hunt just begun), with a new baseline."""
        self.playing[k], self.bases[k], self.next_base[k] = env, VoronoiController(env.current.scenario), None

    def _playing(self, k: int) -> DefenderEnv:
        """The environment hunt ``k`` goes on in: refused before the first reset."""
        env = self.playing[k]
        if env is None:
            raise MpcHuntError("call reset() first")
        return env

    def _base(self, k: int) -> np.ndarray:
        """The baseline's velocities at hunt ``k``'s state, computed once for that state."""
        base, self.next_base[k] = self.next_base[k], None
        if base is None:
            base = (
                cast(VoronoiController, self.bases[k])
                .command(self._playing(k).current.controller_observation())
                .velocities
            )
        return base

    def views(self, k: int) -> np.ndarray:
        """Hunt ``k``'s views, one row per defender (:func:`~mpc_hunt.control.ppo_team.team_views`)."""
        e, base = self._playing(k).current, self._base(k)
        self.next_base[k] = base  # the state's first step uses it again
        return team_views(e.scenario, e.attacker, e.attacker_velocity, e.defenders, e.defender_velocities, base)

    def reset(self) -> np.ndarray:
        """Every hunt started anew: the views, one row per agent (hunt by hunt)."""
        for k in range(len(self.envs)):
            self._start(k)
        return np.vstack([self.views(k) for k in range(len(self.envs))])

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict]]:
        """One decision of every agent (``actions``: a correction in [−1, 1]² each): the views after it, each
        agent's reward (its team's), whether its hunt ended, and an info per hunt (``termination``, ``truncated``,
        and ``behaviour``, the attacker's) for a hunt that ended, else {}."""
        if self.playing[0] is None:
            raise MpcHuntError("step: call reset() first")
        actions = np.clip(
            checked_action(
                actions,
                spaces.Box(-1.0, 1.0, (self.agents, 2)),
                "actions",
                "a correction (ax, ay) in [-1, 1] per agent, one row each",
            ),
            -1.0,
            1.0,
        ).reshape(len(self.envs), self.defenders, 2)  # before anything moves
        views, rewards, dones, infos = [], [], [], []
        for k in range(len(self.envs)):
            env = self._playing(k)
            e = env.current
            total, ended, info = 0.0, False, {}
            for _ in range(self.decision_steps):
                active = ~e.scenario.failed(e.time)
                velocities = corrected(e.scenario, e.defenders, self._base(k), actions[k], active)
                _, reward, terminated, truncated, _ = env.step(velocities)
                total += reward
                if terminated or truncated:
                    ended = True
                    info = {"termination": e.termination, "truncated": bool(truncated), "behaviour": env.attacker_name}
                    break
            if ended:
                self.terminal_views[k] = self.views(k)
                self._start(k)
            views.append(self.views(k))
            rewards += [total] * self.defenders
            dones += [ended] * self.defenders
            infos.append(info)
        return np.vstack(views), np.array(rewards), np.array(dones), infos

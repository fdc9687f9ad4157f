"""Between the environments and the simulator: the project's controllers as policies, any policy as an attacker.

:class:`ControllerPolicy` plays the defenders of a :class:`~mpc_hunt.envs.DefenderEnv`
with a controller of the project (a baseline for a learned team, or the expert of
imitation learning). :class:`PolicyAttacker` moves the simulator's attacker by
any policy of the attacker's observation (a trained agent of
:class:`~mpc_hunt.envs.AttackerEnv`): ``simulate(scenario, behaviour=PolicyAttacker(scenario, policy))``.
"""

from __future__ import annotations

from typing import Callable, cast

import numpy as np

from mpc_hunt.control.controller import Controller
from mpc_hunt.control.recommended import RECOMMENDED_CONTROLLER
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.envs.episode import Episode
from mpc_hunt.envs.observation import observe
from mpc_hunt.errors import OptionError, SettingError
from mpc_hunt.world.behaviours.base import attacker_move
from mpc_hunt.world.belief import Belief
from mpc_hunt.world.scenario import Scenario


def controller_spec(
    controller: str | ControllerSpec, options: dict | None, argument: str, probe: Scenario, belief: Belief
) -> ControllerSpec:
    """An environment's controller: a spec, or a name with ``options`` (:meth:`ControllerSpec.of`; a field not given
    takes its default), checked once on the hunt ``probe`` (:meth:`ControllerSpec.probed`); a refusal is an
    :class:`OptionError` naming the environment's argument (``controller`` or ``argument``)."""
    if isinstance(controller, ControllerSpec):
        if options is not None:
            raise OptionError(
                f"{argument}: the spec {controller.label!r} holds its options: give them in it "
                f"(ControllerSpec(..., options=...)), or give the controller by name"
            )
        spec = controller
    else:
        if options is not None and not isinstance(options, dict):
            raise OptionError(f"{argument}: a dict of the controller's options or None, got {type(options).__name__}")
        try:
            spec = ControllerSpec.of(controller, options)
        except SettingError as exc:
            raise (exc if exc.fields == ("controller",) else OptionError(f"{argument}: {exc}")) from None
    spec.probed(probe, belief=belief, argument=argument)
    return spec


class ControllerPolicy:
    """``policy(observation) → the team's velocities`` by ``controller`` (a name with ``options``, or a
    :class:`ControllerSpec`) for the hunt ``env`` plays, built anew for each hunt the environment starts."""

    def __init__(
        self,
        env,
        controller: str | ControllerSpec = RECOMMENDED_CONTROLLER,
        options: dict | None = None,
        belief: Belief = Belief(),
        seed: int = 0,
    ):
        self.env, self.belief = env, belief
        self.spec = controller_spec(controller, options, "options", env.hunts.probe(), belief)
        self.rng = np.random.default_rng(seed)
        self.episode: Episode | None = None
        self.controller: Controller | None = None

    def __call__(self, observation: np.ndarray) -> np.ndarray:
        episode: Episode = self.env.episode
        if self.episode is not episode:  # a new hunt: a new controller (it keeps memory)
            self.episode = episode
            self.controller = self.spec.build(episode.scenario, belief=self.belief, rng=self.rng)
        return cast(Controller, self.controller).command(episode.controller_observation()).velocities


class PolicyAttacker:
    """An attacker behaviour (:mod:`mpc_hunt.world.behaviours`) moved by ``policy(observation) → velocity``,
    capped at v_a and kept out of every obstacle as an environment's attacker is."""

    def __init__(
        self, scenario: Scenario, policy: Callable[[np.ndarray], np.ndarray], max_obstacles: int | None = None
    ):
        self.scenario, self.policy = scenario, policy
        self.max_obstacles = len(scenario.obstacles) if max_obstacles is None else max_obstacles
        self.steps = 0
        self.last: tuple[np.ndarray, np.ndarray] | None = None

    def velocity(self, p_a: np.ndarray, p_d: np.ndarray) -> np.ndarray:
        T = self.scenario.hunt.time_step
        v_a, v_d = (
            (np.zeros(2), np.zeros_like(p_d))
            if self.last is None
            else ((p_a - self.last[0]) / T, (p_d - self.last[1]) / T)
        )
        observation = observe(self.scenario, self.steps * T, p_a, v_a, p_d, v_d, self.max_obstacles)
        self.steps += 1
        self.last = (np.array(p_a, dtype=float), np.array(p_d, dtype=float))
        return attacker_move(self.scenario, p_a, self.policy(observation))

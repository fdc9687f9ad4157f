"""Hunts as Gymnasium and PettingZoo environments (the optional extra ``pip install "mpc-hunt[envs]"``).

- :class:`HuntParallelEnv`: PettingZoo ``ParallelEnv``, the attacker and every defender as agents;
- :class:`AttackerEnv`: Gymnasium, the attacker against a controller of the project (the recommended one);
- :class:`DefenderEnv`: Gymnasium, the defending team against an attacker behaviour of the world;
- :class:`AttackerHunts`: many ``AttackerEnv`` hunts stepped in one call by the batched engine
  (:mod:`mpc_hunt.envs.vector`; Stable-Baselines3 takes it as a ``VecEnv``, :func:`mpc_hunt.envs.sb3.as_vec_env`),
  :class:`AttackerViewHunts` the PPO attacker's training hunts so (:mod:`mpc_hunt.envs.view_hunts`);
- :class:`ControllerPolicy`, :class:`PolicyAttacker`: the project's controllers as policies, a policy as the
  simulator's attacker.

Each builds with no arguments (random hunts of three defenders, drawn from the reset's seed); the Gymnasium
ones are registered as ``mpc_hunt/Attacker-v0`` and ``mpc_hunt/Defenders-v0`` (``gymnasium.make``). Spaces, rewards
and the end of a hunt: :mod:`mpc_hunt.envs.observation`, :mod:`mpc_hunt.envs.episode`; docs/envs.md. The core
package never imports this one.
"""

try:
    import gymnasium  # noqa: F401
    import pettingzoo  # noqa: F401
except ImportError:
    from mpc_hunt.errors import MpcHuntError

    raise MpcHuntError('mpc_hunt.envs needs Gymnasium and PettingZoo: pip install "mpc-hunt[envs]"') from None

from mpc_hunt.envs.attacker_env import AttackerEnv
from mpc_hunt.envs.defender_env import DefenderEnv
from mpc_hunt.envs.parallel import HuntParallelEnv
from mpc_hunt.envs.policies import ControllerPolicy, PolicyAttacker
from mpc_hunt.envs.vector import AttackerHunts
from mpc_hunt.envs.view_hunts import AttackerViewHunts

gymnasium.register("mpc_hunt/Attacker-v0", entry_point="mpc_hunt.envs:AttackerEnv")
gymnasium.register("mpc_hunt/Defenders-v0", entry_point="mpc_hunt.envs:DefenderEnv")

__all__ = [
    "AttackerEnv",
    "AttackerHunts",
    "AttackerViewHunts",
    "ControllerPolicy",
    "DefenderEnv",
    "HuntParallelEnv",
    "PolicyAttacker",
]

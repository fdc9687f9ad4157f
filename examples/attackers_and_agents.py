"""Attackers the defenders do not know, beliefs wrong on purpose, and learned agents on both sides.

The world moves the attacker by a named behaviour (the scenario's ``attacker.behaviour``: ``apf``, the paper's,
``flee``, ``gap``, ``voronoi``, ``noisy``, ``learned``, ``minimax``, ``ppo``); a controller is built on the
defenders' belief about the attacker (``Belief``: the world's value over the believed one), never on the world.
This runs, on ``paper-open``:

1. the recommended controller (``trap``, which reads nothing of the attacker's law) against the ``gap``
   attacker; ``enclose``, which predicts the attacker with its model of the paper's attacker, against that
   attacker, once with the exact belief and once with one that underestimates its perception radius by 30 %;
2. the learned agents: the PPO attacker (``ppo``) against the recommended controller, and the PPO team
   (``ControllerSpec("ppo")``) against the paper's attacker; both are NumPy networks shipped with the package;
3. the same world as a Gymnasium environment (``pip install "mpc-hunt[envs]"``): the defending team against the
   ``gap`` attacker, a controller of the project as its policy, for a few steps.

    python examples/attackers_and_agents.py [--scenario paper-obstacles] [--steps 20]
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from mpc_hunt import Belief, ControllerSpec, builtin_scenario, simulate


def hunt(scenario, attacker: str, spec: ControllerSpec, belief: Belief = Belief()) -> None:
    world = dataclasses.replace(scenario, attacker=dataclasses.replace(scenario.attacker, behaviour=attacker))
    controller = spec.build(world, belief=belief, rng=np.random.default_rng(0))
    result = simulate(world, controller, rng=np.random.default_rng(0))  # rng: what the behaviour draws
    outcome = f"captured at {result.capture_time:.1f} s" if result.captured else f"not captured ({result.termination})"
    print(f"  {spec.label:20s} vs {attacker:4s}, belief {belief.label():22s}: {outcome}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="paper-open")
    parser.add_argument("--steps", type=int, default=10, help="environment steps")
    args = parser.parse_args()
    scenario = builtin_scenario(args.scenario)

    print(f"{scenario.name}:")
    recommended = ControllerSpec()
    hunt(scenario, "gap", recommended)
    hunt(scenario, "apf", ControllerSpec("enclose", horizon=5))
    wrong = Belief(perception_radius=1.3)  # the attacker perceives 30 % farther than the defenders believe
    hunt(scenario, "apf", ControllerSpec("enclose", horizon=5), wrong)
    hunt(scenario, "ppo", recommended)
    hunt(scenario, "apf", ControllerSpec("ppo"))

    try:
        from mpc_hunt.envs import ControllerPolicy, DefenderEnv
    except ImportError as exc:
        print(f'environments: skipped ({exc}; pip install "mpc-hunt[envs]")')
        return
    env = DefenderEnv(attacker="gap")
    policy = ControllerPolicy(env, "voronoi")
    observation, info = env.reset(seed=0)
    total = 0.0
    for _ in range(args.steps):
        observation, reward, terminated, truncated, info = env.step(policy(observation))
        total += reward
        if terminated or truncated:
            break
    print(
        f"DefenderEnv against gap, the voronoi controller as its policy: {args.steps} steps to t = "
        f"{info['time']:.1f} s, reward {total:.3f}"
    )


if __name__ == "__main__":
    main()

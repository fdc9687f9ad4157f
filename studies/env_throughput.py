"""Environment throughput: steps per second of the hunt environments, one and vectorised, beside the controller's share.

For each controller of ``CONTROLLERS`` (the Voronoi baseline and the recommended controller), ``AttackerEnv``
steps with a fixed action (the attacker heading east at full speed) on the random hunts of reset seeds
``SEED``, ``SEED + 1``, ... (a hunt that ends is followed by the next), ``STEPS`` steps a run, best of
``REPEATS`` runs: the time of a step, the time of the controller's ``command`` within it (timed by wrapping
it) and the rest, the environment's own work (the world's step, the capture test, the observation, the
action's check). Then the same steps vectorised with Gymnasium's vector API on 2 environments (``SyncVectorEnv``
in one process; ``AsyncVectorEnv`` in a process each, both cores), then ``BATCHED`` hunts in one call of the
batched engine's environment (:class:`mpc_hunt.envs.vector.AttackerHunts`, one process), and ``DefenderEnv``
against the paper's attacker for the environment alone. Writes ``studies/env_throughput/results.json`` and README.md, and the table
in docs/envs.md.

    python studies/env_throughput.py            # measure (a minute or two), write the results and the docs' table
    python studies/env_throughput.py --check    # the docs' table is the committed results'
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser, count
from mpc_hunt.bench.machine import describe_machine, machine_lines
from mpc_hunt.control.recommended import RECOMMENDED_CONTROLLER

from studies.docs_block import read_block, write_block
from studies.study_check import check_result, read_json_file, run_study

OUT = Path(__file__).resolve().parent / "env_throughput"
DOCS = Path(__file__).resolve().parents[1] / "docs" / "envs.md"
COMMAND = "python studies/env_throughput.py"
CONTROLLERS = ("voronoi", RECOMMENDED_CONTROLLER)
STEPS, REPEATS, SEED, VECTOR, BATCHED = 1500, 3, 3, 2, 256
ACTION = np.array([1.0, 0.0])      # the attacker heads east, capped at its v_a


class Timed:
    """A controller whose ``command`` adds its time to ``spent``."""

    def __init__(self, controller, spent: list):
        self.controller, self.spent = controller, spent

    def command(self, obs):
        start = time.perf_counter()
        out = self.controller.command(obs)
        self.spent[0] += time.perf_counter() - start
        return out


def one_env(controller: str, steps: int) -> dict:
    """``steps`` steps of one AttackerEnv against ``controller``: ms a step, ms of it in the controller."""
    from mpc_hunt.envs import AttackerEnv

    env = AttackerEnv(controller=controller)
    spent, seed = [0.0], SEED
    env.reset(seed=seed)
    env.controller = Timed(env.controller, spent)
    start = time.perf_counter()
    for _ in range(steps):
        _, _, terminated, truncated, _ = env.step(ACTION * env.action_space.high)
        if terminated or truncated:
            seed += 1
            env.reset(seed=seed)
            env.controller = Timed(env.controller, spent)
    total = time.perf_counter() - start
    return {"step_ms": 1e3 * total / steps, "controller_ms": 1e3 * spent[0] / steps}


def vector_env(controller: str | None, steps: int, asynchronous: bool) -> float:
    """Steps a second (of all environments together) of ``VECTOR`` environments: AttackerEnvs against
    ``controller``, or DefenderEnvs (None), the team standing still."""
    import gymnasium as gym

    from mpc_hunt.envs import AttackerEnv, DefenderEnv

    make = (lambda: AttackerEnv(controller=controller)) if controller is not None else (lambda: DefenderEnv())
    envs = (gym.vector.AsyncVectorEnv if asynchronous else gym.vector.SyncVectorEnv)([make] * VECTOR)
    try:
        envs.reset(seed=SEED)
        action = np.tile(ACTION * envs.single_action_space.high, (VECTOR, 1)) if controller is not None else \
            np.zeros((VECTOR, *envs.single_action_space.shape))
        start = time.perf_counter()
        for _ in range(steps // VECTOR):
            envs.step(action)
        return VECTOR * (steps // VECTOR) / (time.perf_counter() - start)
    finally:
        envs.close()


def batched_env(controller: str, steps: int) -> float:
    """Steps a second (of all hunts together) of ``BATCHED`` hunts in one AttackerHunts against ``controller``,
    at least ``steps`` steps and at least one call after a warm-up call."""
    from mpc_hunt.envs.vector import AttackerHunts

    hunts = AttackerHunts(BATCHED, controller=controller)
    hunts.reset(seed=SEED)
    action = np.tile(ACTION * hunts.single_action_space.high, (BATCHED, 1))
    hunts.step(action)
    calls = max(1, steps // BATCHED)
    start = time.perf_counter()
    for _ in range(calls):
        hunts.step(action)
    return BATCHED * calls / (time.perf_counter() - start)


def defender_env(steps: int) -> float:
    from mpc_hunt.envs import DefenderEnv

    env, seed = DefenderEnv(), SEED
    env.reset(seed=seed)
    action = np.zeros(env.action_space.shape)
    start = time.perf_counter()
    for _ in range(steps):
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            seed += 1
            env.reset(seed=seed)
    return steps / (time.perf_counter() - start)


def measure(steps: int, repeats: int) -> dict:
    rows = []
    for controller in CONTROLLERS:
        best = min((one_env(controller, steps) for _ in range(repeats)), key=lambda r: r["step_ms"])
        sync = max(vector_env(controller, steps, False) for _ in range(repeats))
        parallel = max(vector_env(controller, steps, True) for _ in range(repeats))
        batched = max(batched_env(controller, steps) for _ in range(repeats))
        rows.append({"controller": controller, **best, "steps_per_s": 1e3 / best["step_ms"],
                     "sync_steps_per_s": sync, "async_steps_per_s": parallel, "batched_steps_per_s": batched})
        print(f"{controller}: {1e3 / best['step_ms']:.0f} steps/s", file=sys.stderr, flush=True)
    team = max(defender_env(steps) for _ in range(repeats))
    team_async = max(vector_env(None, steps, True) for _ in range(repeats))
    return {"settings": {"steps": steps, "repeats": repeats, "seed": SEED, "vector": VECTOR, "batched": BATCHED,
                         "controllers": list(CONTROLLERS)},
            "attacker_env": rows, "defender_env": {"steps_per_s": team, "async_steps_per_s": team_async}}


def headline(results: dict) -> str:
    s, d = results["settings"], results["defender_env"]
    rows = [[f"`AttackerEnv`, defenders `{r['controller']}`", f"{r['steps_per_s']:.0f}",
             f"{r['controller_ms']:.3f} ({100 * r['controller_ms'] / r['step_ms']:.0f} %)",
             f"{r['step_ms'] - r['controller_ms']:.3f}", f"{r['sync_steps_per_s']:.0f}",
             f"{r['async_steps_per_s']:.0f}", f"{r['batched_steps_per_s']:.0f}"] for r in results["attacker_env"]]
    rows.append(["`DefenderEnv`, attacker `apf`", f"{d['steps_per_s']:.0f}", "–", f"{1e3 / d['steps_per_s']:.3f}", "–",
                 f"{d['async_steps_per_s']:.0f}", "–"])
    lines = [f"`{COMMAND}` ({s['steps']} steps a run, best of {s['repeats']}; {s['vector']} environments "
             "vectorised):", "",
             *markdown.table(["environment", "steps/s, one env", "controller's ms a step",
                              "environment's own ms a step",
                              f"steps/s, {s['vector']} envs in one process (`SyncVectorEnv`)",
                              f"steps/s, {s['vector']} processes (`AsyncVectorEnv`)",
                              f"steps/s, {s['batched']} hunts a call (`AttackerHunts`, one process)"], "lrrrrrr",
                             rows)]
    return "\n".join(lines) + "\n"


def write(results: dict, machine: dict) -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "results.json").write_text(json.dumps({"machine": machine, **results}, indent=1) + "\n", encoding="utf-8")
    (OUT / "README.md").write_text("\n".join(["# Environment throughput", "", headline(results),
                                              *machine_lines(machine), ""]), encoding="utf-8")
    write_block("env-throughput", headline(results), DOCS)


def check() -> list[str]:
    committed = read_json_file(OUT / "results.json", f"rerun {COMMAND}")
    errors = []
    if committed["settings"]["controllers"] != list(CONTROLLERS):
        errors.append(f"results.json: measured {committed['settings']['controllers']}, the study measures "
                      f"{list(CONTROLLERS)}")
    if read_block("env-throughput", DOCS) != headline(committed):
        errors.append("docs/envs.md: its throughput table is not the committed results'")
    return errors


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=count(100_000), default=STEPS, help="steps a run")
    parser.add_argument("--repeats", type=count(20), default=REPEATS, help="runs, the best kept")
    parser.add_argument("--check", action="store_true", help="check the docs' table against the committed results")
    args = parser.parse_args(argv)
    if args.check:
        return check_result(check(), "studies/env_throughput", COMMAND)
    write(measure(args.steps, args.repeats), describe_machine())
    print(f"wrote {OUT / 'README.md'} and the table of docs/envs.md")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

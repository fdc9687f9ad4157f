"""Train the PPO attacker and the PPO team with Stable-Baselines3, and ship their networks for NumPy.

Needs the optional extra ``pip install -e ".[learn]"`` (Stable-Baselines3 on torch's CPU build); nothing
else of the project imports either. Both sides are PPO with an MLP of two hidden layers of 64 ReLU
units (ReLU, not SB3's default tanh: the shipped network is evaluated in NumPy with the same bits on
every CPU, :mod:`mpc_hunt.world.mlp`), observations normalised by ``VecNormalize``, a decision every
``DECISION_STEPS`` steps of the world (0.5 s):

- ``attacker``: :class:`mpc_hunt.envs.learning.AttackerViewEnv`'s hunts against the recommended controller
  (``RECOMMENDED_CONTROLLER``), random hunts of the sweep's default ranges with 2 to 5 defenders, ``--hunts`` of
  them in one call of the batched engine (:class:`mpc_hunt.envs.view_hunts.AttackerViewHunts`, hunt k as the
  single environment reset from the seed + k plays it);
- ``team``: :class:`mpc_hunt.envs.learning.TeamHunts`, teams of 3 sharing one policy (one ``VecEnv``
  slot per defender), against the world's behaviours ``TEAM_ATTACKERS``, one drawn per hunt; the policy's
  action corrects the Voronoi baseline's velocity (residual policy learning, :mod:`mpc_hunt.control.ppo_team`),
  its first spread narrow (``LOG_STD_INIT``), so the team starts as the baseline and PPO improves on it.
  Tried first and given up: PPO from a random network (no capture in the 165 hunts of its first 7 minutes: a
  capture needs the ring closed and held for 2 s), and a network cloned from the baseline with three rounds
  of DAgger (116 000 views; it fitted the baseline's velocities to a mean squared
  error of 0.06 and captured none of 20 hunts in any round, the baseline 20 of 40).

Each side trains for ``--minutes`` of wall time (default 50), its progress on stderr each rollout.
Ctrl-C, or the end of the budget, writes a checkpoint (``studies/train_ppo/checkpoint/``, not
committed: torch's files); ``--resume`` continues from it with the minutes left. At the end the
network goes to the package (``mpc_hunt/world/behaviours/ppo_attacker.npz``,
``mpc_hunt/control/ppo_team.npz``) and the curve to ``studies/train_ppo/<side>.json`` and README.md.
Training hunts come from seeds of their own (``TRAIN_SEED``), never a sweep's or a study's.

    python studies/train_ppo.py                       # both sides, one after the other
    python studies/train_ppo.py --side attacker       # one side (run the two at once on two cores)
    python studies/train_ppo.py --side team --resume  # continue a stopped training
    python studies/train_ppo.py --check               # the shipped networks are the committed runs'
"""

from __future__ import annotations

import hashlib
import json
import sys
import time
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser, count, output_folder
from mpc_hunt.bench.machine import describe_machine, machine_lines
from mpc_hunt.control.ppo_team import RESIDUAL, TEAM_POLICY
from mpc_hunt.control.recommended import RECOMMENDED_CONTROLLER
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.world.behaviours.ppo import ATTACKER_POLICY

from studies.study_check import check_result, run_study

OUT = Path(__file__).resolve().parent / "train_ppo"
COMMAND = "python studies/train_ppo.py"
TRAIN_SEED = 31_337
DECISION_STEPS = 5
MINUTES = 50
TEAM = 3
TEAM_HUNTS = 4
MAX_ATTACKER_HUNTS = 4096    # the attacker's hunts side by side, at most
TEAM_ATTACKERS = ("apf", "flee", "gap", "voronoi", "noisy", "learned", "minimax")
HIDDEN = (64, 64)
BINS = 12                 # rows of a side's curve in the README
PPO_SETTINGS = {
    "attacker": {"n_steps": 512, "batch_size": 128, "n_epochs": 10, "gamma": 0.99, "gae_lambda": 0.95,
                 "learning_rate": 3e-4, "clip_range": 0.2, "ent_coef": 0.0},
    "team": {"n_steps": 128, "batch_size": 256, "n_epochs": 10, "gamma": 0.99, "gae_lambda": 0.95,
             "learning_rate": 3e-4, "clip_range": 0.2, "ent_coef": 0.0},
}
LOG_STD_INIT = {"attacker": 0.0, "team": -1.0}   # the Gaussian's first log σ: the team's corrections start small
SIDE_FILES = {"attacker": ATTACKER_POLICY.file, "team": TEAM_POLICY.file}
SIDE_NAMES = {"attacker": "attacker", "team": "defender"}


def learn_imports():
    """Stable-Baselines3 and torch, or a one-line error saying how to install them."""
    try:
        import stable_baselines3
        import torch
    except ImportError:
        raise MpcHuntError('training needs Stable-Baselines3 and torch: pip install -e ".[learn]"') from None
    return stable_baselines3, torch


def team_vec_env(hunts: int, seed: int):
    """:class:`TeamHunts` as Stable-Baselines3's ``VecEnv``: one slot per defender, the hunt's reward on each."""
    from gymnasium import spaces

    from mpc_hunt.control.ppo_team import TEAM_VIEW
    from mpc_hunt.envs.learning import BOUND, TeamHunts
    from mpc_hunt.envs.sb3 import plain_vec_env

    class TeamVecEnv(plain_vec_env()):
        def __init__(self):
            self.hunts = TeamHunts(hunts, TEAM_ATTACKERS, TEAM, DECISION_STEPS, seed)
            super().__init__(self.hunts.agents, spaces.Box(-BOUND, BOUND, (TEAM_VIEW,), np.float64),
                             spaces.Box(-1.0, 1.0, (2,), np.float64))
            self.actions = None

        def reset(self):
            return self.hunts.reset()

        def step_wait(self):
            views, rewards, dones, hunt_infos = self.hunts.step(self.actions)
            infos = []
            for k, info in enumerate(hunt_infos):
                for i in range(TEAM):
                    slot = dict(info) if i == 0 else {}
                    if dones[k * TEAM]:
                        slot["terminal_observation"] = self.hunts.terminal_views[k][i]
                    infos.append(slot)
            return views, rewards.astype(np.float32), dones, infos

    return TeamVecEnv()


def attacker_vec_env(hunts: int, seed: int):
    """:class:`AttackerViewHunts` (``hunts`` hunts of the view environment in one call of the batched engine) as
    Stable-Baselines3's ``VecEnv``, hunt k reset from ``seed + k``."""
    from mpc_hunt.envs.sb3 import as_vec_env
    from mpc_hunt.envs.view_hunts import AttackerViewHunts

    venv = as_vec_env(AttackerViewHunts(hunts, controller=RECOMMENDED_CONTROLLER, decision_steps=DECISION_STEPS))
    venv.seed(seed)
    return venv


def export(policy, obs_rms, clip: float, epsilon: float, side: str, path: Path) -> None:
    """The policy's network (its ``mlp_extractor.policy_net`` and ``action_net``) and the observation's running
    statistics as a policy file :func:`mpc_hunt.world.mlp.load_mlp` reads."""
    import torch

    linear = [m for m in policy.mlp_extractor.policy_net if isinstance(m, torch.nn.Linear)] + [policy.action_net]
    arrays = {"side": np.array(SIDE_NAMES[side]), "decision_steps": np.array(DECISION_STEPS),
              "clip": np.array(float(clip)), "epsilon": np.array(float(epsilon)),
              "obs_mean": np.asarray(obs_rms.mean, dtype=float), "obs_var": np.asarray(obs_rms.var, dtype=float)}
    for k, layer in enumerate(linear):
        arrays[f"w{k}"] = layer.weight.detach().cpu().numpy().astype(float)
        arrays[f"b{k}"] = layer.bias.detach().cpu().numpy().astype(float)
    with open(path, "wb") as f:
        np.savez(f, **arrays)


def read_checkpoint(path: Path) -> dict:
    """A checkpoint's progress (its elapsed seconds and curve), or a one-line MpcHuntError naming the file."""
    try:
        progress = json.loads(path.read_text(encoding="utf-8"))
    except (ValueError, UnicodeDecodeError):
        progress = None
    if not (isinstance(progress, dict) and isinstance(progress.get("elapsed_s"), (int, float))
            and isinstance(progress.get("curve"), list)):
        raise MpcHuntError(f"{path}: not a training's progress; delete {path.parent} to train from the start")
    return progress


def digest(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def train_side(side: str, minutes: float, hunts: int, out: Path, resume: bool) -> dict:
    """Train ``side`` for ``minutes`` of wall time (the module's docstring); its curve and settings."""
    sb3, torch = learn_imports()
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecNormalize

    torch.set_num_threads(1)
    folder = out / "checkpoint" / side
    progress_path = folder / "progress.json"
    if resume and not progress_path.exists():
        raise MpcHuntError(f"{folder}: no checkpoint of the {side} to resume; train without --resume")
    progress = read_checkpoint(progress_path) if resume else {"elapsed_s": 0.0, "curve": []}
    seed = TRAIN_SEED + (0 if side == "attacker" else 1) + 1000 * len(progress["curve"])
    venv = attacker_vec_env(hunts, seed) if side == "attacker" else team_vec_env(TEAM_HUNTS, seed)
    if resume:
        try:
            venv = VecNormalize.load(str(folder / "vecnormalize.pkl"), venv)
            model = PPO.load(str(folder / "model.zip"), env=venv, device="cpu")
        except Exception as exc:        # a damaged file: pickle, zip and torch each raise their own
            venv.close()
            raise MpcHuntError(f"{folder}: a damaged checkpoint ({type(exc).__name__}); delete it to train from the "
                               "start") from None
    else:
        venv = VecNormalize(venv, norm_obs=True, norm_reward=True, clip_obs=10.0, gamma=PPO_SETTINGS[side]["gamma"])
        model = PPO("MlpPolicy", venv, seed=TRAIN_SEED, device="cpu", verbose=0,
                    policy_kwargs={"activation_fn": torch.nn.ReLU, "log_std_init": LOG_STD_INIT[side],
                                   "net_arch": {"pi": list(HIDDEN), "vf": list(HIDDEN)}},
                    **PPO_SETTINGS[side])
    budget = minutes * 60.0
    start = time.perf_counter() - progress["elapsed_s"]

    class Budget(BaseCallback):
        """Counts the hunts each rollout ends, writes the curve's row, stops at the budget."""

        def _on_rollout_start(self) -> None:
            self.ended = {"captured": 0, "attacker_escaped": 0, "time_limit": 0, "non_finite_state": 0}

        def _on_step(self) -> bool:
            for info in self.locals["infos"]:
                if info.get("termination") in self.ended:
                    self.ended[info["termination"]] += 1
            return time.perf_counter() - start < budget

        def _on_rollout_end(self) -> None:
            hunts = sum(self.ended.values())
            row = {"wall_time_s": round(time.perf_counter() - start, 1), "timesteps": int(self.num_timesteps),
                   "hunts": hunts, **self.ended}
            progress["curve"].append(row)
            won = self.ended["captured"] if side == "team" else hunts - self.ended["captured"]
            print(f"{side}: {row['wall_time_s']:.0f} s, {row['timesteps']} steps, {hunts} hunts ended, "
                  f"{won} won by the learner", file=sys.stderr, flush=True)

    def checkpoint() -> None:
        folder.mkdir(parents=True, exist_ok=True)
        model.save(str(folder / "model.zip"))
        venv.save(str(folder / "vecnormalize.pkl"))
        progress["elapsed_s"] = time.perf_counter() - start
        progress_path.write_text(json.dumps(progress), encoding="utf-8")

    try:
        if time.perf_counter() - start < budget:
            model.learn(total_timesteps=10**9, callback=Budget(), reset_num_timesteps=not resume)
    except KeyboardInterrupt:
        checkpoint()
        try:
            venv.close()
        except (EOFError, OSError):         # the environments' processes took the Ctrl-C too
            pass
        raise
    checkpoint()
    venv.close()
    path = Path(str(SIDE_FILES[side]()))
    export(model.policy, venv.obs_rms, venv.clip_obs, venv.epsilon, side, path)
    settings = {"minutes": minutes, "decision_steps": DECISION_STEPS, "hidden": list(HIDDEN), "activation": "relu",
                "log_std_init": LOG_STD_INIT[side],
                "train_seed": TRAIN_SEED, **PPO_SETTINGS[side],
                **({"against": RECOMMENDED_CONTROLLER, "teams": [2, 3, 4, 5], "hunts": hunts}
                   if side == "attacker" else {"team": TEAM, "hunts": TEAM_HUNTS, "attackers": list(TEAM_ATTACKERS),
                                               "residual": RESIDUAL})}
    return {"side": side, "settings": settings, "curve": progress["curve"], "policy": path.name,
            "sha256": digest(path), "versions": {"stable_baselines3": sb3.__version__, "torch": torch.__version__}}


def write(result: dict, machine: dict, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{result['side']}.json").write_text(json.dumps({"machine": machine, **result}, indent=1) + "\n",
                                                 encoding="utf-8")
    write_readme(out)


def write_readme(out: Path) -> None:
    lines = ["# The PPO attacker and the PPO team", "",
             f"`{COMMAND}` (Stable-Baselines3 PPO; the settings in each side's JSON). Each row is the hunts that "
             f"ended over a {BINS}th of the training's rollouts: the learner's share won (the attacker: escaped or "
             "outlasted the time limit; the "
             "team: captured). Each rollout's hunts are new draws, so the curve is noisy: its trend is the result. "
             "How the trained agents fare on hunts they never saw: studies/attackers/README.md."]
    for side in ("attacker", "team"):
        path = out / f"{side}.json"
        if not path.exists():
            continue
        r = json.loads(path.read_text(encoding="utf-8"))
        s = r["settings"]
        what = (f"against `{s['against']}`, teams of {s['teams'][0]} to {s['teams'][-1]}" if side == "attacker"
                else f"a team of {s['team']} against {', '.join(s['attackers'])}")
        body = []
        for chunk in np.array_split(np.arange(len(r["curve"])), min(BINS, len(r["curve"]))) if r["curve"] else []:
            rows = [r["curve"][i] for i in chunk]
            hunts = sum(c["hunts"] for c in rows)
            won = sum(c["captured"] if side == "team" else c["hunts"] - c["captured"] for c in rows)
            share = f"{won} / {hunts} ({100 * won / hunts:.0f} %)" if hunts else "–"
            body.append([f"{rows[-1]['wall_time_s'] / 60:.1f}", rows[-1]["timesteps"], hunts, share])
        lines += ["", f"## {side} ({what}; {s['minutes']:g} min; shipped as `{r['policy']}`)", "",
                  *markdown.table(["wall time (min)", "steps", "hunts ended", "won by the learner"], "rrrr", body),
                  "", *machine_lines(r["machine"])]
    (out / "README.md").write_text("\n".join(lines) + "\n", encoding="utf-8")


def check(out: Path) -> list[str]:
    """Each shipped network is the one its committed run wrote (its digest)."""
    errors = []
    for side, where in SIDE_FILES.items():
        path = out / f"{side}.json"
        if not path.exists():
            errors.append(f"{path}: missing")
            continue
        committed = json.loads(path.read_text(encoding="utf-8"))
        if digest(where()) != committed["sha256"]:
            errors.append(f"{where().name}: not the network of {path.name}")
        if not committed["curve"]:
            errors.append(f"{path.name}: no curve")
    return errors


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--side", choices=("attacker", "team", "both"), default="both")
    parser.add_argument("--minutes", type=count(600), default=MINUTES, help="wall time per side, 1 to 600")
    parser.add_argument("--hunts", type=count(MAX_ATTACKER_HUNTS), default=2,
                        help="the attacker's hunts stepped at once (one process, the batched engine)")
    parser.add_argument("--output", type=output_folder, default=OUT, help="the study's folder")
    parser.add_argument("--resume", action="store_true", help="continue from the checkpoint in --output")
    parser.add_argument("--check", action="store_true", help="check the committed results against the package")
    args = parser.parse_args(argv)
    if args.check:
        return check_result(check(args.output), "studies/train_ppo", COMMAND)
    learn_imports()
    for side in ("attacker", "team") if args.side == "both" else (args.side,):
        try:
            result = train_side(side, args.minutes, args.hunts, args.output, args.resume)
        except KeyboardInterrupt:
            print(f"interrupted: the {side}'s checkpoint is in {args.output / 'checkpoint' / side}; continue with "
                  f"--side {side} --resume", file=sys.stderr)
            return 130
        write(result, describe_machine(), args.output)
        print(f"wrote {result['policy']} and {args.output / (side + '.json')}")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

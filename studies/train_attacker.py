"""Train the ``learned`` attacker: the cross-entropy method on its linear policy, against the enclose controller.

The policy is :mod:`mpc_hunt.world.behaviours.learned`'s W (2 × 10 numbers). Each generation draws
``--population`` candidates W ~ N(μ, σ²) (the first is μ itself), plays each against ``AGAINST`` (the enclose
controller on rti/HPIPM, N = 10, the paper's objective with its model of the attacker, built on the defenders'
default belief: the recommended controller when the shipped weights were trained) on the same ``--episodes`` random hunts (common random numbers), and moves μ and σ to the mean and
spread of the best quarter. A hunt scores t_capture / time limit when the attacker is captured (surviving
longer is better), 1 when the time limit comes, and 1 + ½ (1 − t_escape / time limit) when it leaves the arena
(escaping, and sooner, is better still: without this the many candidates that merely survive would tie, and
the best quarter would be drawn at random among them). Training hunts are the sweep's random scenarios (its default ranges, the ones
the attackers study plays on: a smaller arena or a shorter limit were tried and let an attacker that stands
still win by the time limit or the arena's edge, which teaches nothing), each reachable by the defenders
(:func:`mpc_hunt.sweep.reachability.reachable`), drawn from seeds of their own
(``SeedSequence([TRAIN_SEED, generation, episode])``), never the sweeps' or the attackers study's. The final μ
is written as the shipped weights; the attackers study (``python studies/attackers.py``) plays every
strategy against it on hunts it never trained on.

    python studies/train_attacker.py             # train (27 minutes on 2 cores here), write the weights and the
                                                 # curve (studies/train_attacker/, mpc_hunt/world/behaviours/)
    python studies/train_attacker.py --resume    # continue a training stopped by Ctrl-C (its finished
                                                 # generations are kept in studies/train_attacker/generations.jsonl)
    python studies/train_attacker.py --check     # the shipped weights are the committed run's final mean
"""

from __future__ import annotations

import json
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser, count, output_file, output_folder
from mpc_hunt.bench.machine import describe_machine, machine_lines
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.sweep.random_scenario import ScenarioRanges, random_scenario
from mpc_hunt.sweep.reachability import reachable
from mpc_hunt.workers import run_local
from mpc_hunt.world.behaviours.learned import FEATURES, PARAMETERS, LearnedAttacker, shipped_weights
from mpc_hunt.world.scenario import Scenario

from studies.study_check import check_result, read_json_file, run_study

OUT = Path(__file__).resolve().parent / "train_attacker"
PROGRESS = "generations.jsonl"  # in --output while training runs: the settings, then a line per finished generation
WEIGHTS = Path(__file__).resolve().parents[1] / "mpc_hunt" / "world" / "behaviours" / PARAMETERS
COMMAND = "python studies/train_attacker.py"
AGAINST = "enclose:rti:hpipm:10"  # the controller the attacker is trained against
TRAIN_SEED = 24_601          # the training hunts' own seed: no sweep or study draws from it
RANGES = ScenarioRanges()
GENERATIONS, POPULATION, EPISODES = 10, 10, 3
ELITE = 0.25                 # the fraction of the population μ and σ are refitted to
SIGMA_FLOOR = 0.05           # σ never collapses below this (exploration while the fitness is noisy)
MAX_DRAWS = 100              # scenarios drawn per episode before giving up on a reachable one


@dataclass(frozen=True)
class Trial:
    """One hunt of one candidate: its weights and the scenario."""

    candidate: int
    index: int
    weights: tuple[tuple[float, ...], ...]
    scenario: Scenario


def episode(task: Trial) -> dict:
    """The candidate's attacker against ``AGAINST`` on the task's hunt; its fitness."""
    scenario = task.scenario
    controller = ControllerSpec.parse(AGAINST).build(scenario)
    attacker = LearnedAttacker(scenario, np.random.default_rng(0), np.array(task.weights))
    result = simulate(scenario, controller, behaviour=attacker)
    limit = scenario.hunt.time_limit
    if result.captured:
        fitness = result.capture_time / limit
    elif result.termination == "attacker_escaped":
        fitness = 1.0 + 0.5 * (1.0 - result.times[-1] / limit)
    else:
        fitness = 1.0
    return {"candidate": task.candidate, "episode": task.index, "fitness": fitness,
            "termination": result.termination}


def training_hunt(generation: int, index: int) -> Scenario:
    """Hunt ``index`` of ``generation``: the first reachable draw of its own seed."""
    rng = np.random.default_rng(np.random.SeedSequence([TRAIN_SEED, generation, index]))
    for _ in range(MAX_DRAWS):
        scenario = random_scenario(rng, RANGES, name=f"train-{generation}-{index}")
        if reachable(scenario):
            return scenario
    raise MpcHuntError(f"no reachable training hunt in {MAX_DRAWS} draws (generation {generation}, episode {index})")


def generation_tasks(generation: int, mean: np.ndarray, spread: np.ndarray, population: int,
                     episodes: int) -> tuple[np.ndarray, list[Trial]]:
    """The candidates of ``generation`` (the first is μ) and their episodes, every candidate on the same hunts."""
    rng = np.random.default_rng(np.random.SeedSequence([TRAIN_SEED, generation]))
    candidates = mean + spread * rng.standard_normal((population, *mean.shape))
    candidates[0] = mean
    hunts = [training_hunt(generation, e) for e in range(episodes)]
    tasks = [Trial(k, e, tuple(map(tuple, candidates[k].tolist())), hunts[e])
             for k in range(population) for e in range(episodes)]
    return candidates, tasks


def train(generations: int, population: int, episodes: int, workers: int, progress: Path | None = None,
          settings: dict | None = None, resume: bool = False) -> dict:
    """The cross-entropy method of the module's docstring; progress on stderr, the curve returned. Each finished
    generation is appended to ``progress`` (:data:`PROGRESS`) as it ends, so Ctrl-C loses only the generation
    running; ``resume`` continues from the generations there (the same numbers as a run never stopped: each
    generation draws from its own seeds)."""
    finished = read_progress(progress, settings) if resume and progress is not None else []
    if progress is not None and not finished:
        start_progress(progress, settings)
    mean, spread = np.zeros((2, FEATURES)), np.ones((2, FEATURES))
    if finished:
        mean, spread = np.array(finished[-1]["mean"]), np.array(finished[-1]["spread"])
        print(f"resuming after generation {len(finished)} of {generations}", file=sys.stderr, flush=True)
    elite = max(2, int(round(ELITE * population)))
    curve = [f["curve"] for f in finished]
    start = time.perf_counter() - (curve[-1]["wall_time_s"] if curve else 0.0)
    for g in range(len(finished), generations):
        candidates, tasks = generation_tasks(g, mean, spread, population, episodes)
        fitness = np.zeros((population, episodes))
        for row in run_local(tasks, episode, workers):
            fitness[row["candidate"], row["episode"]] = row["fitness"]
        score = fitness.mean(axis=1)
        best = np.argsort(-score)[:elite]
        curve.append({"generation": g, "mean_candidate": float(score[0]), "elite": float(score[best].mean()),
                      "best": float(score[best[0]]), "population": float(score.mean()),
                      "spread": float(spread.mean()), "wall_time_s": time.perf_counter() - start})
        mean = candidates[best].mean(axis=0)
        spread = np.maximum(candidates[best].std(axis=0), SIGMA_FLOOR)
        if progress is not None:
            append_progress(progress, {"curve": curve[-1], "mean": mean.tolist(), "spread": spread.tolist()})
        print(f"generation {g + 1}/{generations}: μ's fitness {score[0]:.3f}, elite {score[best].mean():.3f}, "
              f"σ {spread.mean():.3f} ({time.perf_counter() - start:.0f} s)", file=sys.stderr, flush=True)
    return {"curve": curve, "weights": mean.tolist()}


def _resumable(settings: dict) -> dict:
    """The settings a resumed training must share with the stopped one (all but the number of generations)."""
    return {k: v for k, v in settings.items() if k != "generations"}


def start_progress(path: Path, settings: dict | None) -> None:
    """A new progress file: its first line the training's settings."""
    path.write_text(json.dumps({"settings": settings}) + "\n", encoding="utf-8")


def append_progress(path: Path, generation: dict) -> None:
    """One finished generation (its curve row, the μ and σ it ends with) on its own line, on disk at once."""
    with path.open("a", encoding="utf-8") as f:
        f.write(json.dumps(generation) + "\n")
        f.flush()
        os.fsync(f.fileno())


def read_progress(path: Path, settings: dict | None) -> list[dict]:
    """The finished generations in a progress file (none if there is no file), each checked; a last line cut
    short (the process killed while writing it) is dropped. An MpcHuntError if the file is damaged or, given
    ``settings``, its training had others."""
    if not path.exists():
        return []
    lines = path.read_text(encoding="utf-8").splitlines()
    entries = []
    for number, line in enumerate(lines, 1):
        try:
            entries.append(json.loads(line))
        except json.JSONDecodeError:
            if number == len(lines) and number > 1:
                break
            raise MpcHuntError(f"{path}: line {number} is not JSON; delete the file to train from the start") \
                from None
    if not entries or not isinstance(entries[0], dict) or "settings" not in entries[0]:
        raise MpcHuntError(f"{path}: not a training's progress file; delete it to train from the start")
    if settings is not None and _resumable(entries[0]["settings"] or {}) != _resumable(settings):
        raise MpcHuntError(f"{path}: a training with other settings; give the same --population and --episodes, "
                           "or delete the file to train from the start")
    finished = entries[1:]
    for i, f in enumerate(finished):
        if not (isinstance(f, dict) and isinstance(f.get("curve"), dict) and f["curve"].get("generation") == i
                and np.shape(f.get("mean")) == (2, FEATURES) and np.shape(f.get("spread")) == (2, FEATURES)):
            raise MpcHuntError(f"{path}: generation {i + 1} is malformed; delete the file to train from the start")
    return finished


def write(result: dict, settings: dict, machine: dict, out: Path, weights: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    (out / "results.json").write_text(json.dumps({"machine": machine, "settings": settings, **result}, indent=1)
                                      + "\n", encoding="utf-8")
    weights.write_text(json.dumps({"weights": result["weights"], "trained_by": COMMAND, "settings": settings},
                                  indent=1) + "\n", encoding="utf-8")
    lines = ["# The `learned` attacker's training", "",
             f"`{COMMAND}` ({settings['generations']} generations of {settings['population']} candidates, "
             f"{settings['episodes']} hunts each against `{settings['against']}`; "
             f"{result['curve'][-1]['wall_time_s'] / 60:.0f} min). Fitness of a hunt: t_capture / time limit when the "
             "attacker is captured, 1 at the time limit, 1 + ½ (1 − t_escape / time limit) when it escapes; a "
             "candidate's is its mean over the generation's hunts. "
             "Each generation's hunts are new draws, so the curve is noisy: its trend, not a value, is the result. "
             "How the trained attacker fares on hunts it never saw: studies/attackers/README.md.", "",
             *markdown.table(["generation", "μ", "elite mean", "best", "population mean", "mean σ"], "rrrrrr",
                             ([c["generation"] + 1, *(f"{c[k]:.3f}" for k in ("mean_candidate", "elite", "best",
                                                                               "population", "spread"))]
                              for c in result["curve"])),
             "", *machine_lines(machine)]
    (out / "README.md").write_text("\n".join(lines) + "\n", encoding="utf-8")


def check(out: Path) -> list[str]:
    """The shipped weights are the committed run's final μ; the committed curve has one row per generation."""
    committed = read_json_file(out / "results.json", f"rerun {COMMAND}")
    errors = []
    if not np.array_equal(np.array(committed["weights"]), shipped_weights()):
        errors.append(f"mpc_hunt/world/behaviours/{PARAMETERS}: not the final weights of results.json")
    if len(committed["curve"]) != committed["settings"]["generations"]:
        errors.append("results.json: the curve does not have one row per generation")
    return errors


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--generations", type=count(100), default=GENERATIONS, help="1 to 100")
    parser.add_argument("--population", type=count(64), default=POPULATION, help="candidates a generation, 4 to 64")
    parser.add_argument("--episodes", type=count(20), default=EPISODES, help="hunts per candidate, 1 to 20")
    parser.add_argument("--workers", type=count(64), default=2, help="local worker processes")
    parser.add_argument("--output", type=output_folder, default=OUT, help="the study's folder (default studies/train_attacker)")
    parser.add_argument("--weights", type=output_file, default=WEIGHTS, help="where to write the trained weights")
    parser.add_argument("--check", action="store_true", help="check the committed results against the code")
    parser.add_argument("--resume", action="store_true",
                        help=f"continue the training stopped in --output (its finished generations, {PROGRESS})")
    args = parser.parse_args(argv)
    if args.check:
        return check_result(check(args.output), "studies/train_attacker", COMMAND)
    if args.population < 4:
        parser.error(f"--population: at least 4, got {args.population}")
    settings = {"generations": args.generations, "population": args.population, "episodes": args.episodes,
                "elite": ELITE, "sigma_floor": SIGMA_FLOOR, "train_seed": TRAIN_SEED,
                "against": ControllerSpec.parse(AGAINST).label,
                "ranges": "the sweep's defaults"}
    progress = args.output / PROGRESS
    try:
        finished = read_progress(progress, settings if args.resume else None)
    except MpcHuntError as exc:
        parser.error(str(exc))
    if finished and not args.resume:
        parser.error(f"--output {args.output}: holds {len(finished)} finished generations of a stopped training; "
                     f"continue it with --resume, or delete {progress} to start again")
    args.output.mkdir(parents=True, exist_ok=True)
    try:
        result = train(args.generations, args.population, args.episodes, args.workers, progress, settings,
                       resume=args.resume)
    except KeyboardInterrupt:
        kept = len(read_progress(progress, None)) if progress.exists() else 0
        print(f"interrupted: {kept} finished generations kept in {progress}; continue with --resume "
              "(the weights and the curve are written when training ends)", file=sys.stderr)
        return 130
    except MpcHuntError as exc:
        print(f"train_attacker.py: error: {exc}", file=sys.stderr)
        return 2
    write(result, settings, describe_machine(), args.output, args.weights)
    progress.unlink()
    print(f"wrote {args.weights} and {args.output / 'README.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

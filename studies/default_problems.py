"""Build the problem set shipped with the package (``mpc_hunt/problems/default.json``).

It holds, for each built-in scenario, tagged ``default``, the state
``mpc-hunt solve`` starts from: the first state of the scenario's closed-loop
run (the paper's strategy, prediction on) at which the hunting circle has
formed (:func:`mpc_hunt.capture_state.first_formed_circle`); then, for the
paper's two scenarios, runs of 4 consecutive capture-stage states starting
every 560th capture-stage state of that run (two runs per scenario, for
warm-started solving); then two random
states per constraint family, drawn with seed 0 around paper-obstacles'
robots, each making its family active (:mod:`mpc_hunt.random_states`). It is
small enough for ``studies/compare.py`` (every pair, N = 1, 5, 10, both modes)
to run in about ten minutes on two cores.

    python studies/default_problems.py            # rewrite the shipped file
    python studies/default_problems.py --check    # fail if the code no longer gives the shipped file
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from mpc_hunt import builtin_names, builtin_scenario
from mpc_hunt.build_problems import build_problem_set
from mpc_hunt.problem_set import ProblemSet, dumps_problem_set

TARGET = Path(__file__).resolve().parents[1] / "mpc_hunt" / "problems" / "default.json"
EVERY, RUN_LENGTH, RANDOM_PER_CASE, SEED = 560, 4, 2, 0
SAMPLED = ("paper-open", "paper-obstacles")     # whose closed-loop runs are sampled


def build() -> ProblemSet:
    names = sorted(builtin_names(), key=lambda n: n != "paper-obstacles")   # the random states' template first
    return build_problem_set(
        [builtin_scenario(n) for n in names], np.random.default_rng(SEED), every=EVERY, run_length=RUN_LENGTH,
        random_per_case=RANDOM_PER_CASE, sampled=set(SAMPLED),
        description="States shipped with mpc-hunt: 'default' tags the state `mpc-hunt solve` starts from for each "
                    f"built-in scenario; 'closed-loop' runs of {RUN_LENGTH} consecutive capture-stage states every "
                    f"{EVERY}th of the hunts of {' and '.join(SAMPLED)}; 'random' states, {RANDOM_PER_CASE} per constraint family "
                    f"(seed {SEED}). Rebuild with `python studies/default_problems.py`.")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare with the shipped file instead of writing it")
    args = parser.parse_args(argv)
    text = dumps_problem_set(build())
    if args.check:
        if TARGET.read_text(encoding="utf-8") != text:
            print(f"{TARGET} differs from what the code builds: run python studies/default_problems.py",
                  file=sys.stderr)
            return 1
        print(f"{TARGET.name}: up to date")
        return 0
    TARGET.write_text(text, encoding="utf-8")
    print(f"wrote {TARGET}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

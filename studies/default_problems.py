"""Build the problem set shipped with the package (``mpc_hunt/bench/problems/default.json``).

It holds, for each built-in scenario, tagged ``default``, the state
``mpc-hunt solve`` starts from: the first state of the scenario's closed-loop
run (the paper's strategy, prediction on) at which the hunting circle has
formed (:func:`mpc_hunt.bench.capture_state.first_formed_circle`); then, for the
paper's two scenarios, runs of 4 consecutive capture-stage states starting
every 560th capture-stage state of that run (two runs per scenario, for
warm-started solving); then two random
states per constraint family, drawn with seed 0 around paper-obstacles'
robots, each making its family active (:mod:`mpc_hunt.bench.random_states`). It is
small enough for ``studies/compare.py`` (every pair, N = 1, 5, 10, both modes)
to run in about ten minutes on two cores.

The file is an artifact, not a figure: the closed-loop states are where one
run happened to be, and another machine's last bits, or a nanometre, move them
(studies/reproduction/). So ``--check`` verifies what matters about it: every
state poses a valid capture problem, the tags and runs are what the recipe
makes, the scenarios are the code's, the random states are the recipe's (they
come from the generator alone), and each default state is reproduced within
``DEFAULT_TOLERANCE`` by the closed loop that finds it.

    python studies/default_problems.py            # rewrite the shipped file
    python studies/default_problems.py --check    # fail if the shipped file is not what the recipe makes
"""

from __future__ import annotations

import sys
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt.arguments import CommandParser
from mpc_hunt import builtin_names, builtin_scenario
from mpc_hunt.bench.activity import ActivityProbe
from mpc_hunt.world.attacker import perceives
from mpc_hunt.bench.build_problems import build_problem_set
from mpc_hunt.bench.capture_state import first_formed_circle
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.world.ensemble import perturbed
from mpc_hunt.capture.evaluator import VIOLATION_NAMES
from mpc_hunt.bench.problem_set import ProblemSet, dumps_problem_set, load_problem_set
from mpc_hunt.bench.random_states import random_entries
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.world.scenario_io import scenario_to_dict

from studies.study_check import check_result, run_study

TARGET = Path(__file__).resolve().parents[1] / "mpc_hunt" / "bench" / "problems" / "default.json"
EVERY, RUN_LENGTH, RANDOM_PER_CASE, SEED = 560, 4, 2, 0
SAMPLED = ("paper-open", "paper-obstacles")     # whose closed-loop runs are sampled
# A default state, rebuilt, within this of the shipped one: (time in s, every position in m). Set from what a
# nanometre does (`python studies/default_problems.py --spread`, 3 members): paper-obstacles' closed loop is
# chaotic before its circle forms (up to 0.5 s and 1.2 cm apart), the others keep their state to 2e-8 m.
SPREAD_MEMBERS = 3
DEFAULT_TOLERANCE = {"paper-obstacles": (1.0, 0.05)}
TIGHT_TOLERANCE = (1e-6, 1e-6)


def build() -> ProblemSet:
    names = sorted(builtin_names(), key=lambda n: n != "paper-obstacles")   # the random states' template first
    return build_problem_set(
        [builtin_scenario(n) for n in names], np.random.default_rng(SEED), every=EVERY, run_length=RUN_LENGTH,
        random_per_case=RANDOM_PER_CASE, sampled=set(SAMPLED),
        description="States shipped with mpc-hunt: 'default' tags the state `mpc-hunt solve` starts from for each "
                    f"built-in scenario; 'closed-loop' runs of {RUN_LENGTH} consecutive capture-stage states every "
                    f"{EVERY}th of the hunts of {' and '.join(SAMPLED)}; 'random' states, {RANDOM_PER_CASE} per constraint family "
                    f"(seed {SEED}). Rebuild with `python studies/default_problems.py`.")


def _valid(shipped: ProblemSet) -> list[str]:
    """Every state poses a capture problem; the scenarios are the code's built-in ones."""
    errors = []
    for entry in shipped.problems:
        try:
            shipped.problem(entry)
        except MpcHuntError as exc:
            errors.append(f"{entry.id}: not a valid capture-stage state ({exc})")
    errors += [f"scenario {name}: not the built-in scenario as the code declares it" for name in builtin_names()
               if scenario_to_dict(shipped.scenarios[name]) != scenario_to_dict(builtin_scenario(name))]
    return errors


def _tags(shipped: ProblemSet) -> list[str]:
    """One default state per built-in scenario; closed-loop runs of RUN_LENGTH capture-stage states one step apart,
    of the sampled scenarios only; RANDOM_PER_CASE random states per constraint family, that family active."""
    errors = [f"{name}: {len(found)} states tagged default, not 1" for name in builtin_names()
              if len(found := [e for e in shipped.tagged("default") if e.scenario == name]) != 1]
    runs = shipped.sequences()
    for name in SAMPLED:
        if not [s for s in runs if s.startswith(f"{name}/")]:
            errors.append(f"{name}: no closed-loop run")
    for sequence, entries in runs.items():
        scenario = shipped.scenarios[entries[0].scenario]
        steps = [round(e.state.time / scenario.hunt.time_step) for e in entries]
        if entries[0].scenario not in SAMPLED or len(entries) != RUN_LENGTH or \
                steps != list(range(steps[0], steps[0] + RUN_LENGTH)):
            errors.append(f"{sequence}: not a run of {RUN_LENGTH} consecutive states of a sampled scenario")
        errors += [f"{e.id}: tagged {e.tags}, not a closed-loop capture-stage state" for e in entries
                   if "closed-loop" not in e.tags
                   or not perceives(scenario, e.state.attacker, e.state.defenders).any()]
    for family in VIOLATION_NAMES:
        cases = [e for e in shipped.tagged("random") if f"case:{family}" in e.tags]
        if len(cases) != RANDOM_PER_CASE or any(f"active:{family}" not in e.tags for e in cases):
            errors.append(f"random states of case {family}: {len(cases)}, not {RANDOM_PER_CASE} with it active")
    return errors


def _rebuilt(shipped: ProblemSet) -> list[str]:
    """The random states are the recipe's to the last bit (the generator alone draws them); each default state
    is where the closed loop first forms the circle, within DEFAULT_TOLERANCE."""
    errors = []
    _, entries = random_entries(builtin_scenario("paper-obstacles"), RANDOM_PER_CASE, np.random.default_rng(SEED),
                                ActivityProbe())
    ours = {e.id: e for e in shipped.tagged("random")}
    for new in entries:
        old = ours.get(new.id)
        if old is None or old.tags != new.tags or not (np.array_equal(old.state.attacker, new.state.attacker)
                                                        and np.array_equal(old.state.defenders, new.state.defenders)):
            errors.append(f"{new.id}: not the state the recipe draws (seed {SEED})")
    for name in builtin_names():
        old = next(e.state for e in shipped.tagged("default") if e.scenario == name)
        new = first_formed_circle(builtin_scenario(name))
        moved = _moved(old, new)
        time_tolerance, position_tolerance = DEFAULT_TOLERANCE.get(name, TIGHT_TOLERANCE)
        if abs(new.time - old.time) > time_tolerance or moved > position_tolerance:
            errors.append(f"{name}/default: the closed loop now forms the circle at {new.time:.1f} s, robots up to "
                          f"{moved:.2e} m from the shipped state (at {old.time:.1f} s)")
    return errors


def _moved(a, b) -> float:
    """The largest coordinate difference between two states' robots."""
    return float(max(np.max(np.abs(a.attacker - b.attacker)), np.max(np.abs(a.defenders - b.defenders))))


def spread() -> list[str]:
    """Per built-in scenario: how far a nanometre moves its default state (the tolerances above come from this)."""
    lines = []
    for name in builtin_names():
        nominal = first_formed_circle(builtin_scenario(name))
        states = [first_formed_circle(perturbed(builtin_scenario(name), np.random.default_rng(m)))
                  for m in range(1, SPREAD_MEMBERS + 1)]
        lines.append(f"{name}: time up to {max(abs(s.time - nominal.time) for s in states):.2f} s apart, "
                     f"robots up to {max(_moved(s, nominal) for s in states):.2e} m")
    return lines


def check() -> list[str]:
    shipped = load_problem_set(TARGET)      # reading it checks every state: positions, robots outside obstacles
    errors = _valid(shipped) + _tags(shipped)
    return errors or _rebuilt(shipped)


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true", help="check the shipped file instead of writing it")
    mode.add_argument("--spread", action="store_true", help="print how far a nanometre moves each default state")
    args = parser.parse_args(argv)
    with stop_at_once("problem-set study"):      # Ctrl-C: at once, nothing written
        if args.spread:
            print("\n".join(spread()))
            return 0
        if args.check:
            return check_result(check(), TARGET.name, "python studies/default_problems.py")
        text = dumps_problem_set(build())
    TARGET.write_text(text, encoding="utf-8")
    print(f"wrote {TARGET}")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

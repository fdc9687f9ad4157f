"""The ``mpc-hunt`` command line: simulate, solve, compare, problems, scenarios, backends.

Every name and output path is checked before any work, and every error is one
line on stderr with exit status 2, never a traceback. Formulations, backends
and controllers are listed from the registry without importing them.
"""

from __future__ import annotations

import argparse
import copy
import itertools
import json
import os
import shlex
import sys
from contextlib import contextmanager
from pathlib import Path

from mpc_hunt import __version__
from mpc_hunt.arguments import EXIT_USAGE, CommandParser, count, non_negative, positive_float, run_command, seed
from mpc_hunt.capture.problem import OBJECTIVES
from mpc_hunt.cli import sweep as cli_sweep
from mpc_hunt.cli.common import (
    MAX_PROBLEMS,
    MAX_RANDOM,
    MAX_RUN_LENGTH,
    MAX_STARTS,
    Progress,
    belief,
    check_writable,
    flag,
    messages,
    quiet_solvers,
)
from mpc_hunt.control import controllers
from mpc_hunt.control.recommended import OTHER_HORIZON, PAPER, RECOMMENDED, RECOMMENDED_CONTROLLER
from mpc_hunt.control.spec import ControllerSpec, horizon_argument
from mpc_hunt.errors import MpcHuntError, SettingError
from mpc_hunt.interrupt import stop_at_once, stop_keeping
from mpc_hunt.solving import registry
from mpc_hunt.solving.backends.base import ACCURACIES, MAX_ITERATIONS
from mpc_hunt.solving.backends.hpipm import MODES as HPIPM_MODES
from mpc_hunt.solving.export import TARGETS as EXPORT_TARGETS
from mpc_hunt.world.behaviours import BEHAVIOURS, with_behaviour
from mpc_hunt.world.belief import Belief, belief_rng
from mpc_hunt.world.scenario import MAX_DEFENDERS
from mpc_hunt.world.scenario_io import (
    DEFAULT_SCENARIO,
    builtin_name,
    builtin_names,
    builtin_scenario,
    dumps_scenario,
    resolve_scenario,
)

EXIT_ERROR = EXIT_USAGE  # an error's, and an interrupted run's that kept what finished
FIGURE_SUFFIXES = (".png", ".pdf", ".svg")
ANIMATION_SUFFIXES = (".gif",)
EXPORT_BACKENDS = tuple(b for b in registry.BACKENDS if registry.backend_class(b).exports)  # their steps as C
OWN_LOOP = "own-loop"  # compare's mode whose pairs run hunts in their own loops (mpc_hunt/bench/own_loop.py)
OWN_LOOP_SCENARIOS = ("paper-open", "paper-obstacles")
MAX_OWN_LOOP_HUNTS = 200

# problems --build's counts: (option, its number type, default, metavar, what it counts)
BUILD_COUNTS = (
    ("--every", count(MAX_PROBLEMS), 560, "K", "a run starts at every K-th capture-stage state"),
    ("--run-length", count(MAX_RUN_LENGTH), 4, "L", "consecutive states per run"),
    ("--random", non_negative(MAX_RANDOM), 2, "M", "random states per constraint family"),
)


def _backend_help() -> str:
    defaults = ", ".join(f"{f}→{registry.formulation_class(f).default_backend}" for f in registry.FORMULATIONS)
    return f"solver backend (default: the formulation's own: {defaults})"


def _solver_arguments(p: argparse.ArgumentParser, default: dict, which: str) -> None:
    p.add_argument(
        "--scenario",
        default=DEFAULT_SCENARIO,
        metavar="NAME_OR_FILE",
        help=f"built-in name ({', '.join(builtin_names())}) or a TOML file (default: {DEFAULT_SCENARIO})",
    )
    p.add_argument(
        "--formulation",
        choices=sorted(registry.FORMULATIONS),
        help=f"capture-stage formulation (default: {default['formulation']}, {which})",
    )
    p.add_argument("--backend", choices=sorted(registry.BACKENDS), help=_backend_help())
    p.add_argument(
        "--horizon",
        type=horizon_argument,
        metavar="N",
        help=f"receding horizon in steps (default: {OTHER_HORIZON}"
        + ("" if default["horizon"] == OTHER_HORIZON else f"; {default['horizon']} with the default formulation")
        + ")",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object instead of a summary")
    p.set_defaults(solver_default=default)


def _budget_arguments(p: argparse.ArgumentParser, deadline: str | None = None) -> None:
    """A capture step's budget, one name for every backend's setting (docs/benchmarks.md, "Budgets"); ``deadline``,
    where the command runs a loop, prefixes --deadline's help with the runs it applies to."""
    p.add_argument(
        "--time-limit",
        type=positive_float,
        metavar="SECONDS",
        help="time limit of each capture-stage step: its solves share it, each handed what is left; a solve "
        "stopped by it fails (the hunt's own limit is the scenario's time_limit)",
    )
    p.add_argument(
        "--max-iter",
        type=count(MAX_ITERATIONS),
        metavar="N",
        help="iteration cap of each capture-stage solve (every backend's, under this one name)",
    )
    if deadline is not None:
        p.add_argument(
            "--deadline",
            type=positive_float,
            metavar="SECONDS",
            help=f"{deadline}the step's budget (e.g. 0.02 for 50 Hz): the report counts the steps that took "
            "longer, beside those longer than the time step T",
        )


def _spec(args, controller: str, options: dict | None = None) -> ControllerSpec:
    """The controller spec the flags name (--formulation, --backend, --horizon; the command's default stage where
    they name none) with ``options``, checked before any work; a refusal names the fields, :func:`main` the flags."""
    return ControllerSpec(
        controller, args.formulation, args.backend, args.horizon, options=options or {}, stage=args.solver_default
    )


def build_parser() -> argparse.ArgumentParser:
    parser = CommandParser(prog="mpc-hunt", description="Multi-robot cooperative hunting as optimisation and MPC.")
    parser.add_argument("--version", action="version", version=f"mpc-hunt {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=CommandParser)

    sim = sub.add_parser(
        "simulate",
        help="run one closed-loop hunt",
        description="Run one closed-loop hunt and report capture, path lengths and clearances. "
        "Progress goes to stderr (not with --json).",
    )
    _solver_arguments(
        sim,
        RECOMMENDED,
        "the recommended capture stage; the paper's is --controller paper "
        "--formulation nlp --horizon 1 (docs/robustness.md)",
    )
    sim.add_argument(
        "--controller",
        default=RECOMMENDED_CONTROLLER,
        choices=sorted(controllers.CONTROLLERS),
        help=f"{controllers.described()} (default: {RECOMMENDED_CONTROLLER}; only "
        f"{', '.join(controllers.SOLVING)} take --formulation, --backend, --horizon, --time-limit "
        f"and --score)",
    )
    sim.add_argument(
        "--attacker",
        choices=list(BEHAVIOURS),
        metavar="NAME",
        help=f"how the world moves the attacker, instead of the scenario's behaviour: "
        f"{', '.join(BEHAVIOURS)} (mpc_hunt/world/behaviours/)",
    )
    sim.add_argument(
        "--belief",
        type=belief,
        default=Belief(),
        metavar="SPEC",
        help="the defenders' model of the attacker, as errors against the world: "
        "perception_radius=1.3x,eta=3x,intent_heading=60 (degrees), or exact (the default)",
    )
    sim.add_argument(
        "--seed",
        type=seed,
        metavar="S",
        help="seed of the world's random generator, numpy.random.default_rng(S) (what the attacker's "
        "behaviour draws), and of the belief's heading error, child 0 of SeedSequence(S) "
        "(default: 0)",
    )
    sim.add_argument(
        "--no-prediction",
        action="store_true",
        help="approach the attacker's current position instead of the predicted intercept",
    )
    _budget_arguments(sim, deadline="")
    sim.add_argument("--time-budget", type=positive_float, dest="time_limit", help=argparse.SUPPRESS)  # its old name
    sim.add_argument(
        "--score",
        action="store_true",
        help="score every capture-stage plan with the evaluator (without it only a failed solve's "
        "plan is scored, for the fallback; rti and stage-sqp run as a control loop either way)",
    )
    sim.add_argument(
        "--plot", type=Path, metavar="FILE", help=f"write the trajectory figure ({', '.join(FIGURE_SUFFIXES)})"
    )
    sim.add_argument("--animate", type=Path, metavar="FILE.gif", help="write an animation of the hunt")

    solve = sub.add_parser(
        "solve",
        help="solve one capture-stage problem",
        description="Solve one capture-stage problem (Eqs. 12-15) and score it with the shared evaluator. "
        "The state is --state FILE, or the scenario's default state: for a built-in scenario the one "
        "shipped in the problem set 'default'; for a scenario file the first state of its closed-loop "
        "run (paper strategy, prediction on) at which every defender is within R_agg and their "
        "distances to the attacker differ by at most 2 r_d (the hunting circle has formed).",
    )
    _solver_arguments(solve, PAPER, "the paper's one-step problem")
    solve.add_argument(
        "--state",
        type=Path,
        metavar="FILE",
        help='JSON state {"attacker": [x, y], "defenders": [[x, y], ...]} to solve at',
    )
    solve.add_argument("--save-state", type=Path, metavar="FILE", help="write the state solved at as JSON")
    _budget_arguments(solve)
    solve.add_argument(
        "--accuracy",
        choices=ACCURACIES,
        default="default",
        help="the solver's tolerances: default, high or low (docs/benchmarks.md)",
    )
    solve.add_argument(
        "--objective",
        choices=OBJECTIVES,
        default="paper",
        help="paper: Eq. 12 as published (default); enclose: places on the hunting circle, "
        "built at the state as the enclose controller's first step would (docs/formulations.md)",
    )

    exp = sub.add_parser(
        "export",
        help="write a stage-form capture step (rti, stage-sqp, distributed) as C sources for a robot's board",
        description="Write, for the structure of the capture problem at a state (as `solve` poses it: --scenario, "
        "--state, --horizon, --objective), the step of --formulation as C sources with a header, a "
        "Makefile, a program that reads a state's θ and reference and prints the plan, and that state's "
        "input and Python's plan (mpc_hunt/solving/export.py). On hpipm: linearisation, HPIPM, "
        "read-back (stage-sqp repeats it to convergence), HPIPM and BLASFEO as dependencies; on "
        "daqp-condensed (distributed's default): the step condensed to a dense QP in its controls and "
        "DAQP's own sources, nothing else needed, so it cross-compiles (--target).",
    )
    exp.add_argument(
        "--scenario",
        default=DEFAULT_SCENARIO,
        metavar="NAME_OR_FILE",
        help=f"built-in name or a TOML file (default: {DEFAULT_SCENARIO})",
    )
    exp.add_argument("--state", type=Path, metavar="FILE", help="JSON state to pose the problem at (as solve)")
    exp.add_argument("--horizon", type=horizon_argument, default=10, metavar="N", help="default: 10")
    exp.add_argument("--objective", choices=OBJECTIVES, default="paper", help="default: paper")
    exp.add_argument(
        "--formulation",
        default="rti",
        metavar="NAME",
        help="a stage-form step: rti (one QP a step, the default), stage-sqp (QPs to convergence) or "
        "distributed (one robot's own QP; with --objective enclose)",
    )
    exp.add_argument(
        "--backend",
        choices=EXPORT_BACKENDS,
        metavar="NAME",
        help="the step's solver: "
        + ", ".join(EXPORT_BACKENDS)
        + " (default: the formulation's own: "
        + ", ".join(f"{f}→{registry.formulation_class(f).default_backend}" for f in registry.stage_formulations())
        + ")",
    )
    exp.add_argument(
        "--robot",
        type=count(MAX_DEFENDERS),
        metavar="I",
        help="distributed only: the planned defender whose step to write, counted from 1 (default: 1)",
    )
    exp.add_argument(
        "--hpipm-mode",
        choices=HPIPM_MODES,
        help="hpipm only: HPIPM's mode: robust (the hpipm backend's, the default) or balance (Cholesky "
        "instead of LQ factorisations: faster with a BLASFEO built for the board's CPU, `make "
        "BLASFEO=DIR`; plans differ from robust's within HPIPM's tolerances)",
    )
    exp.add_argument(
        "--target",
        choices=tuple(EXPORT_TARGETS),
        default="host",
        help="the CPU the Makefile builds for: host (default), aarch64-linux (with "
        "aarch64-linux-gnu-gcc; run under qemu-aarch64 -L /usr/aarch64-linux-gnu) or cortex-m7 "
        "(bare metal, arm-none-eabi-gcc with newlib; `make run` on qemu's mps2-an500 board); "
        "daqp-condensed only",
    )
    exp.add_argument(
        "--output",
        type=Path,
        required=True,
        metavar="DIR",
        help="the folder to write (a new or existing folder, not the current one)",
    )
    exp.set_defaults(json=False)

    scen = sub.add_parser(
        "scenarios",
        help="list built-in scenarios, or write one out as TOML",
        description="List the built-in scenarios, or write one out as TOML to start from.",
    )
    scen.add_argument("--write", metavar="NAME", help="print (or with --output, save) this built-in as TOML")
    scen.add_argument("--output", type=Path, metavar="FILE", help="where --write saves the TOML")

    sub.add_parser(
        "backends",
        help="list formulations, backends and which pairs work here",
        description="List every registered formulation and backend, what each accepts, and whether "
        "its solver package is installed (with the install command if not).",
    )
    _compare_parser(sub)
    _problems_parser(sub)
    cli_sweep.add_parsers(sub)
    for command in sub.choices.values():
        command.add_argument(
            "--verbose",
            action="store_true",
            help="also show what the solver packages write to stderr (CasADi's and IPOPT's "
            "warnings, Python's warnings); without it only this command's own messages",
        )
    return parser


def _compare_parser(sub) -> None:
    from mpc_hunt.bench.compare import MODES
    from mpc_hunt.bench.own_loop import ABANDON_AFTER
    from mpc_hunt.capture.evaluator import OBJECTIVE
    from mpc_hunt.solving.accuracy import accuracy_table
    from mpc_hunt.solving.backends.base import ACCURACIES

    cmp = sub.add_parser(
        "compare",
        help="score formulations x backends over a problem set, like a solver benchmark",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Run every (formulation, backend) pair asked for over a problem set, at each horizon, in two "
        "modes: cold (each problem alone, fresh solver) and replayed (the set's recorded sequences, "
        "warm-started as the controller does). Per pair, mode and horizon: success rate, all-in solve "
        "time (median, p95, shifted geometric mean), solver time and our overhead, set-up apart, "
        "iterations, optimality gap against the best known, and the largest true violations. "
        "A progress bar goes to stderr (not with --json); Ctrl-C stops and keeps the finished solves.",
        epilog=f"The score of every plan, for every pair:\n\n{OBJECTIVE}\n\nAccuracy levels (the success rule's "
        f"violation tolerance and what each backend is handed):\n\n{accuracy_table()}\n\n"
        "Metrics are defined in docs/benchmarks.md.",
    )
    cmp.add_argument(
        "--problems",
        default="default",
        metavar="NAME_OR_FILE",
        help="a shipped problem set or a problem set file (default: default; see mpc-hunt problems)",
    )
    cmp.add_argument(
        "--tag",
        action="append",
        default=[],
        metavar="TAG",
        help="only problems with this tag (repeat for several, all required)",
    )
    cmp.add_argument(
        "--limit",
        type=count(MAX_PROBLEMS),
        metavar="K",
        help="at most K problems, drawn with --seed (sequences kept whole)",
    )
    cmp.add_argument(
        "--seed", type=seed, default=0, help="seed of the draw and of the reference's random starts (default: 0)"
    )
    cmp.add_argument(
        "--pair",
        action="append",
        metavar="FORMULATION[:BACKEND]",
        help="a pair to run (a formulation alone: all its installed backends); repeat for several "
        "(default: every registered pair whose solver is installed)",
    )
    cmp.add_argument(
        "--horizon",
        type=horizon_argument,
        nargs="+",
        default=[1],
        metavar="N",
        help="one or more horizons (default: 1)",
    )
    cmp.add_argument(
        "--mode",
        nargs="+",
        choices=MODES + (OWN_LOOP,),
        default=list(MODES),
        help="cold and replayed (the problem set's recorded states; the default: both), or "
        "own-loop alone: each pair drives whole hunts in its own receding-horizon loop, from the "
        "shipped paper scenarios and --hunts random ones (mpc_hunt/bench/own_loop.py)",
    )
    cmp.add_argument(
        "--hunts",
        type=non_negative(MAX_OWN_LOOP_HUNTS),
        default=10,
        metavar="K",
        help="own-loop: random hunts beside the two paper scenarios, drawn as the sweep draws hunt K of "
        "--seed (default: 10)",
    )
    cmp.add_argument(
        "--window",
        type=positive_float,
        default=120.0,
        metavar="SECONDS",
        help="own-loop: each hunt runs from where the paper's strategy first reaches the capture stage, "
        "for at most this long (default: 120)",
    )
    _budget_arguments(cmp, deadline="own-loop: ")
    cmp.add_argument(
        "--abandon-after",
        type=positive_float,
        metavar="SECONDS",
        help="own-loop: stop a hunt whose capture stage has failed this long in a row, counted "
        f"abandoned (default: {ABANDON_AFTER:g})",
    )
    cmp.add_argument(
        "--workers",
        type=count(os.cpu_count() or 1),
        metavar="K",
        help="own-loop: hunts at once on K processes (at most one a core), each hunt whole on one "
        "(default: 1; each "
        "hunt's times are then taken beside the others')",
    )
    cmp.add_argument(
        "--accuracy",
        choices=ACCURACIES,
        nargs="+",
        default=["default"],
        help="one or more profiles, each run on the same problems: default (ours, per backend), high, "
        "low, solver (each solver's own defaults) (default: default)",
    )
    cmp.add_argument(
        "--starts", type=count(MAX_STARTS), default=4, help="starts of the reference multi-start NLP (default: 4)"
    )
    cmp.add_argument(
        "--objective",
        choices=OBJECTIVES,
        default="paper",
        help="pose every problem with this objective: paper (Eq. 12, default) or enclose (the places "
        "the enclose controller would set at each state); plans are scored on it",
    )
    cmp.add_argument("--json", action="store_true", help="print one JSON object (machine, settings, rows)")
    cmp.add_argument("--csv", type=Path, metavar="FILE.csv", help="also write the rows as CSV")
    cmp.add_argument(
        "--report",
        type=Path,
        metavar="DIR",
        help="also write a Markdown report with its figures and every solve (results.json) into DIR",
    )
    cmp.add_argument("--plot", type=Path, metavar="DIR", help="also write the figures into DIR")


def _problems_parser(sub) -> None:
    prob = sub.add_parser(
        "problems",
        help="list, describe or build problem sets",
        description="Without arguments, list the problem sets shipped with mpc-hunt. With a set (a shipped name or "
        "a .json file), describe it, one line per problem. With --build, build a set: each scenario's "
        "default state and runs of consecutive capture-stage states from its closed-loop hunt, then "
        "random states around random obstacle layouts, each making one constraint family active; the "
        "format is documented in docs/benchmarks.md.",
    )
    prob.add_argument("set", nargs="?", metavar="NAME_OR_FILE", help="the set to describe")
    prob.add_argument("--build", type=Path, metavar="FILE.json", help="build a set and write it here")
    prob.add_argument(
        "--scenario",
        action="append",
        metavar="NAME_OR_FILE",
        help="a scenario whose hunt is sampled; repeat for several (default: every built-in); "
        "the first one's robots are the random states' template",
    )
    for option, number, default, metavar, meaning in BUILD_COUNTS:
        prob.add_argument(option, type=number, default=default, metavar=metavar, help=f"{meaning} (default: {default})")
    prob.add_argument("--seed", type=seed, default=0, help="seed of the random states (default: 0)")


def check_output(path: Path | None, suffixes: tuple[str, ...], option: str) -> None:
    """Refuse, before any work, an output path that cannot be written in a supported format."""
    if path is None:
        return
    if path.suffix.lower() not in suffixes:
        got = f"extension {path.suffix!r}" if path.suffix else "no extension"
        raise MpcHuntError(f"{option} {path}: {got} (use {', '.join(suffixes)})")
    if path.is_dir():
        raise MpcHuntError(f"{option} {path}: is a directory")
    if not path.parent.is_dir():
        raise MpcHuntError(f"{option} {path}: folder {path.parent} does not exist")
    check_writable(path.parent, option, path)


def _controller_spec(args) -> ControllerSpec:
    """--controller with the flags' settings (:func:`_spec`: the same as the sweep's strategy of that name)."""
    options = {"prediction": False} if args.no_prediction else {}
    if args.time_limit is not None:
        options["time_limit"] = args.time_limit
    if args.max_iter is not None:
        options["max_iter"] = args.max_iter
    if args.score:
        options["score"] = True
    return _spec(args, args.controller, options)


def _world(args, scenario):
    """The scenario with --attacker's behaviour, the world's random generator and the belief's (--seed;
    :func:`~mpc_hunt.world.belief.belief_rng` of a lone hunt)."""
    import numpy as np

    from mpc_hunt.sim.simulator import DEFAULT_SEED

    if args.attacker is not None:
        try:
            scenario = with_behaviour(scenario, args.attacker)
        except MpcHuntError as exc:
            raise MpcHuntError(f"--attacker {args.attacker} on {args.scenario}: {exc}") from None
    world_seed = DEFAULT_SEED if args.seed is None else args.seed
    return scenario, np.random.default_rng(world_seed), belief_rng(world_seed)


def _simulate(args) -> int:
    from mpc_hunt.sim.simulator import simulate

    spec = _controller_spec(args)
    check_output(args.plot, FIGURE_SUFFIXES, "--plot")
    check_output(args.animate, ANIMATION_SUFFIXES, "--animate")
    scenario, world, drawn = _world(args, resolve_scenario(args.scenario))
    controller = spec.build(scenario, belief=args.belief, rng=drawn)
    with stop_at_once("simulate"), Progress(scenario.hunt.time_limit, "hunt", quiet=args.json) as update:
        result = simulate(scenario, controller, progress=update, rng=world, deadline=args.deadline)
    report = result.to_dict()
    # The report goes out before any figure is written, so a failed write loses nothing computed.
    print(json.dumps(report) if args.json else _summary(result, report, scenario))
    if args.plot:
        from mpc_hunt.plots.hunt import plot_hunt

        plot_hunt(result, scenario, args.plot)
    if args.animate:
        from mpc_hunt.plots.animation import animate_hunt

        animate_hunt(result, scenario, args.animate)
    if not args.json:
        for path in (args.plot, args.animate):
            if path:
                print(f"wrote {path}")
    return 0


def _summary(result, report: dict, scenario) -> str:
    stats = report["solve_time"]
    c = result.controller
    if c["controller"] in controllers.SOLVING:
        how = (
            f"controller: {c['controller']}, its capture stage {c['formulation']} on {c['backend']}, horizon "
            f"{c['horizon']}, objective {c['objective']}"
        )
    else:
        how = f"controller: {c['controller']} (no capture-stage optimisation)"
    lines = [
        f"scenario {scenario.name}: "
        + (
            f"captured at t = {result.capture_time:.1f} s"
            if result.captured
            else f"NOT captured ({result.termination.replace('_', ' ')})"
        ),
        how + ("" if "prediction" not in c else f"; trajectory prediction {'on' if c['prediction'] else 'off'}"),
        "path lengths: " + ", ".join(f"{x:.2f} m" for x in result.path_lengths),
        f"final hunting radius: {result.final_hunting_radius:.3f} m (R_hunt {scenario.hunt.hunt_radius} m)",
        "min clearance to an obstacle surface: "
        + ("no obstacles" if result.min_obstacle_clearance is None else f"{result.min_obstacle_clearance:.3f} m"),
        "min defender separation: "
        + (
            "one defender"
            if report["min_defender_separation_m"] is None
            else f"{report['min_defender_separation_m']:.3f} m"
        )
        + "; "
        f"min attacker distance: {result.min_attacker_distance:.3f} m; steps: {result.steps}",
    ]
    if stats["count"]:
        lines.append(
            f"capture-stage solves: {stats['count']}, median {stats['median_s'] * 1e3:.2f} ms, "
            f"p95 {stats['p95_s'] * 1e3:.2f} ms, max {stats['max_s'] * 1e3:.2f} ms; "
            f"failed {result.failed_solves}, fallbacks {result.fallbacks}"
        )
        misses = stats["deadline_misses"]
        lines.append(
            f"solves longer than T = {misses['time_step_s']:g} s: {misses['over_time_step']}"
            + (
                ""
                if misses["deadline_s"] is None
                else f", than the deadline {misses['deadline_s']:g} s: {misses['over_deadline']}"
            )
            + f"; budget hits {result.budget_hits}; longest failure streak {result.longest_failure_streak}"
        )
    return "\n".join(lines)


def _state(args, scenario):
    from mpc_hunt.bench.capture_state import first_formed_circle
    from mpc_hunt.bench.problem_set import builtin_problem_set
    from mpc_hunt.world.hunt_state import load_state

    if args.state:
        return load_state(args.state, scenario)
    if builtin_name(args.scenario) is not None:
        state = builtin_problem_set("default").default_state(scenario.name)
        if state is not None:
            return state
    with Progress(scenario.hunt.time_limit, "finding the default state", quiet=args.json) as update:
        return first_formed_circle(scenario, progress=update)


def _solve(args) -> int:
    from mpc_hunt.control.posing import posed_problem
    from mpc_hunt.solving.solver import CaptureSolver
    from mpc_hunt.world.hunt_state import save_state

    stage = _spec(args, args.objective)  # the controller of each objective's name poses that objective
    formulation, backend, horizon = stage.capture_stage
    if args.save_state:
        check_output(args.save_state, (".json",), "--save-state")
    solver = CaptureSolver(
        formulation, backend, time_limit=args.time_limit, max_iter=args.max_iter, accuracy=args.accuracy
    )
    scenario = resolve_scenario(args.scenario)
    with stop_at_once("solve"):
        state = _state(args, scenario)
        solution = solver.solve(posed_problem(scenario, state, horizon, args.objective))
    if args.save_state:
        save_state(state, args.save_state)
    report = solution.to_dict()
    report.update(scenario=scenario.name, state=state.to_dict(), horizon=horizon)
    if args.json:
        print(json.dumps(report))
        return 0 if solution.success else 1
    lines = [
        f"{solution.formulation} on {solution.backend}, horizon {horizon}, scenario {scenario.name} "
        f"at t = {state.time:.1f} s: {solution.status.value} ({solution.message})"
    ]
    if solution.objective is not None and solution.violation is not None and solution.plan is not None:  # scored
        own = "–" if solution.formulation_objective is None else f"{solution.formulation_objective:.6g}"
        lines.append(f"objective (evaluator): {solution.objective:.6g}; formulation's own: {own}")
        lines.append("violations (m): " + ", ".join(f"{k} {v:.2e}" for k, v in solution.violation.items()))
        lines.append(
            "first step: " + "; ".join(f"defender {i}: [{x:.4f}, {y:.4f}]" for i, (x, y) in enumerate(solution.plan[0]))
        )
    if solution.certificate is not None:
        c = solution.certificate
        lines.append(
            f"certificate ({'IPOPT' if c.kind == 'nlp' else 'the QP handed to the solver'}): primal residual "
            f"{c.primal_residual:.2e}, dual residual {c.dual_residual:.2e}, duality gap {c.duality_gap:.2e}"
        )
    lines.append(
        f"time: solver {solution.solver_time * 1e3:.2f} ms + overhead {solution.overhead_time * 1e3:.2f} ms "
        f"(set-up {solution.setup_time * 1e3:.2f} ms); iterations {solution.iterations}"
    )
    print("\n".join(lines))
    return 0 if solution.success else 1


@contextmanager
def _export_flags(given: dict):
    """An export's refusal (:class:`SettingError`, naming its fields: mpc_hunt/solving/export.py) said with the
    flags, each with the value ``given`` it."""
    try:
        yield
    except SettingError as exc:
        flags = ", ".join(f"--{name} {given[name]}" for name in exc.fields)
        raise MpcHuntError(f"{flags}: {exc.reason}") from None


def _export(args) -> int:
    from mpc_hunt.control.posing import posed_problem
    from mpc_hunt.solving.export import check_target
    from mpc_hunt.solving.solver import CaptureSolver

    if args.formulation not in registry.stage_formulations():
        raise MpcHuntError(registry.stage_form_message(args.formulation))
    per_robot = registry.formulation_class(args.formulation).per_robot
    backend = args.backend or registry.formulation_class(args.formulation).default_backend
    if args.robot is not None and not per_robot:
        raise MpcHuntError(
            f"--robot: only a formulation that plans robot by robot (distributed) writes one robot's "
            f"step; {args.formulation} plans the team at once: drop --robot"
        )
    exports = registry.backend_class(backend).exports
    if args.hpipm_mode is not None and exports != "hpipm":
        raise MpcHuntError(
            f"--hpipm-mode: the step is solved by {backend}, not HPIPM: drop --hpipm-mode or add --backend hpipm"
        )
    if not str(args.output).strip() or args.output.resolve() == Path.cwd().resolve():
        raise MpcHuntError(
            f"--output {str(args.output)!r}: that is the current folder (as an empty name is); name "
            "a folder of its own for the step's files"
        )
    if args.output.exists() and not args.output.is_dir():
        raise MpcHuntError(f"--output {args.output}: exists and is not a folder")
    given = {"target": args.target, "backend": backend}
    with _export_flags(given):
        check_target(args.target, exports)
    scenario = resolve_scenario(args.scenario)
    robot = 1 if args.robot is None else args.robot
    options = {} if args.hpipm_mode is None else {"mode": args.hpipm_mode}
    with stop_at_once("export"):
        problem = posed_problem(scenario, _state(args, scenario), args.horizon, args.objective)
        if robot > problem.structure.planned:
            raise MpcHuntError(
                f"--robot {robot}: {problem.structure.planned} defenders are planned at this "
                f"state (1 to {problem.structure.planned})"
            )
        with _export_flags(given):
            files = CaptureSolver(args.formulation, backend, **options).export(
                args.output, problem, robot=robot - 1, target=args.target
            )
    structure = problem.structure if not per_robot else f"robot {robot} of {problem.structure}"
    run = EXPORT_TARGETS[args.target]["run"]
    print(
        f"wrote {len(files)} files for the structure ({structure}) into {args.output}; build with "
        f"make -C {shlex.quote(str(args.output))}, run with {run}"
    )
    return 0


def _scenarios(args) -> int:
    if args.write is None:
        if args.output:
            raise MpcHuntError("--output needs --write NAME")
        for name in builtin_names():
            scenario = builtin_scenario(name)
            default = " (default)" if name == DEFAULT_SCENARIO else ""
            print(f"{name}{default}: {scenario.description}")
        return 0
    text = dumps_scenario(resolve_scenario(args.write))
    if args.output:
        args.output.write_text(text, encoding="utf-8")
        print(f"wrote {args.output}")
    else:
        sys.stdout.write(text)
    return 0


def _backends(args) -> int:
    for f in registry.FORMULATIONS:
        cls = registry.formulation_class(f)
        notes = "; one QP per robot" if cls.per_robot else ""
        if set(cls.objectives) != set(OBJECTIVES):
            notes += f"; objective {' or '.join(cls.objectives)} only"
        print(
            f"formulation {f} (emits {cls.kind}; default backend {cls.default_backend}{notes}): "
            f"{', '.join(registry.compatible_backends(f))}"
        )
    for b in registry.BACKENDS:
        solver = registry.backend_class(b)
        where = "installed" if registry.installed(b) else f"NOT installed: pip install {solver.package}"
        only = f"; objective {' or '.join(solver.objectives)} only" if solver.objectives is not None else ""
        print(f"backend {b} (accepts {', '.join(solver.accepts)}{only}): {where}")
    return 0


def check_folder(path: Path | None, option: str) -> None:
    """Refuse, before any work, an output folder that is a file or whose parent does not exist."""
    if path is None:
        return
    if path.exists() and not path.is_dir() or not path.parent.is_dir():
        raise MpcHuntError(
            f"{option} {path}: " + ("is not a folder" if path.exists() else f"folder {path.parent} does not exist")
        )
    check_writable(path if path.exists() else path.parent, option, path)


def _compare(args) -> int:
    import numpy as np

    from mpc_hunt.bench.compare import check_pairs, planned_solves, run_compare
    from mpc_hunt.bench.compare_report import document, dumps, table, write_csv
    from mpc_hunt.bench.compare_rows import rows as score_rows
    from mpc_hunt.bench.machine import describe_machine, load_average
    from mpc_hunt.bench.problem_set import resolve_problem_set
    from mpc_hunt.plots.compare import plot_compare
    from mpc_hunt.plots.compare_report import write_report

    pairs = check_pairs(args.pair, args.objective)
    if OWN_LOOP in args.mode:
        return _compare_own_loop(args, pairs)
    for option, given in (
        ("--deadline", args.deadline),
        ("--abandon-after", args.abandon_after),
        ("--workers", args.workers),
    ):
        if given is not None:
            raise MpcHuntError(f"{option}: own-loop only (--mode own-loop)")
    check_output(args.csv, (".csv",), "--csv")
    check_folder(args.report, "--report")
    check_folder(args.plot, "--plot")
    rng = np.random.default_rng(args.seed)
    problem_set = resolve_problem_set(args.problems).select(tuple(args.tag), args.limit, rng)
    if not problem_set.problems:
        raise MpcHuntError(f"--tag {' '.join(args.tag)}: no problem of {args.problems!r} carries every tag")
    machine = describe_machine()
    accuracies = list(dict.fromkeys(args.accuracy))
    total = planned_solves(problem_set, len(pairs), args.horizon, args.mode, args.starts) * len(accuracies)
    runs = []
    with Progress(total, "compare", quiet=args.json, unit="solves") as update:
        done = itertools.count(1)
        for accuracy in accuracies:  # one run per profile, on the same problems and the same draws
            runs.append(
                run_compare(
                    problem_set,
                    pairs,
                    args.horizon,
                    args.mode,
                    copy.deepcopy(rng),
                    accuracy=accuracy,
                    time_limit=args.time_limit,
                    max_iter=args.max_iter,
                    starts=args.starts,
                    objective=args.objective,
                    progress=(lambda: update(next(done))) if update else None,
                )
            )
            if runs[-1].interrupted:
                break
    machine["load_average_end"] = load_average()
    rows = [row for run in runs for row in score_rows(run)]
    extra = {"problem_set": args.problems, "tags": args.tag, "limit": args.limit, "seed": args.seed}
    doc = document(runs[0], machine, rows, extra)
    doc["settings"]["accuracy"] = accuracies
    print(dumps(doc) if args.json else table(rows))
    if args.csv:
        write_csv(rows, args.csv)
    for run in runs:  # a folder per profile when there are several
        where = (lambda folder: folder) if len(runs) == 1 else (lambda folder: folder / run.accuracy)
        if args.plot:
            where(args.plot).mkdir(parents=True, exist_ok=True)
            plot_compare(run, score_rows(run), where(args.plot))
        if args.report:
            write_report(run, machine, where(args.report), "mpc-hunt " + shlex.join(args.argv), extra)
    solves = sum(len(run.records) for run in runs)
    if (
        len({row["solves"] for row in rows if row["mode"] == "cold"}) > 1
        or len({row["solves"] for row in rows if row["mode"] == "replayed"}) > 1
    ):
        print(
            "mpc-hunt compare: the rows hold different numbers of solves (see the solves column): compare them "
            "on the solves they share",
            file=messages(),
        )
    if runs[-1].interrupted:
        print(f"mpc-hunt compare: interrupted: kept {len(rows)} rows from {solves} finished solves", file=messages())
        return EXIT_ERROR
    return 0


def _compare_own_loop(args, pairs) -> int:
    from mpc_hunt.bench.compare_report import dumps
    from mpc_hunt.bench.machine import describe_machine, load_average
    from mpc_hunt.bench.own_loop import (
        ABANDON_AFTER,
        OwnLoopRun,
        capture_stage_hunts,
        hunt_summary,
        rows_of,
        run_own_loop,
    )
    from mpc_hunt.bench.own_loop import (
        table as loop_table,
    )
    from mpc_hunt.solving.accuracy import VIOLATION_TOLERANCE
    from mpc_hunt.sweep.random_scenario import sweep_scenario

    if len(args.mode) > 1:
        raise MpcHuntError("--mode own-loop: it runs hunts, not the problem set's states: give it alone")
    if len(args.accuracy) > 1:
        raise MpcHuntError("--accuracy: own-loop runs one profile at a time")
    for option, given in (
        ("--csv", args.csv),
        ("--report", args.report),
        ("--plot", args.plot),
        ("--tag", args.tag),
        ("--limit", args.limit),
    ):
        if given:
            raise MpcHuntError(f"{option}: not with --mode own-loop (its results: the table, or --json)")
    untimed = [b for _, b in pairs if args.time_limit is not None and not registry.backend_class(b).TIME_LIMIT]
    if untimed:
        raise MpcHuntError(
            f"--time-limit: backend {untimed[0]} takes none; leave it out of the pairs (--pair) or drop --time-limit"
        )
    if not args.json:
        print("finding where each hunt's capture stage starts (the paper's strategy)", file=messages())
    with stop_at_once("compare"):
        scenarios = capture_stage_hunts(
            [builtin_scenario(name) for name in OWN_LOOP_SCENARIOS],
            (sweep_scenario(args.seed, i) for i in itertools.count()),
            args.hunts,
            args.window,
        )
    controller = "paper" if args.objective == "paper" else "enclose"
    abandon_after = ABANDON_AFTER if args.abandon_after is None else args.abandon_after
    workers = 1 if args.workers is None else args.workers
    machine = describe_machine()
    settings = {
        "mode": OWN_LOOP,
        "controller": controller,
        "scenarios": [s.name for s in scenarios],
        "window_s": args.window,
        "pairs": [f"{f}:{b}" for f, b in pairs],
        "horizons": args.horizon,
        "accuracy": args.accuracy[0],
        "violation_tolerance_m": VIOLATION_TOLERANCE[args.accuracy[0]],
        "time_limit_s": args.time_limit,
        "max_iter": args.max_iter,
        "deadline_s": args.deadline,
        "abandon_after_s": abandon_after,
        "workers": workers,
        "seed": args.seed,
    }
    finished: list = []

    def report(interrupted: bool) -> None:
        """The rows of the hunts finished so far (on Ctrl-C too: nothing computed is lost)."""
        machine["load_average_end"] = load_average()
        rows = rows_of(
            [hunt_summary(h) for h in finished], pairs, args.horizon, settings["violation_tolerance_m"], args.deadline
        )
        print(
            dumps({"machine": machine, "settings": settings, "interrupted": interrupted, "rows": rows})
            if args.json
            else loop_table(rows)
        )

    total = len(scenarios) * len(pairs) * len(args.horizon)
    with (
        stop_keeping("compare", lambda: report(True)),
        Progress(total, "compare (own loop)", quiet=args.json, unit="hunts") as update,
    ):
        done = itertools.count(1)

        def keep(hunt) -> None:
            finished.append(hunt)
            if update:
                update(next(done))

        run = OwnLoopRun(
            scenarios,
            pairs,
            args.horizon,
            controller=controller,
            accuracy=args.accuracy[0],
            time_limit=args.time_limit,
            max_iter=args.max_iter,
            deadline=args.deadline,
            abandon_after=abandon_after,
        )
        run_own_loop(run, workers, keep)
    report(False)
    return 0


def _problems(args) -> int:
    from mpc_hunt.bench.problem_set import builtin_problem_set, builtin_problem_sets, resolve_problem_set

    if args.build:
        if args.set:
            raise MpcHuntError("--build: give either a set to describe or --build FILE, not both")
        return _build_problems(args)
    if args.set is None:
        for name in builtin_problem_sets():
            ps = builtin_problem_set(name)
            print(f"{name}: {len(ps.problems)} problems; {ps.description}")
        return 0
    ps = resolve_problem_set(args.set)
    print("\n".join(ps.describe()))
    for p in ps.problems:
        controlled = int(ps.problem(p).controlled.sum())
        print(
            f"{p.id}: scenario {p.scenario}, t = {p.state.time:.1f} s, {controlled} controlled"
            + (f", sequence {p.sequence}" if p.sequence else "")
            + f"; tags: {', '.join(p.tags) or '-'}"
        )
    return 0


def _build_problems(args) -> int:
    import numpy as np

    from mpc_hunt.bench.build_problems import build_problem_set
    from mpc_hunt.bench.problem_set import save_problem_set

    check_output(args.build, (".json",), "--build")
    scenarios = [resolve_scenario(s) for s in (args.scenario or builtin_names())]
    with stop_at_once("problems"):
        ps = build_problem_set(
            scenarios,
            np.random.default_rng(args.seed),
            every=args.every,
            run_length=args.run_length,
            random_per_case=args.random,
            description=f"Built by mpc-hunt problems --build (every {args.every}, runs of "
            f"{args.run_length}, {args.random} random states per family, seed "
            f"{args.seed}).",
        )
    save_problem_set(ps, args.build)
    print("\n".join(ps.describe()))
    print(f"wrote {args.build}")
    return 0


def main(argv: list[str] | None = None) -> int:
    """Run ``mpc-hunt`` with the arguments ``argv`` (default: the process's) and return its exit status: 0 when
    the command succeeded; an error of the toolkit's or of a file is one line on stderr and status 2, and so is
    Ctrl-C, after what finished was kept. ``mpc_hunt.cli.main(["simulate", "--json"])`` runs a command from
    Python as the shell would."""
    args = build_parser().parse_args(argv)
    args.argv = sys.argv[1:] if argv is None else list(argv)
    command = {
        "simulate": _simulate,
        "solve": _solve,
        "scenarios": _scenarios,
        "backends": _backends,
        "compare": _compare,
        "problems": _problems,
        "export": _export,
        **cli_sweep.HANDLERS,
    }[args.command]

    def run() -> int:
        with quiet_solvers(args.verbose):
            return command(args)

    return run_command(f"mpc-hunt {args.command}", run, flag)


if __name__ == "__main__":
    sys.exit(main())

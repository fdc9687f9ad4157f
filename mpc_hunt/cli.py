"""The ``mpc-hunt`` command line: simulate, solve, scenarios.

Every error is one line on stderr and a non-zero exit status, never a traceback.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from formulations import FORMULATIONS
from mpc_hunt.backends import BACKENDS
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.scenario_io import DEFAULT_SCENARIO, builtin_names, builtin_scenario, dumps_scenario, resolve_scenario

EXIT_ERROR = 2


class _Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line."""

    def error(self, message: str):  # noqa: D102 - argparse's hook
        self.exit(EXIT_ERROR, f"{self.prog}: error: {message} (see --help)\n")


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive finite number, got {text}")
    return value


def _solver_arguments(p: argparse.ArgumentParser, formulation_default: str | None) -> None:
    p.add_argument("--scenario", default=DEFAULT_SCENARIO, metavar="NAME_OR_FILE",
                   help=f"built-in name ({', '.join(builtin_names())}) or a TOML file (default: {DEFAULT_SCENARIO})")
    p.add_argument("--formulation", default=formulation_default, choices=sorted(FORMULATIONS),
                   help="capture-stage formulation" + (f" (default: {formulation_default})" if formulation_default else ""))
    p.add_argument("--backend", choices=sorted(BACKENDS),
                   help="solver backend (default: the formulation's own: nlp→ipopt, qp/sqp→osqp, socp→clarabel)")
    p.add_argument("--horizon", type=_positive_int, default=1, metavar="N",
                   help="receding horizon in steps (default: 1, the paper's one-step problem)")
    p.add_argument("--json", action="store_true", help="print one JSON object instead of a summary")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="mpc-hunt", description="Multi-robot cooperative hunting as optimisation and MPC.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    sim = sub.add_parser("simulate", help="run one closed-loop hunt",
                         description="Run one closed-loop hunt and report capture, path lengths and clearances.")
    _solver_arguments(sim, "nlp")
    sim.add_argument("--no-prediction", action="store_true",
                     help="approach the attacker's current position instead of the predicted intercept")
    sim.add_argument("--time-budget", type=_positive_float, metavar="SECONDS",
                     help="per-step limit handed to the capture-stage solver")
    sim.add_argument("--plot", type=Path, metavar="FILE", help="write the trajectory figure (PNG, PDF, SVG)")
    sim.add_argument("--animate", type=Path, metavar="FILE.gif", help="write an animation of the hunt")

    solve = sub.add_parser(
        "solve", help="solve one capture-stage problem",
        description="Solve one capture-stage problem (Eqs. 12-15) and score it with the shared evaluator. "
                    "The state is the first one of the scenario's closed-loop run (paper strategy, prediction on) "
                    "at which every defender is within R_agg and their distances to the attacker differ by at most "
                    "2 r_d (the hunting circle has formed), or the state in --state FILE.")
    _solver_arguments(solve, "nlp")
    solve.add_argument("--state", type=Path, metavar="FILE",
                       help='JSON state {"attacker": [x, y], "defenders": [[x, y], ...]} to solve at')
    solve.add_argument("--save-state", type=Path, metavar="FILE", help="write the state solved at as JSON")
    solve.add_argument("--time-limit", type=_positive_float, metavar="SECONDS", help="solver time limit")

    scen = sub.add_parser("scenarios", help="list built-in scenarios, or write one out as TOML",
                          description="List the built-in scenarios, or write one out as TOML to start from.")
    scen.add_argument("--write", metavar="NAME", help="print (or with --output, save) this built-in as TOML")
    scen.add_argument("--output", type=Path, metavar="FILE", help="where --write saves the TOML")
    return parser


def _simulate(args) -> int:
    from mpc_hunt.simulator import simulate
    from mpc_hunt.strategy import HuntingStrategy

    scenario = resolve_scenario(args.scenario)
    strategy = HuntingStrategy(scenario, prediction=not args.no_prediction, formulation=args.formulation,
                               backend=args.backend, horizon=args.horizon, time_limit=args.time_budget)
    result = simulate(scenario, strategy)
    report = result.to_dict()
    # The report goes out before any figure is written, so a bad output path loses nothing computed.
    print(json.dumps(report) if args.json else _summary(result, report, scenario))
    if args.plot:
        from mpc_hunt.plotting import plot_hunt
        plot_hunt(result, scenario, args.plot)
    if args.animate:
        from mpc_hunt.animation import animate_hunt
        animate_hunt(result, scenario, args.animate)
    if not args.json:
        for path in (args.plot, args.animate):
            if path:
                print(f"wrote {path}")
    return 0


def _summary(result, report: dict, scenario) -> str:
    stats = report["solve_time"]
    lines = [
        f"scenario {scenario.name}: "
        + (f"captured at t = {result.capture_time:.1f} s" if result.captured
           else f"NOT captured ({result.termination.replace('_', ' ')})"),
        f"capture stage: {result.formulation} on {result.backend}, horizon {result.horizon}; "
        f"trajectory prediction {'on' if result.prediction else 'off'}",
        "path lengths: " + ", ".join(f"{x:.2f} m" for x in result.path_lengths),
        f"final hunting radius: {result.final_hunting_radius:.3f} m (R_hunt {scenario.hunt.hunt_radius} m)",
        "min clearance to an obstacle surface: "
        + ("no obstacles" if result.min_obstacle_clearance is None else f"{result.min_obstacle_clearance:.3f} m"),
        f"min defender separation: {report['min_defender_separation_m']:.3f} m; "
        f"min attacker distance: {result.min_attacker_distance:.3f} m; steps: {result.steps}",
    ]
    if stats["count"]:
        lines.append(f"capture-stage solves: {stats['count']}, median {stats['median_s'] * 1e3:.2f} ms, "
                     f"p95 {stats['p95_s'] * 1e3:.2f} ms, max {stats['max_s'] * 1e3:.2f} ms; "
                     f"failed {result.failed_solves}, fallbacks {result.fallbacks}")
    return "\n".join(lines)


def _solve(args) -> int:
    from mpc_hunt.capture_problem import CaptureProblem
    from mpc_hunt.capture_state import first_formed_circle, load_state, save_state
    from mpc_hunt.solver import solve

    scenario = resolve_scenario(args.scenario)
    state = load_state(args.state, scenario) if args.state else first_formed_circle(scenario)
    if args.save_state:
        save_state(state, args.save_state)
    problem = CaptureProblem.at_state(scenario, state.attacker, state.defenders, args.horizon)
    solution = solve(problem, args.formulation, args.backend, time_limit=args.time_limit)
    report = solution.to_dict()
    report.update(scenario=scenario.name, state=state.to_dict(), horizon=args.horizon)
    if args.json:
        print(json.dumps(report))
        return 0 if solution.success else 1
    lines = [f"{solution.formulation} on {solution.backend}, horizon {args.horizon}, scenario {scenario.name} "
             f"at t = {state.time:.1f} s: {solution.status.value} ({solution.message})"]
    if solution.objective is not None:
        lines.append(f"objective (evaluator): {solution.objective:.6g}; "
                     f"formulation's own: {solution.formulation_objective:.6g}")
        lines.append("violations (m): " + ", ".join(f"{k} {v:.2e}" for k, v in solution.violation.items()))
        lines.append("first step: " + "; ".join(f"defender {i}: [{x:.4f}, {y:.4f}]"
                                                  for i, (x, y) in enumerate(solution.plan[0])))
    lines.append(f"time: solver {solution.solver_time * 1e3:.2f} ms + overhead {solution.overhead_time * 1e3:.2f} ms "
                 f"(set-up {solution.setup_time * 1e3:.2f} ms); iterations {solution.iterations}")
    print("\n".join(lines))
    return 0 if solution.success else 1


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


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    command = {"simulate": _simulate, "solve": _solve, "scenarios": _scenarios}[args.command]
    try:
        return command(args)
    except MpcHuntError as exc:
        print(f"mpc-hunt {args.command}: error: {exc}", file=sys.stderr)
    except BrokenPipeError:  # the reader went away (e.g. `| head`): nothing left to report
        return EXIT_ERROR
    except OSError as exc:
        print(f"mpc-hunt {args.command}: error: {exc.filename or ''}: {exc.strerror or exc}", file=sys.stderr)
    except KeyboardInterrupt:
        print(f"mpc-hunt {args.command}: interrupted", file=sys.stderr)
    return EXIT_ERROR


if __name__ == "__main__":
    sys.exit(main())

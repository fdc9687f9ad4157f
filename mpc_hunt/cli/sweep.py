"""``mpc-hunt sweep`` and ``mpc-hunt sweep-report``: Monte Carlo hunts, stored and summarised."""

from __future__ import annotations

import json
from pathlib import Path

from mpc_hunt.arguments import cores_count, count, seed, shown
from mpc_hunt.cli.common import MAX_HUNTS, Progress, belief, check_writable, messages
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.world.behaviours import BEHAVIOURS, DEFAULT_BEHAVIOUR
from mpc_hunt.world.belief import Belief


def add_parsers(sub) -> None:
    from mpc_hunt.sweep.runner import DEFAULT_STRATEGIES, MAX_TASKS

    sw = sub.add_parser(
        "sweep",
        help="run many random hunts for one or more strategies",
        description="Run --hunts random hunts (mpc_hunt.sweep.random_scenario; ranges from --ranges FILE and --set) "
        "for each strategy against each attacker with each belief, on local worker processes or a Dask "
        "cluster, streaming one row per hunt into an SQLite file; then print the summary per strategy, "
        "attacker and belief. A strategy is a controller spec, "
        "controller[:formulation[:backend[:horizon]]], e.g. paper:nlp:ipopt:1 (the paper's), "
        "paper:qp:daqp:5, apf; a field left out is what simulate --controller takes for it (enclose is "
        "enclose:rti:hpipm:10). "
        "Failure causes and the file's columns: docs/robustness.md.",
    )
    sw.add_argument(
        "--strategy", action="append", metavar="SPEC", help=f"repeatable (default: {' '.join(DEFAULT_STRATEGIES)})"
    )
    sw.add_argument(
        "--attacker",
        action="append",
        choices=list(BEHAVIOURS),
        metavar="NAME",
        help=f"how the world moves the attacker: {', '.join(BEHAVIOURS)}; repeatable (default: "
        f"{DEFAULT_BEHAVIOUR}, the paper's). Hunt i's scenario is the same for every attacker, its "
        "behaviour replaced",
    )
    sw.add_argument(
        "--belief",
        action="append",
        type=belief,
        metavar="SPEC",
        help="the defenders' model of the attacker, as errors against the world: "
        "perception_radius=1.3x,eta=3x,intent_heading=60 (degrees), or exact; repeatable "
        "(default: exact). Stored and run as its label (values to 6 significant digits)",
    )
    sw.add_argument(
        "--hunts",
        type=count(MAX_HUNTS),
        default=100,
        help=f"hunts per strategy, attacker and belief (default: 100; at most {MAX_TASKS} hunts in all)",
    )
    sw.add_argument("--seed", type=seed, default=0, help="the sweep's seed (≥ 0); hunt i uses scenario (seed, i)")
    sw.add_argument("--ranges", type=Path, metavar="FILE", help="TOML file of scenario ranges ([ranges] table)")
    sw.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="FIELD=VALUE",
        help="override one range, e.g. --set n_defenders=3 --set defender_failure=0.5 (TOML values)",
    )
    sw.add_argument("--output", type=Path, default=Path("sweep.db"), help="the results file (default: sweep.db)")
    sw.add_argument("--resume", action="store_true", help="continue the sweep in --output, skipping finished hunts")
    sw.add_argument(
        "--workers", type=cores_count, help="local worker processes (default: the number of cores; at most 4 per core)"
    )
    sw.add_argument("--dask-scheduler", metavar="ADDRESS", help="run on this Dask distributed scheduler instead")
    sw.add_argument("--json", action="store_true", help="print the summary as JSON")
    rep = sub.add_parser(
        "sweep-report",
        help="summarise a sweep's results file",
        description="Recompute a sweep's summary, table and plots from its results file alone.",
    )
    rep.add_argument("file", type=Path)
    what = rep.add_mutually_exclusive_group()
    what.add_argument(
        "--plot",
        type=Path,
        metavar="DIR",
        help="write the figures (PNG) into this folder, with the best strategy's typical captured and "
        "lost hunt (of every attacker and belief) rerun with their own attacker and belief "
        "(a few seconds each)",
    )
    what.add_argument(
        "--versus",
        nargs=2,
        metavar=("A", "B"),
        help="instead of the summary: strategy A's captures minus B's on the hunts both ran, per attacker and "
        "belief, with Newcombe's 95 %% interval for paired proportions (which of the two it tells apart), and "
        "A's capture time minus B's on the hunts both captured (median, sign-test 95 %% interval)",
    )
    rep.add_argument("--json", action="store_true", help="print the summary as JSON")


def _strategy(text: str, flag: str = "--strategy"):
    """The controller spec ``flag`` writes (:meth:`~mpc_hunt.control.spec.ControllerSpec.parse`), a refusal
    naming it."""
    from mpc_hunt.control.spec import ControllerSpec

    try:
        return ControllerSpec.parse(text)
    except MpcHuntError as exc:
        raise MpcHuntError(f"{flag} {shown(text)}: {exc}") from None


def _ranges(args):
    import tomllib

    from mpc_hunt.sweep.random_scenario import ScenarioRanges, load_ranges, ranges_with

    ranges = load_ranges(args.ranges) if args.ranges else ScenarioRanges()
    overrides = {}
    for item in args.set:
        field, sep, value = item.partition("=")
        if not sep:
            raise MpcHuntError(f"--set {item!r}: expected FIELD=VALUE")
        try:
            overrides[field.strip()] = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError:
            raise MpcHuntError(f"--set {item!r}: the value is not a TOML number or array") from None
    return ranges_with(ranges, overrides)


def sweep(args) -> int:
    from mpc_hunt.sweep.random_scenario import ranges_to_dict
    from mpc_hunt.sweep.runner import DEFAULT_STRATEGIES, check_buildable, connect_dask, tasks, total_tasks
    from mpc_hunt.sweep.store import SweepStore
    from mpc_hunt.sweep.stored_run import run_into

    strategies = [_strategy(s).label for s in (args.strategy or DEFAULT_STRATEGIES)]
    attackers = list(dict.fromkeys(args.attacker or [DEFAULT_BEHAVIOUR]))
    beliefs = list(dict.fromkeys(b.label() for b in (args.belief or [Belief()])))  # eta=3 and eta=3x are one
    total_tasks(strategies, args.hunts, attackers, beliefs)  # bounded, before any file is written
    ranges = _ranges(args)
    check_buildable(strategies, attackers, args.seed, ranges)  # each built once, before any file is written
    if args.output.is_dir() or not args.output.parent.is_dir():
        raise MpcHuntError(f"--output {args.output}: not a file in an existing folder")
    check_writable(args.output.parent, "--output", args.output)
    arguments = {
        "strategies": strategies,
        "attackers": attackers,
        "beliefs": beliefs,
        "hunts": args.hunts,
        "seed": args.seed,
        "ranges": ranges_to_dict(ranges),
    }
    client = connect_dask(args.dask_scheduler) if args.dask_scheduler else None  # before any file is written
    store = SweepStore(args.output, arguments, resume=args.resume)
    todo = tasks(strategies, args.hunts, args.seed, ranges, store.done(), attackers, beliefs)
    with Progress(len(todo), "sweep", quiet=args.json, unit="hunts") as update:
        stopped = run_into(store, todo, args.workers, client, update)
    code = _report(store.rows(), args.json, None)  # the summary so far, if stopped
    store.close()
    if stopped:
        print(
            f"mpc-hunt sweep: {stopped}; finished hunts are in {args.output} (continue with --resume)", file=messages()
        )
        return 2
    return code


def sweep_report(args) -> int:
    from mpc_hunt.sweep.store import SweepStore

    store = SweepStore(args.file)
    rows = store.rows()
    store.close()
    if args.plot and not args.plot.is_dir():
        raise MpcHuntError(f"--plot {args.plot}: not an existing folder")
    if args.plot:
        check_writable(args.plot, "--plot", args.plot)
    if args.versus:
        return _versus(rows, args.versus, args.json)
    return _report(rows, args.json, args.plot)


def _versus(rows: list[dict], pair: list[str], as_json: bool) -> int:
    from mpc_hunt.sweep.paired import versus, versus_table

    try:
        entries = versus(rows, *(_strategy(name, "--versus").label for name in pair))
    except MpcHuntError as exc:
        raise MpcHuntError(f"--versus {exc}") from None
    print(json.dumps({"versus": entries}) if as_json else versus_table(entries))
    return 0


def _report(rows: list[dict], as_json: bool, plot: Path | None) -> int:
    from mpc_hunt.sweep.summary import summarise, table

    summaries = summarise(rows)
    print(json.dumps({"strategies": summaries}) if as_json else table(summaries))
    if plot:
        from mpc_hunt.plots.sweep import write_plots
        from mpc_hunt.plots.typical_hunts import plot_typical_hunts
        from mpc_hunt.sweep.typical import typical_hunts

        for path in write_plots(rows, plot) + plot_typical_hunts(typical_hunts(rows, summaries), plot):
            if not as_json:
                print(f"wrote {path}")
    return 0


HANDLERS = {"sweep": sweep, "sweep-report": sweep_report}

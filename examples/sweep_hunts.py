"""Sweep random hunts, on local processes and on a Dask cluster, and summarise them per strategy.

A sweep's task is a ``Hunt``: a strategy (a controller spec's label, ``controller[:formulation[:backend[:horizon]]]``)
on the random scenario (seed, index) drawn from ranges, the attacker moving by a named behaviour, the defenders
holding a belief. ``run_local`` runs tasks on local worker processes and ``run_dask`` on the cluster of a Dask
client, both yielding each hunt's row (plain data) as it finishes; ``summarise`` turns rows into one summary per
strategy, attacker and belief; ``versus`` sets two strategies side by side on the hunts both ran (their paired
difference, with Newcombe's interval). ``mpc-hunt sweep`` adds the results file (resume after an interruption) and
``mpc-hunt sweep-report`` the figures.

Small by default: one hunt per strategy locally, then the first strategy's on a one-worker Dask cluster started here
(skipped, with the reason, without ``pip install "mpc-hunt[dask]"``), scenarios of four or five defenders and at
most two obstacles.
``--scheduler tcp://HOST:8786`` uses a running cluster instead.

    python examples/sweep_hunts.py [--hunts 20] [--workers 2] [--strategy voronoi --strategy trap:rti:hpipm:10]
"""

from __future__ import annotations

import argparse

from mpc_hunt.sweep import Hunt, connect_dask, run_dask, run_local, summarise, versus, versus_table


def show(where: str, rows: list[dict]) -> None:
    print(f"{where}: {len(rows)} hunts")
    for s in summarise(rows):
        rate = "n/a" if s["success_rate"] is None else f"{s['success_rate']:.0%}"
        failures = {cause: n for cause, n in s["failures"].items() if n}
        print(
            f"  {s['strategy']:22s} vs {s['attacker']:5s} ({s['belief']}): captured {s['captured']}/{s['hunts']} "
            f"({rate}), failures {failures or 'none'}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--strategy", action="append", help="a controller spec's label (repeatable)")
    parser.add_argument("--hunts", type=int, default=1)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int, default=1, help="local worker processes")
    parser.add_argument("--scheduler", help="a running Dask scheduler's address (default: a local cluster)")
    args = parser.parse_args()
    strategies = args.strategy or ["voronoi", "trap:rti:hpipm:5"]
    ranges = {"n_defenders": [4, 5], "n_obstacles": [0, 2]}  # any of ScenarioRanges' fields; the rest keep defaults

    tasks = [Hunt(s, args.seed, i, ranges) for i in range(args.hunts) for s in strategies]
    local = list(run_local(tasks, workers=args.workers))
    show(f"local, {args.workers} worker process(es)", local)
    if len(strategies) > 1:  # the first two, hunt by hunt (a handful of hunts tells little apart)
        print(versus_table(versus(local, *strategies[:2])))

    if args.scheduler:
        client = connect_dask(args.scheduler)
    else:
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            print('Dask: skipped (pip install "mpc-hunt[dask]")')
            return
        # in this process, one thread: a cluster of machines is started with `dask scheduler` and `dask worker`
        client = Client(LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None))
    again = [task for task in tasks if task.strategy == strategies[0]]
    on_dask = list(run_dask(again, client))  # closes the client when done
    show("Dask", on_dask)
    outcomes = {(r["strategy"], r["index"]): (r["outcome"], r["capture_time_s"]) for r in local}
    same = all(outcomes[r["strategy"], r["index"]] == (r["outcome"], r["capture_time_s"]) for r in on_dask)
    print(f"the same hunts on Dask as locally, to the capture time: {same}")


if __name__ == "__main__":
    main()

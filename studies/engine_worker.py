"""One process of the engine study (``studies/engine.py``): hunts of the study timed in this process, once warm.

Run by the study with the engine under test first on the path (this tree's, or the engine before the batched one,
unpacked from git; so it imports nothing of ``studies``): ``python studies/engine_worker.py --mode M --seed S
--first F --count C --batch B`` runs C hunts of the study from the F-th (``voronoi`` defenders, 3 to 5, against
the ``gap`` attacker, the sweep's random scenarios of seed S), M ``one`` one by one with ``simulate``, ``batch``
in batches of B with ``simulate_batch``; prints one JSON line: the seconds they took, their steps, and each
hunt's end.
"""

from __future__ import annotations

import dataclasses
import json
import sys
import time
from pathlib import Path

from mpc_hunt.arguments import CommandParser, count, run_command, seed
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.sweep.random_scenario import ScenarioRanges, sweep_scenario
from mpc_hunt.sweep.runner import hunt_rngs
from mpc_hunt.world.behaviours import with_behaviour

RANGES = ScenarioRanges(n_defenders=(3, 5))
MAX_HUNTS = 100_000
WARM_TIME_LIMIT = 5.0       # s of simulated time: the warm-up hunt, before the clock starts


def hunt(seed: int, index: int, time_limit: float | None = None):
    """Hunt ``index``: its scenario, controller and world generator, as the sweeps draw them."""
    scenario = with_behaviour(sweep_scenario(seed, index, RANGES), "gap")
    if time_limit is not None:
        scenario = dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, time_limit=time_limit))
    return scenario, ControllerSpec.parse("voronoi").build(scenario), hunt_rngs(seed, index)[0]


def run(mode: str, hunts: list, batch: int) -> list:
    if mode == "one":
        from mpc_hunt.sim.simulator import simulate

        return [simulate(s, c, rng=r) for s, c, r in hunts]
    from mpc_hunt.sim.batch import simulate_batch

    results = []
    for start in range(0, len(hunts), batch):
        part = hunts[start:start + batch]
        results += simulate_batch([h[0] for h in part], [h[1] for h in part], [h[2] for h in part])
    return results


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mode", choices=("one", "batch"), default="batch",
                        help="one by one (simulate) or in batches (simulate_batch; the default)")
    parser.add_argument("--seed", type=seed, default=0, help="the sweep's seed the hunts are drawn from (default 0)")
    parser.add_argument("--first", type=count(MAX_HUNTS), default=1, help="the first hunt, counted from 1 (default 1)")
    parser.add_argument("--count", type=count(MAX_HUNTS), default=1, help="how many hunts (default 1)")
    parser.add_argument("--batch", type=count(MAX_HUNTS), default=1, help="hunts a batch, batch mode (default 1)")
    args = parser.parse_args(argv)
    run(args.mode, [hunt(args.seed, args.first - 1, WARM_TIME_LIMIT)], args.batch)  # imports, caches, first calls
    hunts = [hunt(args.seed, i) for i in range(args.first - 1, args.first - 1 + args.count)]
    start = time.perf_counter()
    results = run(args.mode, hunts, args.batch)
    seconds = time.perf_counter() - start
    print(json.dumps({"seconds": seconds, "steps": sum(len(r.times) - 1 for r in results),
                      "ends": [[r.termination, r.capture_time] for r in results]}))
    return 0


if __name__ == "__main__":
    sys.exit(run_command(Path(sys.argv[0]).name, main))

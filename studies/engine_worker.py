"""One process of the engine study (``studies/engine.py``): hunts of the study timed in this process, once warm.

Run by the study with the engine under test first on the path (this tree's, or the engine before the batched one,
unpacked from git): ``python studies/engine_worker.py MODE SEED FIRST COUNT [BATCH]`` runs hunts FIRST ...
FIRST + COUNT − 1 of the study (``voronoi`` defenders, 3 to 5, against the ``gap`` attacker, the sweep's random
scenarios of SEED), MODE ``one`` one by one with ``simulate``, ``batch`` in batches of BATCH with
``simulate_batch``; prints one JSON line: the seconds they took, their steps, and each hunt's end.
"""

from __future__ import annotations

import dataclasses
import json
import sys
import time

from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.sweep.random_scenario import ScenarioRanges, sweep_scenario
from mpc_hunt.sweep.runner import hunt_rngs
from mpc_hunt.world.behaviours import with_behaviour

RANGES = ScenarioRanges(n_defenders=(3, 5))
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


def main(argv: list[str]) -> None:
    mode, seed, first, count = argv[0], int(argv[1]), int(argv[2]), int(argv[3])
    batch = int(argv[4]) if len(argv) > 4 else 1
    run(mode, [hunt(seed, first, WARM_TIME_LIMIT)], batch)           # imports, caches, first calls
    hunts = [hunt(seed, i) for i in range(first, first + count)]
    start = time.perf_counter()
    results = run(mode, hunts, batch)
    seconds = time.perf_counter() - start
    print(json.dumps({"seconds": seconds, "steps": sum(len(r.times) - 1 for r in results),
                      "ends": [[r.termination, r.capture_time] for r in results]}))


if __name__ == "__main__":
    main(sys.argv[1:])

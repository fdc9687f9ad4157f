"""One process of the engine study (``studies/engine.py``): hunts of the study timed in this process, once warm.

Run by the study with the engine under test first on the path (this tree's, or the engine before the batched one,
unpacked from git; so it imports nothing of ``studies``): ``python studies/engine_worker.py --mode M --seed S
--first F --count C --batch B --controller K`` runs C hunts of the study from the F-th (controller K, ``voronoi``
unless told, 3 to 5 defenders, against the ``gap`` attacker, the sweep's random scenarios of seed S), M ``one``
one by one with ``simulate``, ``batch`` in batches of B with ``simulate_batch``; prints one JSON line: the seconds
they took (once warm: the first ``WARM_TIME_LIMIT`` s of every hunt run before the clock starts, so a compiled
capture step is built), their steps, and each hunt's end. With ``--qps``, one by one: after each hunt (off its
clock), its capture-stage steps are solved again alone, back to back, each from the inputs and warm start it had
in the hunt, and only the step Function's evaluations are timed (``evaluation_time``: the linearisation and the
QP in CasADi's compiled code, no Python; what a batch solved in one call into compiled code would still run);
their seconds, their count, the largest difference of a plan solved alone from the hunt's, and the seconds the
same steps took in the hunts (their own records) are printed too; and the same steps solved once more, those of
one structure in one call into compiled code (:func:`in_one_call`), its seconds.
"""

from __future__ import annotations

import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

from mpc_hunt.arguments import CommandParser, count, run_command, seed
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.sweep.random_scenario import ScenarioRanges, sweep_scenario
from mpc_hunt.sweep.runner import hunt_rngs
from mpc_hunt.world.behaviours import with_behaviour

RANGES = ScenarioRanges(n_defenders=(3, 5))
MAX_HUNTS = 100_000
WARM_TIME_LIMIT = 5.0       # s of simulated time: each hunt's warm-up, before the clock starts


def hunt(seed: int, index: int, controller: str, time_limit: float | None = None):
    """Hunt ``index``: its scenario, controller and world generator, as the sweeps draw them."""
    scenario = with_behaviour(sweep_scenario(seed, index, RANGES), "gap")
    if time_limit is not None:
        scenario = dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, time_limit=time_limit))
    return scenario, ControllerSpec.parse(controller).build(scenario), hunt_rngs(seed, index)[0]


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


def with_qps_alone(hunts: list) -> tuple[list, float, float, int, float, dict | None]:
    """The hunts one by one, each hunt's capture steps then solved again alone: (results, the hunts' seconds, the
    steps' evaluations' seconds alone, how many, the largest difference between a plan solved alone and the hunt's,
    the same steps in one call a structure (:func:`in_one_call`: its seconds and the largest difference of its plans
    from those solved alone; None where a step is not one CasADi Function))."""
    from mpc_hunt.sim.simulator import simulate

    results, hunting, alone, solves, differ, together = [], 0.0, 0.0, 0, 0.0, {"seconds": 0.0, "difference": 0.0}
    for scenario, controller, rng in hunts:
        solver, posed = controller.mpc.solver, []

        def solve(problem, plan=None, duals=None, solve=solver.solve, posed=posed):
            solution = solve(problem, plan, duals)
            posed.append((problem, plan, solution.x))
            return solution

        solver.solve = solve
        start = time.perf_counter()
        results.append(simulate(scenario, controller, rng=rng))
        hunting += time.perf_counter() - start
        groups: dict = {}  # structure: (its step, the steps' inputs, their plans solved alone)
        for problem, plan, x in posed:
            step = solver.step_for(problem)
            step.load(problem, plan)
            step.step()
            alone += step.evaluation_time
            differ = max(differ, float(np.max(np.abs(step.plan.reshape(-1) - x))))
            group = groups.setdefault(problem.structure, (step, [], [], []))
            group[1].append(step.theta.copy()), group[2].append(step.reference.reshape(-1).copy())
            group[3].append(step.plan.reshape(-1).copy())
        solves += len(posed)
        for step, thetas, references, plans in groups.values():
            one_call = in_one_call(step, np.array(thetas), np.array(references))
            if one_call is None or together is None:
                together = None
                continue
            together["seconds"] += one_call[0]
            together["difference"] = max(together["difference"], float(np.max(np.abs(one_call[1] - plans))))
    return results, hunting, alone, solves, differ, together


def in_one_call(step, thetas: np.ndarray, references: np.ndarray) -> tuple[float, np.ndarray] | None:
    """The steps of one structure (``step``'s; their inputs a row each) solved in one call into compiled code:
    the step Function mapped over them (CasADi's ``map``, one after another in one call, no Python between
    them), as an engine solving a batch's QPs in one call would. (its seconds, the plans a row each); None where
    the step is not a CasADi Function."""
    import casadi as ca

    function = step.backend.loop_function(step.step_function)
    if not isinstance(function, ca.Function) or step.formulation.iteration.max_qps != 1:  # one evaluation a step
        return None
    mapped = function.map(len(thetas), "serial")
    buffer, evaluate = mapped.buffer()
    thetas, references = np.ascontiguousarray(thetas), np.ascontiguousarray(references)  # column-major (size, n)
    plans = np.empty_like(references)
    buffer.set_arg(0, thetas.data)
    buffer.set_arg(1, references.data)
    buffer.set_res(0, plans.data)
    start = time.perf_counter()
    evaluate()
    return time.perf_counter() - start, plans


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mode", choices=("one", "batch"), default="batch",
                        help="one by one (simulate) or in batches (simulate_batch; the default)")
    parser.add_argument("--seed", type=seed, default=0, help="the sweep's seed the hunts are drawn from (default 0)")
    parser.add_argument("--first", type=count(MAX_HUNTS), default=1, help="the first hunt, counted from 1 (default 1)")
    parser.add_argument("--count", type=count(MAX_HUNTS), default=1, help="how many hunts (default 1)")
    parser.add_argument("--batch", type=count(MAX_HUNTS), default=1, help="hunts a batch, batch mode (default 1)")
    parser.add_argument("--controller", default="voronoi", help="the defenders' controller (default voronoi)")
    parser.add_argument("--qps", action="store_true", help="time each hunt's capture steps again, alone")
    args = parser.parse_args(argv)
    indices = range(args.first - 1, args.first - 1 + args.count)
    run(args.mode, [hunt(args.seed, i, args.controller, WARM_TIME_LIMIT) for i in indices], args.batch)  # imports,
    hunts = [hunt(args.seed, i, args.controller) for i in indices]  # caches, first calls, each hunt's capture step
    out = {}
    if args.qps:
        results, seconds, alone, solves, differ, together = with_qps_alone(hunts)
        in_hunt = sum(float(np.sum(r.solve_times)) for r in results)
        out = {"qp_seconds": alone, "qps": solves, "replay_difference": differ, "qp_seconds_in_hunts": in_hunt,
               "one_call": together}
    else:
        start = time.perf_counter()
        results = run(args.mode, hunts, args.batch)
        seconds = time.perf_counter() - start
    print(json.dumps({"seconds": seconds, "steps": sum(len(r.times) - 1 for r in results),
                      "ends": [[r.termination, r.capture_time] for r in results], **out}))
    return 0


if __name__ == "__main__":
    sys.exit(run_command(Path(sys.argv[0]).name, main))

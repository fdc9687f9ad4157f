"""Compare formulations and backends: cold on the same problems, then each in its own loop under a deadline.

Two views of the same pairs, as ``mpc-hunt compare`` and ``mpc-hunt compare --mode own-loop`` give them:

1. **cold** (``run_compare``): every pair solves the same recorded capture-stage states from scratch, each plan
   scored by the one evaluator; per pair, how many solves succeeded, their times and their certificates;
2. **in its own loop** (``run_own_loop``): every pair drives the capture stage of a solving controller through
   the same hunt, from where the paper's strategy first reaches the capture stage, meeting the states its own
   plans lead to; per pair, capture, the step's times and the deadline misses.

Small sizes by default (a few problems, one hunt); ``--problems 0`` takes the whole shipped set.

    python examples/compare_pairs.py [--pair qp:daqp --pair rti:hpipm] [--horizon 5] [--deadline 0.02]
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np

from mpc_hunt import builtin_scenario
from mpc_hunt.bench import OwnLoopRun, builtin_problem_set, capture_stage_hunts, run_compare, run_own_loop


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pair", action="append", help="formulation:backend (repeatable)")
    parser.add_argument("--horizon", type=int, default=5)
    parser.add_argument("--problems", type=int, default=8, help="problems drawn from the shipped set (0: all)")
    parser.add_argument("--scenario", default="paper-open", help="the hunt of the own loops")
    parser.add_argument("--controller", default="enclose", help="the solving controller of the own loops")
    parser.add_argument("--deadline", type=float, default=0.02, help="the step's budget in seconds")
    args = parser.parse_args()
    pairs = [tuple(p.split(":", 1)) for p in (args.pair or ["qp:daqp", "rti:hpipm"])]

    problems = builtin_problem_set("default")
    if args.problems:
        problems = problems.select(limit=args.problems, rng=np.random.default_rng(0))
    cold = run_compare(problems, pairs, [args.horizon], ["cold"], np.random.default_rng(0), starts=1)
    print(f"cold, N = {args.horizon}, {len(problems.problems)} problems:")
    print("  pair           solved  median ms   max ms  largest primal / dual residual")
    for formulation, backend in pairs:
        mine = [r for r in cold.records if (r.formulation, r.backend) == (formulation, backend)]
        times = [r.solve_time * 1e3 for r in mine]
        primal = max((r.primal_residual for r in mine if r.primal_residual is not None), default=float("nan"))
        dual = max((r.dual_residual for r in mine if r.dual_residual is not None), default=float("nan"))
        print(
            f"  {formulation + ':' + backend:14s} {sum(r.success for r in mine):3d}/{len(mine):<3d}"
            f" {statistics.median(times):9.2f} {max(times):8.2f}  {primal:.1e} / {dual:.1e}"
        )

    hunts = capture_stage_hunts([builtin_scenario(args.scenario)], [], 0)
    own = run_own_loop(OwnLoopRun(hunts, pairs, [args.horizon], controller=args.controller, deadline=args.deadline))
    print(
        f"own loop, {args.controller} on {args.scenario} from its capture stage, deadline {args.deadline * 1e3:.0f} ms:"
    )
    print("  pair           captured  at s   steps  p95 ms   max ms  misses T / deadline  fallbacks")
    for hunt in own.hunts:
        r = hunt.result
        stats = r.solve_time_stats()
        misses = stats["deadline_misses"]
        print(
            f"  {hunt.formulation + ':' + hunt.backend:14s} {str(r.captured):8s} "
            f"{r.capture_time if r.captured else float('nan'):5.1f} {r.steps:7d} {stats['p95_s'] * 1e3:7.2f} "
            f"{stats['max_s'] * 1e3:8.2f}  {misses['over_time_step']:4d} / {misses['over_deadline']:<4d}"
            f"          {r.fallbacks}"
        )


if __name__ == "__main__":
    main()

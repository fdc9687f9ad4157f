"""Benchmarks of the capture stage: problem sets (shipped, built from closed-loop runs and random states) and
`compare`, which scores every formulation × backend on them, with the machine's description."""

from mpc_hunt.bench.build_problems import build_problem_set
from mpc_hunt.bench.compare import CompareRun, SolveRecord, run_compare
from mpc_hunt.bench.machine import describe_machine
from mpc_hunt.bench.own_loop import LoopHunt, OwnLoopRun, capture_stage_hunts, run_own_loop
from mpc_hunt.bench.problem_set import (
    ProblemSet,
    builtin_problem_set,
    load_problem_set,
    resolve_problem_set,
    save_problem_set,
)

__all__ = [
    "CompareRun",
    "LoopHunt",
    "OwnLoopRun",
    "ProblemSet",
    "SolveRecord",
    "build_problem_set",
    "builtin_problem_set",
    "capture_stage_hunts",
    "describe_machine",
    "load_problem_set",
    "resolve_problem_set",
    "run_compare",
    "run_own_loop",
    "save_problem_set",
]

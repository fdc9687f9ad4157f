"""Export the capture step to a robot's board as C, build it, and check it gives Python's plan.

``CaptureSolver.export(folder, problem, robot=i)`` writes the step of ``problem``'s structure as C sources, a
header, a Makefile and a program that reads a state's inputs (``input.txt``) and prints the plan; the folder also
holds the plan Python's step gives from the same inputs (``expected.txt``). Here the step is robot 1's of the
``distributed`` formulation (each defender its own small QP from the team's broadcast), whose default backend,
``daqp-condensed``, needs nothing beyond the folder: DAQP's own C sources are written into it. Where ``make`` and
a C compiler are found, the program is built for this machine and run, and its plan compared with Python's;
``--target aarch64-linux`` or ``--target cortex-m7`` writes a Makefile for an ARM core instead (built with its
cross compiler; see the export guide).

    python examples/export_to_board.py [--output robot1/] [--robot 1] [--horizon 10] [--cflags=-O1]
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from mpc_hunt import CaptureSolver
from mpc_hunt.bench import builtin_problem_set


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, help="the folder to write (default: a temporary one)")
    parser.add_argument("--scenario", default="paper-obstacles")
    parser.add_argument("--robot", type=int, default=1, help="whose step (0-based)")
    parser.add_argument("--horizon", type=int, default=10)
    parser.add_argument("--target", default="host")
    parser.add_argument("--cflags", help="the C compiler's flags, instead of the Makefile's (-O2)")
    args = parser.parse_args()

    problems = builtin_problem_set("default")
    entry = next(p for p in problems.tagged("default") if p.scenario == args.scenario)
    problem = problems.problem(entry, args.horizon, objective="enclose")  # distributed poses the enclose objective

    with tempfile.TemporaryDirectory() as scratch:
        folder = args.output or Path(scratch) / "board"
        solver = CaptureSolver("distributed")
        written = solver.export(folder, problem, robot=args.robot, target=args.target)
        print(f"wrote {len(written)} files to {folder}: " + ", ".join(sorted(p.name for p in written)[:8]) + ", ...")
        if args.target != "host" or shutil.which("make") is None or shutil.which("cc") is None:
            print("not built here (a cross target, or no make and C compiler)")
            return
        flags = [] if args.cflags is None else [f"CFLAGS={args.cflags}"]
        subprocess.run(["make", "-s", "-C", str(folder), *flags], check=True, capture_output=True)
        with open(folder / "input.txt") as stdin:
            run = subprocess.run(
                [str(folder / "capture_step")], stdin=stdin, capture_output=True, text=True, check=True
            )
        plan, expected = np.array(run.stdout.split(), dtype=float), np.loadtxt(folder / "expected.txt")
        print(
            f"built and run: {plan.size} numbers, largest difference from Python's plan "
            f"{np.abs(plan - expected.ravel()).max():.1e} m"
        )


if __name__ == "__main__":
    main()

"""The stage-form steps exported as C (``mpc-hunt export``), timed in pure C on the latency states.

For ``rti`` and ``stage-sqp``: the step exported for the first state's
structure, built with its Makefile at ``-O2`` (HPIPM and BLASFEO from CasADi's
wheel) and run on the latency states of that structure, each with the inputs
the reference Python run (``CaptureSolver`` on ``hpipm``, warm-started as the
controller does) used: the median time a step in C, and how far its plans are
from Python's.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from mpc_hunt.capture.export import export_step
from step_loop import reference_run

EXPORTED = ("rti", "stage-sqp")


def exported_c(problems: list) -> list[dict] | None:
    """One row per formulation of :data:`EXPORTED` over ``problems`` (consecutive states); None without make/gcc."""
    if shutil.which("make") is None or shutil.which("gcc") is None:
        return None
    rows = []
    for formulation in EXPORTED:
        steps, xs = reference_run(formulation, "hpipm", problems)
        inputs = [np.concatenate(step) for step, x in zip(steps, xs) if x is not None]
        plans = [x for x in xs if x is not None]
        with tempfile.TemporaryDirectory() as folder:
            export_step(problems[0], Path(folder), formulation)
            subprocess.run(["make", "-s", "-C", folder, "CFLAGS=-O2"], check=True, capture_output=True, timeout=1800)
            run = subprocess.run([f"{folder}/capture_step", "--time"], capture_output=True, text=True, timeout=600,
                                 input="\n".join(" ".join(f"{v:.17g}" for v in x) for x in inputs) + "\n")
        times = [float(line.split()[1]) for line in run.stderr.splitlines() if line.startswith("time_us")]
        out = np.array(run.stdout.split(), dtype=float)
        rows.append({"formulation": formulation, "states": len(inputs),
                     "median_step_ms": float(np.median(times[1:])) / 1e3,
                     "max_plan_difference_m": float(np.max(np.abs(out - np.concatenate(plans)))),
                     "exit": run.returncode})
        print(f"exported {formulation}: {rows[-1]['median_step_ms']:.3f} ms in C, plans within "
              f"{rows[-1]['max_plan_difference_m']:.1e} m", flush=True)
    return rows


def exported_lines(exported: list[dict] | None, rows: list[dict], baseline: tuple[str, str]) -> list[str]:
    """The README's paragraph: each exported step's time in C and its ratios to the latency table's steps."""
    if exported is None:
        return ["The exported C steps were not measured: no `make` or `gcc` here.", ""]
    by_pair = {(r["formulation"], r["backend"]): r for r in rows}
    lines = []
    for e in exported:
        f, c = e["formulation"], e["median_step_ms"]
        compared = ((f, "hpipm"), (f, "hpipm-codegen"), ("rti", "hpipm"), baseline)
        ratios = "; ".join(_compared(by_pair[p]["median_step_ms"] / c, "/".join(p))
                           for p in dict.fromkeys(compared) if p in by_pair)
        lines += [f"**The `{f}` step exported as C** (`mpc-hunt export --formulation {f}`, built with its Makefile "
                  f"at `-O2`, HPIPM and BLASFEO from CasADi's wheel), on the {e['states']} states of the first "
                  f"one's structure, each from the reference Python's `{f}`/`hpipm` run used: median {c:.3f} ms a "
                  f"step in pure C (the first excluded); {ratios}. Its plans differ from Python's by at most "
                  f"{e['max_plan_difference_m']:.1e} m (exit status {e['exit']}).", ""]
    return lines


def _compared(ratio: float, pair: str) -> str:
    return f"{ratio:.1f}× faster than `{pair}`'s step" if ratio >= 1 else f"{1 / ratio:.1f}× slower than `{pair}`'s step"

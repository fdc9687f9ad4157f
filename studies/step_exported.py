"""The stage-form steps exported as C (``mpc-hunt export``), timed in pure C on the latency states.

For ``rti`` and ``stage-sqp``, each in HPIPM's modes ``robust`` (the ``hpipm``
backend's) and ``balance`` (Cholesky factorisations): the step exported for the
first state's structure, built with its Makefile at ``-O2`` against HPIPM and
BLASFEO from CasADi's wheel (BLASFEO's generic target) and, given ``blasfeo``
(a folder holding a BLASFEO of the same version built for this CPU), against
that BLASFEO too; run on the latency states of that structure, each with the
inputs the reference Python run (a ``CaptureMPC`` on ``hpipm`` in the same
mode, the formulation's path, warm-started as the controller does) used: the median time a step in C,
and how far its plans are from Python's.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from mpc_hunt import CaptureSolver, markdown
from studies.step_loop import reference_run

EXPORTED = ("rti", "stage-sqp")
MODES = ("robust", "balance")


def exported_c(problems: list, blasfeo: Path | None = None) -> list[dict] | None:
    """One row per formulation of :data:`EXPORTED`, mode of :data:`MODES` and BLASFEO (the wheel's, then
    ``blasfeo`` if given) over ``problems`` (consecutive states); None without make/gcc."""
    if shutil.which("make") is None or shutil.which("gcc") is None:
        return None
    rows = []
    for formulation in EXPORTED:
        for mode in MODES:
            steps, xs = reference_run(formulation, "hpipm", problems, mode=mode)
            inputs = [np.concatenate(step) for step, x in zip(steps, xs) if x is not None]
            plans = np.concatenate([x for x in xs if x is not None])
            text = "\n".join(" ".join(f"{v:.17g}" for v in x) for x in inputs) + "\n"
            with tempfile.TemporaryDirectory() as folder:
                CaptureSolver(formulation, "hpipm", mode=mode).export(Path(folder), problems[0])
                for library in (None, blasfeo) if blasfeo else (None,):
                    rows.append(_timed(folder, text, plans, library) | {
                        "formulation": formulation, "mode": mode, "states": len(inputs),
                        "variant": f"HPIPM `{mode}`, BLASFEO {'of the wheel' if library is None else 'for this CPU'}"})
                    print(f"exported {formulation}, {rows[-1]['variant']}: {rows[-1]['median_step_ms']:.3f} ms in C, "
                          f"plans within {rows[-1]['max_plan_difference_m']:.1e} m", flush=True)
    return rows


def _timed(folder: str, text: str, plans: np.ndarray, blasfeo: Path | None) -> dict:
    """Build the exported step in ``folder`` (against ``blasfeo`` if given), run it on ``text``'s states."""
    subprocess.run(["make", "-s", "-B", "-C", folder, "CFLAGS=-O2", *([f"BLASFEO={blasfeo}"] if blasfeo else [])],
                   check=True, capture_output=True, timeout=1800)
    run = subprocess.run([f"{folder}/capture_step", "--time"], capture_output=True, text=True, timeout=600,
                         input=text)
    times = [float(line.split()[1]) for line in run.stderr.splitlines() if line.startswith("time_us")]
    out = np.array(run.stdout.split(), dtype=float)
    return {"median_step_ms": float(np.median(times[1:])) / 1e3,
            "max_plan_difference_m": float(np.max(np.abs(out - plans))), "exit": run.returncode}


def exported_lines(exported: list[dict] | None, rows: list[dict], baseline: tuple[str, str]) -> list[str]:
    """The README's paragraph: each exported step's time in C and its ratios to the latency table's steps."""
    if exported is None:
        return ["The exported C steps were not measured: no `make` or `gcc` here.", ""]
    by_pair = {(r["formulation"], r["backend"]): r for r in rows}
    first = exported[0]
    lines = [f"**The stage-form steps exported as C** (`mpc-hunt export --formulation F --hpipm-mode M`, built with "
             f"its Makefile at `-O2`; HPIPM from CasADi's wheel, BLASFEO the wheel's generic build or, with "
             f"`--blasfeo DIR`, one built for this CPU: `make BLASFEO=DIR`), on the {first['states']} states of the "
             "first one's structure, each from the reference Python run of the same formulation and mode on "
             "`hpipm`: median time a step in pure C (the first excluded), ratios to the latency table's steps, and "
             "the largest difference from Python's plans.", ""]
    rows = []
    for e in exported:
        f, c = e["formulation"], e["median_step_ms"]
        compared = ((f, "hpipm"), (f, "hpipm-codegen"), ("rti", "hpipm"), baseline)
        ratios = "; ".join(_compared(by_pair[p]["median_step_ms"] / c, "/".join(p))
                           for p in dict.fromkeys(compared) if p in by_pair)
        library = "the wheel's" if "wheel" in e["variant"] else "for this CPU"
        rows.append([f"`{f}`", f"`{e['mode']}`", library, f"{c:.3f}", ratios, f"{e['max_plan_difference_m']:.1e}",
                     e["exit"]])
    return lines + markdown.table(["exported step", "HPIPM mode", "BLASFEO", "median step (ms)",
                                   "speed-up over the step of", "plans within (m)", "exit"], "lllrlrr", rows) + [""]


def _compared(ratio: float, pair: str) -> str:
    return f"`{pair}` {ratio:.2g}×"

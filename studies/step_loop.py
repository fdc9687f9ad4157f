"""The control loop's step (``CaptureSolver.step_for``) timed on the latency states, beside the formulation's path.

For each stage-form pair, ``CaptureMPC(..., loop=False)`` (the formulation's
own path) runs the warm-started sequence as the latency table does; the inputs it
used at each state (θ and the reference) are kept. The pair's control-loop step
(:class:`~mpc_hunt.solving.step.CaptureStep`, from ``CaptureSolver.step_for``) then
takes the same states as a control loop would: the inputs written into its
arrays, one ``step()``, the plan read from its array. Its median time (the first
state excluded, as in the table) and the largest difference from the
formulation path's plans.
"""

from __future__ import annotations

import time

import numpy as np

from mpc_hunt import CaptureMPC, CaptureSolver, markdown
from mpc_hunt.solving import registry

LOOP_PAIRS = (("rti", "hpipm"), ("rti", "hpipm-codegen"), ("stage-sqp", "hpipm"), ("stage-sqp", "hpipm-codegen"))


def reference_run(formulation: str, backend: str, problems: list, **options) -> tuple[list, list]:
    """``CaptureMPC``'s run over ``problems`` on the formulation's own path (as the latency table's; ``options``
    are the backend's): at each state of the first one's structure, the step's inputs (θ, reference) and the
    solver's x (None where it gave none)."""
    stage = registry.formulation_class(formulation)()
    mpc, inputs, plans = CaptureMPC(formulation, backend, loop=False, **options), [], []
    for problem in problems:
        step = mpc.step(problem)
        if problem.structure == problems[0].structure:
            inputs.append(stage.step_inputs(problem, step.start))
            plans.append(step.solution.x)
    return inputs, plans


def loop_latency(problems: list) -> list[dict]:
    """One row per installed pair of :data:`LOOP_PAIRS` over the states of ``problems`` of the first one's
    structure."""
    rows = []
    for formulation, backend in LOOP_PAIRS:
        if (formulation, backend) not in registry.pairs():
            continue
        inputs, plans = reference_run(formulation, backend, problems)
        loop = CaptureSolver(formulation, backend).step_for(problems[0])
        times, differences = [], []
        for (theta, reference), expected in zip(inputs, plans):
            start = time.perf_counter()
            loop.theta[:] = theta
            loop.reference.reshape(-1)[:] = reference
            status = loop.step()
            times.append(time.perf_counter() - start)
            if status.usable and expected is not None:
                differences.append(float(np.max(np.abs(loop.plan.reshape(-1) - expected[:loop.plan.size]))))
        rows.append({"formulation": formulation, "backend": backend, "median_step_ms": float(np.median(times[1:])) * 1e3,
                     "compared": len(differences), "max_plan_difference_m": max(differences, default=float("nan"))})
        print(f"loop {formulation}/{backend}: {rows[-1]['median_step_ms']:.3f} ms, plans within "
              f"{rows[-1]['max_plan_difference_m']:.1e} m", flush=True)
    return rows


def loop_lines(loop: list[dict], rows: list[dict]) -> list[str]:
    """The README's section: the loop's table, with each row's ratio to the interpreted ``rti`` step."""
    by_pair = {(r["formulation"], r["backend"]): r for r in rows}
    interpreted = by_pair.get(("rti", "hpipm"))
    lines = ["## The control loop's step (`CaptureStep`)", "",
             "The same states through `mpc_hunt.solving.step.CaptureStep`: the inputs `CaptureSolver` used written "
             "into the loop's arrays, one `step()`, the plan read from its array; no problem posed, no evaluator, "
             "no solution object. *× rti/hpipm*: the interpreted `rti`/`hpipm` step of the latency table (state in "
             "→ plan out, evaluator excluded) over this row's step; *same pair*: this pair's step in the latency "
             "table over this row's.", ""]

    def ratio(base: dict | None, r: dict) -> str:
        return "–" if base is None else f"{base['median_step_ms'] / r['median_step_ms']:.1f}"

    return lines + markdown.table(
        ["formulation", "backend", "loop step (ms)", "× rti/hpipm", "× same pair", "plans differ by at most (m)"],
        "llrrrr", ([r["formulation"], r["backend"], f"{r['median_step_ms']:.3f}", ratio(interpreted, r),
                    ratio(by_pair.get((r["formulation"], r["backend"])), r), f"{r['max_plan_difference_m']:.1e}"]
                   for r in loop)) + [""]


COMPILED_RATIO, EXPORTED_RATIO, SQP_RATIO = 10.0, 20.0, 20.0     # the compiled step's targets
PLAN_TOLERANCE = 1e-9     # an exported step counts for a target when its plans are Python's to this (m)


def fastest_exported(exported: list[dict] | None, formulation: str) -> dict | None:
    """The fastest exported build of ``formulation`` whose plans are Python's to :data:`PLAN_TOLERANCE`."""
    rows = [e for e in exported or [] if e["formulation"] == formulation
            and e["max_plan_difference_m"] <= PLAN_TOLERANCE]
    return min(rows, key=lambda e: e["median_step_ms"], default=None)


def loop_targets(loop: list[dict], rows: list[dict], exported: list[dict] | None) -> list[str]:
    """The compiled step's targets against this run (ratios to the interpreted ``rti``/``hpipm`` step and to
    ``nlp``/``ipopt`` in the latency table), met or missed by how much."""
    by_pair = {(r["formulation"], r["backend"]): r for r in rows}
    in_loop = {(r["formulation"], r["backend"]): r for r in loop}
    rti, nlp = by_pair.get(("rti", "hpipm")), by_pair.get(("nlp", "ipopt"))
    lines = []

    def verdict(ratio: float, target: float) -> str:
        return "met" if ratio >= target else f"missed by {target / ratio:.1f}×"

    if rti is not None:
        for what, source in (("`CaptureSolver`", by_pair), ("`CaptureStep`", in_loop)):
            if ("rti", "hpipm-codegen") in source:
                ratio = rti["median_step_ms"] / source[("rti", "hpipm-codegen")]["median_step_ms"]
                lines.append(f"- **Compiled `rti` step from Python ≥ {COMPILED_RATIO:.0f}× faster than the "
                             f"interpreted one** (through {what}): {ratio:.1f}×, {verdict(ratio, COMPILED_RATIO)}.")
        c = fastest_exported(exported, "rti")
        if c is not None:
            ratio = rti["median_step_ms"] / c["median_step_ms"]
            lines.append(f"- **Exported C `rti` step ≥ {EXPORTED_RATIO:.0f}× faster than the interpreted one** "
                         f"(its fastest build, {c['variant']}): {ratio:.1f}×, {verdict(ratio, EXPORTED_RATIO)}.")
    c = fastest_exported(exported, "stage-sqp")
    sqp = {"`CaptureStep`": in_loop.get(("stage-sqp", "hpipm-codegen")),
           f"the exported C, {c['variant'] if c else ''}": c}
    for what, row in sqp.items():
        if nlp is not None and row is not None:
            ratio = nlp["median_step_ms"] / row["median_step_ms"]
            lines.append(f"- **Compiled stage SQP ≥ {SQP_RATIO:.0f}× faster than `nlp`/`ipopt`** (through {what}): "
                         f"{ratio:.1f}×, {verdict(ratio, SQP_RATIO)}.")
    if lines:
        lines.append("  Where the time goes: HPIPM through CasADi is most of every compiled step (the profile "
                     "above); the compiled linearisation and the loop's calls leave it as the floor.")
    return lines

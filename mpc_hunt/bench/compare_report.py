"""A compare run written out: a terminal table, JSON, CSV and the Markdown report's text."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

from mpc_hunt import markdown
from mpc_hunt.bench.compare import CompareRun
from mpc_hunt.bench.compare_rows import best_known, gap
from mpc_hunt.bench.machine import machine_lines
from mpc_hunt.capture.evaluator import ENCLOSE_OBJECTIVE, OBJECTIVE, VIOLATION_NAMES
from mpc_hunt.markdown import Column, figure
from mpc_hunt.solving.accuracy import accuracy_table


def settings(run: CompareRun, **extra) -> dict:
    """What was run: the problems (ids, in order), pairs, horizons, modes, accuracy and the caller's extras."""
    return {
        "problems": [p.id for p in run.problem_set.problems],
        "pairs": [f"{f}:{b}" for f, b in run.pairs],
        "horizons": run.horizons,
        "modes": run.modes,
        "objective": run.objective,
        "accuracy": run.accuracy,
        "violation_tolerance_m": run.tolerance,
        "time_limit_s": run.time_limit,
        "reference_starts": run.starts,
        **extra,
    }


def document(run: CompareRun, machine: dict, rows: list[dict], extra: dict, solves: bool = False) -> dict:
    """The JSON object: ``machine``, ``settings``, ``interrupted``, ``rows`` (and, if asked, the best known
    objectives and every solve with its gap)."""
    out = {"machine": machine, "settings": settings(run, **extra), "interrupted": run.interrupted, "rows": rows}
    if solves:
        best = best_known(run)
        out["best_known"] = [{"problem": p, "horizon": n, "objective": v} for (p, n), v in best.items()]
        out["solves"] = [{**r.to_dict(), "gap": gap(r, best)} for r in run.records]
    return out


def _clean(value):
    """JSON has no inf or NaN: None instead."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_clean(v) for v in value]
    return value


def dumps(doc: dict) -> str:
    return json.dumps(_clean(doc))


def write_csv(rows: list[dict], path: Path) -> None:
    with open(path, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]) if rows else ["formulation"])
        writer.writeheader()
        writer.writerows(rows)


COLUMNS = (
    Column("pair", lambda r: f"{r['formulation']}/{r['backend']}", "l"),
    Column("mode", figure("mode"), "l"),
    Column("N", figure("horizon")),
    Column("accuracy", figure("accuracy")),
    Column("solves", figure("solves")),
    Column("success", figure("success_rate", ".0%")),
    Column("median ms", figure("solve_time_median_s", ".2f", 1e3)),
    Column("p95 ms", figure("solve_time_p95_s", ".2f", 1e3)),
    Column("sgm ms", figure("solve_time_shifted_geomean_s", ".2f", 1e3)),
    Column("solver ms", figure("solver_time_median_s", ".2f", 1e3)),
    Column("ours ms", figure("overhead_time_median_s", ".2f", 1e3)),
    Column("warm ×", figure("warm_speedup", ".2f")),
    Column("iters", figure("iterations_median", "g")),
    Column("gap med", figure("optimality_gap_median", ".2g")),
    Column("gap p95", figure("optimality_gap_p95", ".2g")),
    Column("max viol m", figure("max_violation", ".1e")),
    Column("max dual res", figure("max_dual_residual", ".1e")),
    Column("max gap", figure("max_duality_gap", ".1e")),
)


def table(rows: list[dict]) -> str:
    """The rows as a plain-text table for the terminal."""
    return markdown.columns_plain(COLUMNS, rows)


def markdown_table(rows: list[dict]) -> list[str]:
    return markdown.columns_table(COLUMNS, rows)


def violation_table(rows: list[dict]) -> list[str]:
    return markdown.table(
        ["pair", "mode", "N", "statuses", *VIOLATION_NAMES],
        "llrl" + "r" * len(VIOLATION_NAMES),
        (
            [
                f"{r['formulation']}/{r['backend']}",
                r["mode"],
                r["horizon"],
                r["statuses"],
                *(figure(f"max_violation_{n}", ".1e")(r) for n in VIOLATION_NAMES),
            ]
            for r in rows
        ),
    )


def unsolved(run: CompareRun) -> list[str]:
    """Problems no pair solved (by the success rule), per horizon and mode."""
    lines = []
    for horizon in run.horizons:
        for mode in run.modes:
            seen: dict[str, bool] = {}
            for r in run.records:
                if r.horizon == horizon and r.mode == mode:
                    seen[r.problem] = seen.get(r.problem, False) or r.success
            none = [p for p, ok in seen.items() if not ok]
            if none:
                lines.append(f"- N = {horizon}, {mode}: {', '.join(none)}")
    return lines


def readme(run: CompareRun, machine: dict, rows: list[dict], command: str, figures: list[Path]) -> str:
    """The report's ``README.md``: what was run, the score, the results and the ``figures`` (beside it)."""
    sequences = run.problem_set.sequences()
    text = [
        "# Capture-stage formulations × backends, scored on the true problem",
        "",
        f"Regenerate with `{command}`. Every figure below comes from that one run"
        + (" (**interrupted**: only the solves finished are scored)." if run.interrupted else "."),
        "",
        "## Machine",
        "",
        *machine_lines(machine),
        "",
        "## What was run",
        "",
        f"- Problems: {len(run.problem_set.problems)} ({len(sequences)} sequences of consecutive states, "
        f"{sum(map(len, sequences.values()))} states, for the replayed mode); "
        f"{run.problem_set.description}",
        f"- Pairs: {', '.join(f'{f}/{b}' for f, b in run.pairs)}",
        f"- Horizons: {', '.join(map(str, run.horizons))}; modes: {', '.join(run.modes)}",
        f"- Accuracy `{run.accuracy}`: a solve succeeds with a success status and every true violation "
        f"≤ {run.tolerance:g} m; time limit: {'none' if run.time_limit is None else f'{run.time_limit:g} s'}; "
        f"reference: multi-start NLP, {run.starts} starts",
        "",
        "## The score",
        "",
        f"Every plan is scored by the evaluator (`mpc_hunt/capture/evaluator.py`), on the "
        f"objective it was planned for (`{run.objective}`):",
        "",
        "```",
        ENCLOSE_OBJECTIVE if run.objective == "enclose" else OBJECTIVE,
        "```",
        "",
        "Accuracy levels:",
        "",
        accuracy_table(),
        "",
        "Metrics: see docs/benchmarks.md in the repository. Times are all-in, per solve "
        "(the state handed over to the plan returned), set-up apart; `sgm` is the shifted geometric mean "
        "(shift 10 ms); `solver`: inside the solver; `ours`: our overhead.",
        "",
        "## Results",
        "",
        *markdown_table(rows),
        "",
        "Largest true violation of each family (m), and the solvers' statuses:",
        "",
        *violation_table(rows),
        "",
    ]
    missing = unsolved(run)
    if missing:
        text += ["Problems that no pair solved by the success rule:", "", *missing, ""]
    text += ["## Figures", ""] + [f"![{f.name}]({f.name})" for f in figures] + [""]
    return "\n".join(text)

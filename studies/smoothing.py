"""What rounding the field's kink (docs/model.md, E11) does to the NLP's solves, measured side by side.

The states are those at which the paper's strategy (one-step ``nlp`` on
IPOPT) posed a capture problem in its closed-loop run of each paper scenario:
every one for N = 1, every tenth for N = 10. Defenders enter the capture stage
at |r| = R_agg, on the kink. Each is solved cold (from every defender held) by
``nlp`` (the paper's field) and by ``ms-nlp`` (multiple shooting) with the
band half-width w = 0 (the paper's field), 1, 3 and 10 mm, on IPOPT. Reported:
failed solves, iterations and solve time (medians), and how much worse each
plan is than ``nlp``'s under the paper's field (the evaluator's objective,
median and worst relative gap, where both succeeded).

    python studies/smoothing.py [--output studies/smoothing]
"""

from __future__ import annotations

import json
import platform
import sys
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt.arguments import CommandParser, output_folder
from mpc_hunt import CaptureProblem, CaptureSolver, builtin_scenario, markdown, simulate
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.world.attacker import perceives
from studies.study_check import run_study

SCENARIOS = ("paper-open", "paper-obstacles")
WIDTHS = (0.0, 0.001, 0.003, 0.01)
HORIZONS = {1: 1, 10: 10}    # horizon: stride through the states


def capture_states(scenario) -> list:
    """Every observation of the paper strategy's closed-loop run at which a defender is in the capture stage."""
    found = []

    def until(obs) -> bool:
        if perceives(scenario, obs.attacker, obs.defenders).any():
            found.append(obs)
        return False

    simulate(scenario, until=until)
    return found


def solve_all(states, scenario, horizon: int, formulation: str, smoothing: float | None) -> list:
    """Each state solved cold; one Solution per state."""
    solver = CaptureSolver(formulation, "ipopt")
    if smoothing is not None:
        solver.formulation.smoothing = smoothing
    return [solver.solve(CaptureProblem.at_state(scenario, s.attacker, s.defenders, horizon)) for s in states]


def summary(solutions, reference) -> dict:
    gaps = np.array([(s.objective - r.objective) / abs(r.objective) for s, r in zip(solutions, reference)
                     if s.success and r.success])
    return {"failed": sum(not s.success for s in solutions), "solves": len(solutions),
            "median_iterations": float(np.median([s.iterations for s in solutions])),
            "median_solve_ms": float(np.median([s.solve_time for s in solutions]) * 1e3),
            "median_gap": float(np.median(gaps)), "worst_gap": float(np.max(gaps)),
            "max_violation": float(max(s.max_violation for s in solutions))}


def run() -> list[dict]:
    rows = []
    for name in SCENARIOS:
        scenario = builtin_scenario(name)
        every = capture_states(scenario)
        for horizon, stride in HORIZONS.items():
            states = every[::stride]
            reference = solve_all(states, scenario, horizon, "nlp", None)
            rows.append({"scenario": name, "horizon": horizon, "formulation": "nlp", "smoothing_m": None,
                         **summary(reference, reference)})
            print(rows[-1], flush=True)
            for width in WIDTHS:
                solutions = solve_all(states, scenario, horizon, "ms-nlp", width)
                rows.append({"scenario": name, "horizon": horizon, "formulation": "ms-nlp", "smoothing_m": width,
                             **summary(solutions, reference)})
                print(rows[-1], flush=True)
    return rows


def table(rows: list[dict]) -> str:
    return "\n".join(markdown.table(
        ["scenario", "N", "formulation", "w (mm)", "failed / solves", "median iterations", "median solve (ms)",
         "objective gap to nlp, median", "worst", "max violation (m)"], "lrlrrrrrrr",
        ([r["scenario"], r["horizon"], r["formulation"],
          "–" if r["smoothing_m"] is None else f"{r['smoothing_m'] * 1e3:g}", f"{r['failed']} / {r['solves']}",
          f"{r['median_iterations']:.0f}", f"{r['median_solve_ms']:.1f}", f"{100 * r['median_gap']:+.3f} %",
          f"{100 * r['worst_gap']:+.3f} %", f"{r['max_violation']:.1e}"] for r in rows)))


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=output_folder, default=Path(__file__).parent / "smoothing")
    args = parser.parse_args(argv)
    with stop_at_once("smoothing study"):        # Ctrl-C: at once, nothing written
        rows = run()
    args.output.mkdir(parents=True, exist_ok=True)
    (args.output / "results.json").write_text(json.dumps(rows, indent=1) + "\n")
    text = ["# Rounding the field's kink: effect on the NLP's solves", "",
            "Regenerate with `python studies/smoothing.py`. Measured in one run on "
            f"{platform.machine()}, Python {platform.python_version()}; times are per solve (solver and our "
            "overhead, the evaluator included), each solved cold. A failed solve is any status "
            "but optimal. The gap compares the evaluator's objective (the paper's field) with `nlp`'s plan at the "
            "same state; the violation is the largest of any constraint family, against the paper's field.", "",
            table(rows), ""]
    (args.output / "README.md").write_text("\n".join(text))
    print(f"wrote {args.output / 'README.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

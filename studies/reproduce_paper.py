"""Reproduce the paper's two simulations (Figs. 7–8), with and without trajectory prediction.

Runs the built-in scenarios ``paper-open`` and ``paper-obstacles`` as shipped
(no parameter is tuned here), and writes into the output folder the four
trajectory figures, ``results.json`` (each run's report) and ``README.md``
setting our numbers beside the published ones, with the paper's claims checked
against them.

    python studies/reproduce_paper.py [--out studies/reproduction]
    python studies/reproduce_paper.py --check    # fail if the committed results no longer match the code
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mpc_hunt import HuntResult, builtin_scenario, simulate
from mpc_hunt.plotting import plot_hunt

DEFAULT_OUT = Path(__file__).resolve().parent / "reproduction"
SCENARIOS = ("paper-open", "paper-obstacles")
TOLERANCE = 0.15    # claim (c): every path length within this fraction of the paper's
# What --check compares: every figure the README quotes (timings aside), to this relative tolerance.
CHECKED = ("captured", "termination", "capture_time_s", "path_lengths_m", "final_hunting_radius_m",
           "min_obstacle_clearance_m", "min_defender_separation_m", "steps", "failed_solves", "fallbacks")
CHECK_RTOL = 1e-6


@dataclass(frozen=True)
class Published:
    """One run's numbers as printed in the paper (Section V)."""

    figure: str
    final_hunting_radius: float
    path_lengths: tuple[float, ...]


PAPER = {
    ("paper-open", True): Published("Fig. 7(a)", 0.25, (10.61, 11.46, 12.82)),
    ("paper-open", False): Published("Fig. 7(b)", 0.25, (11.73, 12.93, 14.43)),
    ("paper-obstacles", True): Published("Fig. 8(a)", 0.41, (10.75, 11.57, 13.58)),
    ("paper-obstacles", False): Published("Fig. 8(b)", 0.41, (10.66, 11.64, 13.74)),
}


def run_name(scenario: str, prediction: bool) -> str:
    return f"{scenario}-{'prediction' if prediction else 'no-prediction'}"


def relative(ours: float, paper: float) -> float:
    """Signed relative difference to the paper, in %."""
    return 100.0 * (ours - paper) / paper


def metres(x: float | None) -> str:
    return "–" if x is None else f"{x:.2f} m"


def path_table(runs: dict[tuple[str, bool], HuntResult]) -> list[str]:
    lines = ["| run | paper | robot | ours (m) | paper (m) | difference |",
             "| --- | --- | --- | ---: | ---: | ---: |"]
    for key, result in runs.items():
        paper = PAPER[key]
        for i, (ours, theirs) in enumerate(zip(result.path_lengths, paper.path_lengths)):
            lines.append(f"| {run_name(*key)} | {paper.figure} | {i + 1} | {ours:.2f} | {theirs:.2f} "
                         f"| {relative(ours, theirs):+.1f} % |")
    return lines


def run_table(runs: dict[tuple[str, bool], HuntResult]) -> list[str]:
    lines = ["| run | final hunting radius, ours | paper | captured | capture time | "
             "min obstacle clearance | capture-stage fallbacks |",
             "| --- | ---: | ---: | --- | ---: | ---: | ---: |"]
    for key, r in runs.items():
        capture_time = "–" if r.capture_time is None else f"{r.capture_time:.1f} s"
        lines.append(f"| {run_name(*key)} | {metres(r.final_hunting_radius)} "
                     f"| {metres(PAPER[key].final_hunting_radius)} | {'yes' if r.captured else 'no'} "
                     f"| {capture_time} | {metres(r.min_obstacle_clearance)} | {r.fallbacks} |")
    return lines


def claims(runs: dict[tuple[str, bool], HuntResult]) -> list[str]:
    """The paper's claims, each decided from the numbers above."""
    lines = ["## Claims", ""]
    with_p, without_p = runs[("paper-open", True)], runs[("paper-open", False)]
    shorter = with_p.path_lengths < without_p.path_lengths
    per_robot = ", ".join(f"robot {i + 1}: {'yes' if s else 'no'} ({a:.2f} vs {b:.2f} m)"
                          for i, (s, a, b) in enumerate(zip(shorter, with_p.path_lengths,
                                                            without_p.path_lengths)))
    lines.append(f"- (a) Prediction shortens every defender's path in the open area: "
                 f"**{'yes' if shorter.all() else 'no'}** — {per_robot}.")
    safe = {run_name(*key): r.captured and r.min_obstacle_clearance is not None
            and r.min_obstacle_clearance > 0
            for key, r in runs.items() if key[0] == "paper-obstacles"}
    detail = ", ".join(f"{name}: {'yes' if ok else 'no'}" for name, ok in safe.items())
    lines.append(f"- (b) Capture without collision among obstacles (captured and min obstacle clearance "
                 f"> 0): **{'yes' if all(safe.values()) else 'no'}** — {detail}.")
    outside = [f"{run_name(*key)} robot {i + 1} ({relative(ours, theirs):+.1f} %)"
               for key, r in runs.items()
               for i, (ours, theirs) in enumerate(zip(r.path_lengths, PAPER[key].path_lengths))
               if abs(ours - theirs) > TOLERANCE * theirs]
    lines.append(f"- (c) Every path length within {TOLERANCE:.0%} of the paper: "
                 f"**{'no' if outside else 'yes'}**"
                 + (f" — outside: {', '.join(outside)}." if outside else "."))
    return lines


def differences(runs: dict[tuple[str, bool], HuntResult]) -> list[str]:
    """Where the time goes: all defenders in the capture stage, then captured."""
    lines = ["## Where we differ, and why", "",
             "- **Final hunting radius.** Ours is the radius when the success test has held for "
             "`hold_time` (2 s); the circle is then still contracting towards R_hunt / 2. The paper "
             "does not say when its 0.25 m and 0.41 m were measured.",
             "- **Herding before contraction.** Capture-stage defenders stay near the edge of their field "
             "(|r_ai| ≈ R_agg) until the herding has brought the attacker to the centre of the circle, and "
             "only then contract (docs/model.md, E5 and E9). How long that takes depends on the directions "
             "the defenders arrive from:"]
    for key, result in runs.items():
        all_in = np.flatnonzero(result.capture_stage.all(axis=1))
        start = f"{result.times[all_in[0]]:.1f} s" if len(all_in) else "never"
        end = f"{result.capture_time:.1f} s" if result.captured else "not captured"
        lines.append(f"  - {run_name(*key)}: every defender in the capture stage at {start}; captured at {end}.")
    lines.append("- **Obstacles on the straight route.** From [15, 15], defender 2's straight route to the "
                 "attacker crosses the obstacle at [7, 12]; its field turns the defender around it inside the "
                 "protective distance, which is the largest single difference from the paper's path lengths.")
    return lines


def readme(runs: dict[tuple[str, bool], HuntResult], command: str, seconds: float) -> str:
    figures = [f"![{run_name(*key)}]({run_name(*key)}.png)" for key in runs]
    return "\n".join([
        "# Reproduction of the paper's simulations", "",
        f"Regenerate this folder with `{command}` (from the repository root; about {seconds:.0f} s).", "",
        "The built-in scenarios `paper-open` (Fig. 7) and `paper-obstacles` (Fig. 8), as shipped, each "
        "run with and without trajectory prediction. No parameter is tuned for this study; the "
        "published numbers are those printed in the paper. Every run's full report is in "
        "`results.json`.", "",
        "## Path lengths", "", *path_table(runs), "",
        "## Runs", "", *run_table(runs), "",
        "The paper gives no capture times or clearances; a capture-stage fallback is a step whose "
        "solve failed and whose command came from the strategy's fallback.", "",
        *claims(runs), "",
        *differences(runs), "",
        "## Figures", "", *figures, "",
    ])


def run_all(out: Path | None) -> tuple[dict[tuple[str, bool], HuntResult], float]:
    """Every run of the study; figures written into ``out`` if given."""
    start = time.perf_counter()
    runs: dict[tuple[str, bool], HuntResult] = {}
    for name in SCENARIOS:
        scenario = builtin_scenario(name)
        for prediction in (True, False):
            result = simulate(scenario, prediction=prediction)
            runs[(name, prediction)] = result
            if out is not None:
                plot_hunt(result, scenario, out / f"{run_name(name, prediction)}.png")
            print(f"{run_name(name, prediction)}: captured={result.captured}, "
                  f"path lengths {', '.join(f'{x:.2f}' for x in result.path_lengths)} m", flush=True)
    return runs, time.perf_counter() - start


def _close(a, b) -> bool:
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(map(_close, a, b))
    if isinstance(a, float) and isinstance(b, float):
        return math.isclose(a, b, rel_tol=CHECK_RTOL)
    return a == b


def differing(committed: dict, report: dict) -> list[str]:
    """The checked figures that differ between the committed results and a new run."""
    return [f"{run}.{key}: committed {committed.get(run, {}).get(key)}, now {new[key]}"
            for run, new in report.items() for key in CHECKED
            if not _close(committed.get(run, {}).get(key), new[key])]


def _without_timing(text: str) -> str:
    return re.sub(r"about \d+ s", "about N s", text)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT,
                        help="output folder (default: studies/reproduction/ beside this script)")
    parser.add_argument("--check", action="store_true",
                        help="rerun and compare with the committed results.json and README.md; write nothing")
    args = parser.parse_args(argv)
    command = "python studies/reproduce_paper.py"
    if args.out.resolve() != DEFAULT_OUT:
        command += f" --out {args.out}"
    if args.check:
        runs, seconds = run_all(None)
        report = {run_name(*key): r.to_dict() for key, r in runs.items()}
        problems = differing(json.loads((args.out / "results.json").read_text()), report)
        if not problems and _without_timing((args.out / "README.md").read_text()) \
                != _without_timing(readme(runs, command, seconds)):
            problems.append("README.md: text differs")
        for line in problems:
            print(f"differs: {line}", file=sys.stderr)
        print(f"{args.out}: {'up to date' if not problems else f'{len(problems)} differences; rerun {command}'}")
        return 1 if problems else 0
    args.out.mkdir(parents=True, exist_ok=True)
    runs, seconds = run_all(args.out)
    report = {run_name(*key): r.to_dict() for key, r in runs.items()}
    (args.out / "results.json").write_text(json.dumps(report, indent=2) + "\n")
    (args.out / "README.md").write_text(readme(runs, command, seconds))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

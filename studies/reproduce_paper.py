"""Reproduce the paper's two simulations (Figs. 7–8), with and without trajectory prediction.

Runs the built-in scenarios ``paper-open`` and ``paper-obstacles`` as shipped
(no parameter is tuned here), each also as an ensemble: the same run with every
robot's start moved by at most 1e-9 m (:mod:`mpc_hunt.world.ensemble`), and the
nominal runs once more under every OpenBLAS kernel family the CPU can run. It
writes into the output folder the four trajectory figures (nominal runs),
``results.json`` (each run's report, its ensemble's band per figure, and what
the ensemble shows robust) and ``README.md`` setting our numbers (median and
range) beside the published ones, with the paper's claims decided from them.

    python studies/reproduce_paper.py [--output studies/reproduction]
    python studies/reproduce_paper.py --check    # rerun the nominal runs: each robust outcome as committed,
                                                 # each figure inside its committed band; README.md is results.json's
    python studies/reproduce_paper.py --nominal  # print the nominal runs' reports as JSON (nothing written)
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt.arguments import CommandParser, output_folder
from mpc_hunt import builtin_scenario, markdown, simulate
from mpc_hunt.world.ensemble import SCALE, band, outside_band, perturbed, widened
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.bench.machine import blas_kernel_families
from mpc_hunt.plots.hunt import plot_hunt

from studies.study_check import check_result, read_json_file, run_study

DEFAULT_OUT = Path(__file__).resolve().parent / "reproduction"
SCENARIOS = ("paper-open", "paper-obstacles")
TOLERANCE = 0.15    # claim (c): every path length within this fraction of the paper's
MEMBERS = 12        # perturbed reruns of each run, beside the nominal one
# What the ensemble bands: every figure the README quotes (timings aside).
BANDED = ("capture_time_s", "path_lengths_m", "final_hunting_radius_m", "min_obstacle_clearance_m",
          "min_defender_separation_m", "steps", "failed_solves", "fallbacks")
ROBUST = ("captured", "termination", "collision_free")    # kept exact by --check where every member agrees
# --check: a rerun's figure must lie in its band widened by half its width on each side, at least by this
# fraction of the median (a band of one value: the figure to 1e-6, as before the ensemble).
WIDEN, FLOOR_RTOL, FLOOR_ATOL = 0.5, 1e-6, 1e-9
COMMAND = "python studies/reproduce_paper.py"


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


KEYS = [(name, prediction) for name in SCENARIOS for prediction in (True, False)]


def relative(ours: float, paper: float) -> float:
    """Signed relative difference to the paper, in %."""
    return 100.0 * (ours - paper) / paper


def spread(b: dict | None, digits: int = 2, unit: str = " m") -> str:
    """A band as the README shows it: the median, then the range when the members differ at that precision."""
    if b is None:
        return "–"
    low, mid, high = (f"{b[k]:.{digits}f}" for k in ("min", "median", "max"))
    return f"{mid}{unit}" if low == high else f"{mid}{unit} ({low}–{high})"


def within(b: dict, paper: float) -> str:
    """Claim (c) on a band: every member within the tolerance, none, or some."""
    inside = [abs(b[k] - paper) <= TOLERANCE * paper for k in ("min", "max")]
    return "yes" if all(inside) else ("no" if not any(inside) and (b["min"] - paper) * (b["max"] - paper) > 0
                                      else "in part")


def path_table(runs: dict) -> list[str]:
    rows = []
    for key in KEYS:
        paper, bands = PAPER[key], runs[run_name(*key)]["band"]["path_lengths_m"]
        rows += [[run_name(*key), paper.figure, i + 1, spread(b), f"{theirs:.2f} m",
                  f"{relative(b['median'], theirs):+.1f} %", within(b, theirs)]
                 for i, (b, theirs) in enumerate(zip(bands, paper.path_lengths))]
    return markdown.table(["run", "paper", "robot", "ours, median (range)", "paper", "difference of the median",
                           f"within {TOLERANCE:.0%}"], "lllrrrl", rows)


def run_table(runs: dict) -> list[str]:
    rows = []
    for key in KEYS:
        run = runs[run_name(*key)]
        b, captured = run["band"], run["robust"]["captured"]
        rows.append([run_name(*key), spread(b["final_hunting_radius_m"], 3), f"{PAPER[key].final_hunting_radius:.2f} m",
                     "every member" if captured else "no member" if captured is False else "some members",
                     spread(b["capture_time_s"], 1, " s"), spread(b["min_obstacle_clearance_m"]),
                     spread(b["fallbacks"], 0, "")])
    return markdown.table(["run", "final hunting radius, ours", "paper", "captured", "capture time",
                           "min obstacle clearance", "capture-stage fallbacks"], "lrrlrrr", rows)


def claims(runs: dict) -> list[str]:
    """The paper's claims, each decided from the ensembles above (for every member, not only the nominal run)."""
    lines = ["## Claims", ""]
    with_p = runs[run_name("paper-open", True)]["band"]["path_lengths_m"]
    without_p = runs[run_name("paper-open", False)]["band"]["path_lengths_m"]
    shorter = [a["max"] < b["min"] for a, b in zip(with_p, without_p)]
    per_robot = ", ".join(f"robot {i + 1}: {'yes' if s else 'no'} ({a['median']:.2f} vs {b['median']:.2f} m)"
                          for i, (s, a, b) in enumerate(zip(shorter, with_p, without_p)))
    lines.append(f"- (a) Prediction shortens every defender's path in the open area, in every member: "
                 f"**{'yes' if all(shorter) else 'no'}** — {per_robot}.")
    safe = {run_name(*key): runs[run_name(*key)]["robust"]["captured"] is True
            and runs[run_name(*key)]["robust"]["collision_free"] is True for key in KEYS if key[0] == "paper-obstacles"}
    detail = ", ".join(f"{name}: {'yes' if ok else 'no'}" for name, ok in safe.items())
    lines.append(f"- (b) Capture without collision among obstacles, in every member (captured, obstacle clearance "
                 f"and defender separation > 0): **{'yes' if all(safe.values()) else 'no'}** — {detail}.")
    exceptions = [f"{run_name(*key)} robot {i + 1} ({relative(b['min'], theirs):+.1f} to "
                  f"{relative(b['max'], theirs):+.1f} %: {'every member' if within(b, theirs) == 'no' else 'some members'})"
                  for key in KEYS
                  for i, (b, theirs) in enumerate(zip(runs[run_name(*key)]["band"]["path_lengths_m"],
                                                      PAPER[key].path_lengths))
                  if within(b, theirs) != "yes"]
    lines.append(f"- (c) Every path length within {TOLERANCE:.0%} of the paper, in every member: "
                 f"**{'no' if exceptions else 'yes'}**" + (f" — exceptions: {', '.join(exceptions)}." if exceptions else "."))
    return lines


def sensitivity(runs: dict, ensemble: dict) -> list[str]:
    """How much a nanometre moves each run: the finding the ensemble makes."""
    lines = ["## How much a nanometre moves a hunt", "",
             f"Each run was repeated {ensemble['members']} times with every robot's start moved by at most "
             f"{ensemble['scale_m']:g} m along each axis (`mpc_hunt.world.ensemble.perturbed`, member k drawn with seed k), "
             "far below anything a robot could tell apart; the tables above give the median and the range over "
             "those members and the nominal run. Over the members:"]
    for key in KEYS:
        b = runs[run_name(*key)]["band"]
        lengths = b["path_lengths_m"]
        widest = max(x["max"] - x["min"] for x in lengths)
        if b["steps"]["min"] == b["steps"]["max"]:
            lines.append(f"  - {run_name(*key)}: every member takes the same {b['steps']['median']:.0f} steps; "
                         f"its path lengths differ by at most {widest:.1e} m.")
        else:
            lines.append(f"  - {run_name(*key)}: {b['steps']['min']:.0f} to {b['steps']['max']:.0f} steps, capture "
                         f"at {b['capture_time_s']['min']:.1f} to {b['capture_time_s']['max']:.1f} s, path lengths "
                         f"apart by up to {widest * 100:.1f} cm, {b['failed_solves']['min']:.0f} to "
                         f"{b['failed_solves']['max']:.0f} failed capture-stage solves.")
    kernels = ensemble["kernel_families"]
    lines += ["", "Where the members differ, the hunt is chaotic: a difference of a nanometre, or of the last bit of a "
              "sum, grows step by step into another sequence of commands, and the discrete events of the loop (an "
              "IPOPT solve that fails and falls back, a defender entering the capture stage one step earlier) make it "
              "grow faster. The runs among obstacles, whose capture stage fails and falls back dozens of times, are "
              "the sensitive ones. So `--check` holds each figure to its band (widened by half its width), and "
              "the outcomes every member shares (captured, termination, no collision) exactly.", "",
              "The nominal runs repeated under each OpenBLAS kernel family this CPU runs (`OPENBLAS_CORETYPE`): "
              + ", ".join(f"{family} {verdict}" for family, verdict in kernels.items())
              + ". No call on the closed-loop path goes through BLAS (docs/robustness.md), so the kernel does not "
              "move a hunt."]
    return lines


def differences(runs: dict) -> list[str]:
    """Where the time goes: all defenders in the capture stage, then captured (nominal runs)."""
    lines = ["## Where we differ, and why", "",
             "- **Final hunting radius.** Ours is the radius when the success test has held for "
             "`hold_time` (2 s); the circle is then still contracting towards R_hunt / 2. The paper "
             "does not say when its 0.25 m and 0.41 m were measured.",
             "- **Herding before contraction.** Capture-stage defenders stay near the edge of their field "
             "(|r_ai| ≈ R_agg) until the herding has brought the attacker to the centre of the circle, and "
             "only then contract (docs/model.md, E5 and E9). How long that takes depends on the directions "
             "the defenders arrive from (nominal runs):"]
    for key in KEYS:
        report = runs[run_name(*key)]["nominal"]
        start = report["all_in_capture_stage_s"]
        start = "never" if start is None else f"{start:.1f} s"
        end = f"{report['capture_time_s']:.1f} s" if report["captured"] else "not captured"
        lines.append(f"  - {run_name(*key)}: every defender in the capture stage at {start}; captured at {end}.")
    lines.append("- **Obstacles on the straight route.** From [15, 15], defender 2's straight route to the "
                 "attacker crosses the obstacle at [7, 12]; its field turns the defender around it inside the "
                 "protective distance, which is the largest single difference from the paper's path lengths.")
    return lines


def readme(results: dict) -> str:
    """README.md, from results.json alone (so --check can tell whether the committed one is its results')."""
    runs, ensemble = results["runs"], results["ensemble"]
    figures = [f"![{run_name(*key)}]({run_name(*key)}.png)" for key in KEYS]
    return "\n".join([
        "# Reproduction of the paper's simulations", "",
        f"Regenerate this folder with `{COMMAND}` (from the repository root; about {results['seconds']:.0f} s "
        f"on 2 cores). `{COMMAND} --check` reruns the nominal runs and checks them against the bands below.", "",
        "The built-in scenarios `paper-open` (Fig. 7) and `paper-obstacles` (Fig. 8), as shipped, each "
        "run with and without trajectory prediction. No parameter is tuned for this study; the "
        "published numbers are those printed in the paper. Each of our numbers is the median over an ensemble "
        f"of {ensemble['members'] + 1} runs (the nominal run and {ensemble['members']} with the starts moved by a "
        "nanometre), with the range in brackets where the members differ at the precision shown. Every run's "
        "report, band and robust outcomes are in `results.json`.", "",
        "## Path lengths", "", *path_table(runs), "",
        "## Runs", "", *run_table(runs), "",
        "The paper gives no capture times or clearances; a capture-stage fallback is a step whose "
        "solve failed and whose command came from the strategy's fallback.", "",
        *claims(runs), "",
        *sensitivity(runs, ensemble), "",
        *differences(runs), "",
        "## Figures (nominal runs)", "", *figures, "",
    ])


def report(result) -> dict:
    """A run's JSON report, with the time every defender was first in the capture stage."""
    all_in = np.flatnonzero(result.capture_stage.all(axis=1))
    return result.to_dict() | {"all_in_capture_stage_s": float(result.times[all_in[0]]) if len(all_in) else None,
                               "collision_free": _collision_free(result.min_obstacle_clearance,
                                                                 result.min_defender_separation)}


def _collision_free(clearance: float | None, separation: float | None) -> bool:
    return (clearance is None or clearance > 0) and (separation is None or separation > 0)


def hunt(job: tuple[str, bool, int]):
    """One run of the ensemble: member 0 is the scenario as shipped, member k > 0 its starts moved (seed k)."""
    name, prediction, member = job
    scenario = builtin_scenario(name)
    if member:
        scenario = perturbed(scenario, np.random.default_rng(member), SCALE)
    return simulate(scenario, prediction=prediction)


def run_ensemble(members: int, workers: int) -> dict[int, dict[str, object]]:
    """HuntResults by member and run name, on ``workers`` processes."""
    jobs = [(name, prediction, m) for m in range(members + 1) for name, prediction in KEYS]
    # A worker ends at once on Ctrl-C (IPOPT would take a KeyboardInterrupt as the end of its solve only).
    with ProcessPoolExecutor(max_workers=workers, initializer=signal.signal,
                             initargs=(signal.SIGINT, signal.SIG_DFL)) as pool:
        results = list(pool.map(hunt, jobs))
    out: dict[int, dict[str, object]] = {}
    for (name, prediction, m), result in zip(jobs, results):
        out.setdefault(m, {})[run_name(name, prediction)] = result
        print(f"member {m} {run_name(name, prediction)}: captured={result.captured}, steps {result.steps}",
              file=sys.stderr, flush=True)
    return out


def nominal_reports(workers: int) -> dict[str, dict]:
    return {name: report(r) for name, r in run_ensemble(0, workers)[0].items()}


def _without_timing(r: dict) -> dict:
    return {k: v for k, v in r.items() if k != "solve_time"}


def kernel_verdicts(nominal: dict[str, dict]) -> dict[str, str]:
    """Each kernel family this CPU runs: the nominal runs' reports (timings aside) identical to ours, or not."""
    verdicts = {}
    for family in blas_kernel_families():
        env = {**os.environ, "OPENBLAS_CORETYPE": family}
        run = subprocess.run([sys.executable, __file__, "--nominal"], env=env, capture_output=True, text=True)
        if run.returncode:
            verdicts[family] = f"failed ({run.stderr.strip().splitlines()[-1:]})"
            continue
        theirs = json.loads(run.stdout)
        same = all(_without_timing(theirs[n]) == _without_timing(nominal[n]) for n in nominal)
        verdicts[family] = "identical" if same else "different"
    return verdicts


def banded(reports: list[dict]) -> dict:
    """Each figure's band over the members' reports (a list of bands for the path lengths; None where absent)."""
    out = {}
    for key in BANDED:
        values = [r[key] for r in reports]
        if key == "path_lengths_m":
            out[key] = [band(list(v)) for v in zip(*values)]
        else:
            present = [v for v in values if v is not None]
            out[key] = band(present) if len(present) == len(values) else None
    return out


def robust(reports: list[dict]) -> dict:
    """Each outcome every member shares, or None where they differ."""
    return {k: reports[0][k] if all(r[k] == reports[0][k] for r in reports) else None for k in ROBUST}


def study(workers: int) -> tuple[dict, dict]:
    """results.json's content, and the nominal runs' HuntResults (for the figures)."""
    start = time.perf_counter()
    members = run_ensemble(MEMBERS, workers)
    nominal = {name: report(r) for name, r in members[0].items()}
    runs = {}
    for key in KEYS:
        reports = [report(m[run_name(*key)]) for m in members.values()]
        runs[run_name(*key)] = {"nominal": nominal[run_name(*key)], "band": banded(reports),
                                "robust": robust(reports)}
    ensemble = {"members": MEMBERS, "scale_m": SCALE, "kernel_families": kernel_verdicts(nominal)}
    return {"ensemble": ensemble, "seconds": time.perf_counter() - start, "runs": runs}, members[0]


def differing(committed: dict, nominal: dict[str, dict]) -> list[str]:
    """Where a rerun leaves what the committed ensemble says: a robust outcome changed, or a figure off its band."""
    errors = []
    for name, new in nominal.items():
        run = committed["runs"][name]
        errors += [f"{name}.{k}: every member gave {run['robust'][k]!r}, now {new[k]!r}"
                   for k in ROBUST if run["robust"][k] is not None and new[k] != run["robust"][k]]
        for key in BANDED:
            bands, values = run["band"][key], new[key]
            if key != "path_lengths_m":
                bands, values = [bands], [values]
            for b, value in zip(bands, values):
                floor = FLOOR_RTOL * abs(b["median"]) + FLOOR_ATOL if b is not None else 0.0
                if outside_band(value, b, WIDEN, floor):
                    shown = "none" if b is None else "{:.9g} to {:.9g}".format(*widened(b, WIDEN, floor))
                    errors.append(f"{name}.{key}: {value!r} is outside its band ({shown})")
    return errors


def check(out: Path, workers: int) -> list[str]:
    committed = read_json_file(out / "results.json", f"rerun {COMMAND}")
    errors = []
    if (committed["ensemble"]["members"], committed["ensemble"]["scale_m"]) != (MEMBERS, SCALE):
        errors.append(f"results.json: an ensemble of {committed['ensemble']['members']} members at "
                      f"{committed['ensemble']['scale_m']} m, the study runs {MEMBERS} at {SCALE} m")
    if (out / "README.md").read_text(encoding="utf-8") != readme(committed):
        errors.append("README.md: not what results.json gives")
    return errors + differing(committed, nominal_reports(workers))


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=output_folder, default=DEFAULT_OUT,
                        help="output folder (default: studies/reproduction/ beside this script)")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true",
                      help="rerun the nominal runs and compare with the committed bands; write nothing")
    mode.add_argument("--nominal", action="store_true", help="print the nominal runs' reports as JSON")
    args = parser.parse_args(argv)
    workers = min(2, os.cpu_count() or 1)
    with stop_at_once("reproduction study"):     # Ctrl-C: at once, nothing written
        if args.nominal:
            print(json.dumps(nominal_reports(1)))
            return 0
        if args.check:
            return check_result(check(args.output, workers), str(args.output), COMMAND)
        results, nominal = study(workers)
    args.output.mkdir(parents=True, exist_ok=True)
    for key in KEYS:
        plot_hunt(nominal[run_name(*key)], builtin_scenario(key[0]), args.output / f"{run_name(*key)}.png")
    (args.output / "results.json").write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")
    (args.output / "README.md").write_text(readme(results), encoding="utf-8")
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(run_study(main))
    except (KeyboardInterrupt, BrokenProcessPool):
        print("interrupted: nothing written", file=sys.stderr)
        sys.exit(130)

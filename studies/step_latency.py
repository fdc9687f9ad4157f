"""Step latency of every capture-stage formulation × backend, and how the step grows with N and N_d.

One run, side by side on one machine, so that the ratios hold even when the
absolute times of a shared machine drift:

* **Latency.** Every installed pair solves the same consecutive closed-loop
  states of ``paper-obstacles`` (N_d = 3 in the capture stage, N = 10), each
  warm-started as the controller does (the previous plan shifted one step),
  the pairs taking turns on each state so that load on the machine falls on
  all of them alike (the growth tables too).
  *step* is state in → plan out (the capture problem posed, the solve) without
  the shared evaluator; *all-in* adds its scoring (``Solution.score_time``).
  Ratios are to ``nlp``/``ipopt`` on the same states.
* **Peer.** With do-mpc installed (``pip install -e .[peers]``), one more row:
  ``nlp``'s problem written in do-mpc (``studies/do_mpc_peer.py``), solved on
  the same states with the same *step*, its plans scored by the same evaluator.
* **Growth.** The step of the stage-structured pairs (and ``qp`` for contrast)
  for N = 5…50 on the same states, and for N_d = 3…12 defenders evenly placed
  around the attacker of the first state; the fitted exponent b of step ∝ N^b.
* **Floor.** What one QP costs at best, whichever solver and start
  (``step_floor.py``): DAQP from its solution's own working set, HPIPM with
  the obstacles removed.
* **Targets.** Each target of the capture stage, met or missed by how much;
  for the recommended step, where its time goes (``step_profile.py``).

The states are written to ``states.json`` (a problem set: one sequence) and
read back with ``--reuse-states``, so that another checkout of the code can be
measured on the very same states.

    python studies/step_latency.py [--output studies/step_latency] [--states 60] [--pairs qp/osqp …]
                                   [--reuse-states] [--no-growth] [--no-peer]
    python studies/step_latency.py --check      # the committed pairs are the registry's; the cheap ones, rerun
                                                # on the committed states, give the same failures and objectives
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import replace
from importlib.metadata import version
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt import CaptureMPC, CaptureProblem, Status, builtin_scenario, evaluate, markdown

from mpc_hunt.solving import registry
from mpc_hunt.arguments import CommandParser, count, output_folder
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.bench.machine import describe_machine, load_average
from mpc_hunt.bench.compare import timed_step
from mpc_hunt.bench.problem_set import ProblemEntry, ProblemSet, load_problem_set, save_problem_set
from mpc_hunt.world.scenario import Defender

from studies.step_exported import exported_c, exported_lines
from studies.step_floor import floor_lines, qp_floor
from studies.step_loop import loop_latency, loop_lines, loop_targets
from studies.step_profile import rti_profile
from studies.study_check import check_result, read_json_file, run_study

try:
    from studies.do_mpc_peer import DoMPCPeer
except ImportError:                 # do-mpc is an optional extra: pip install -e .[peers]
    DoMPCPeer = None

SCENARIO = "paper-obstacles"
HORIZON = 10
HORIZONS = (5, 10, 20, 30, 50)
TEAM_SIZES = (3, 6, 9, 12)
GROWTH_PAIRS = (("rti", "hpipm"), ("rti", "hpipm-codegen"), ("stage-sqp", "hpipm-codegen"), ("ms-nlp", "ipopt"),
                ("qp", "osqp"), ("qp", "clarabel"))
GROWTH_STATES = 15
MAX_STATES = 1_000      # --states: every pair solves each of them
BASELINE = ("nlp", "ipopt")
PEER = ("do-mpc", "ipopt (peer)")


def closed_loop_states(size: int) -> ProblemSet:
    from mpc_hunt.bench.capture_state import formed_circle_states
    scenario = builtin_scenario(SCENARIO)
    states = formed_circle_states(scenario, size)
    entries = tuple(ProblemEntry(f"{SCENARIO}/{i}", SCENARIO, s, f"{SCENARIO}/closed-loop")
                    for i, s in enumerate(states))
    return ProblemSet({SCENARIO: scenario}, entries,
                      f"{size} consecutive closed-loop states of {SCENARIO} (the paper's strategy), from the first "
                      "with the hunting circle formed. Rebuild with `python studies/step_latency.py`.")


class Sequence:
    """One pair's run over consecutive states, a state at a time, warm-started as the controller does: each step
    timed by ``mpc-hunt compare``'s replayed mode (:func:`~mpc_hunt.bench.compare.timed_step`)."""

    def __init__(self, formulation: str, backend: str):
        # The formulation's own path (posing θ, the backend's solve, the read-back), as the latency table has
        # always timed it; the control loop's step is step_loop's.
        self.mpc, self.rows = CaptureMPC(formulation, backend, loop=False), []

    def step(self, make) -> None:
        """Pose the state (``make()``), solve it, and keep its times and figures: *step* with any set-up, the
        evaluator's scoring apart; a failure is a status with no usable plan."""
        record = timed_step(self.mpc, make, self.mpc.tolerance)
        step = record.solve_time + record.setup_time
        violation = record.violation
        self.rows.append({"step_s": step, "all_in_s": step + record.score_time, "solver_s": record.solver_time,
                          "setup_s": record.setup_time, "iterations": record.iterations,
                          "success": Status(record.status).usable, "objective": record.objective,
                          "obstacle_violation": None if violation is None else violation["obstacle_safety"],
                          "max_violation": None if violation is None else max(violation.values())})


class PeerSequence:
    """:class:`Sequence` for the do-mpc peer: set up once per structure, warm-started as do-mpc does."""

    def __init__(self):
        self.peers, self.rows = {}, []

    def step(self, make) -> None:
        t0 = time.perf_counter()
        problem = make()
        setup = 0.0
        if problem.structure not in self.peers:
            self.peers[problem.structure] = DoMPCPeer(problem)
            setup = self.peers[problem.structure].setup_time
        peer = self.peers[problem.structure]
        plan = peer.solve(problem)
        step = time.perf_counter() - t0
        t1 = time.perf_counter()
        evaluation = evaluate(problem, plan)
        evaluator = time.perf_counter() - t1
        stats = peer.mpc.solver_stats
        self.rows.append({"step_s": step, "all_in_s": step + evaluator, "solver_s": peer.solver_time,
                          "setup_s": setup, "iterations": stats["iter_count"], "success": bool(stats["success"]),
                          "objective": evaluation.objective,
                          "obstacle_violation": evaluation.violation["obstacle_safety"],
                          "max_violation": evaluation.max_violation})


def in_turns(sequences: list, problems: list) -> list[list[dict]]:
    """Every sequence over ``problems`` (callables posing each state), taking turns on each state, so that load on
    the machine falls on all alike; each one's rows."""
    for make in problems:
        for sequence in sequences:
            sequence.step(make)
    return [sequence.rows for sequence in sequences]


def solve_sequence(formulation: str, backend: str, problems: list) -> list[dict]:
    """One pair alone over ``problems``: its rows."""
    return in_turns([Sequence(formulation, backend)], problems)[0]


def summarise(rows: list[dict]) -> dict:
    later = rows[1:]                      # the first solve also sets up
    med = lambda key: float(np.median([r[key] for r in later]))  # noqa: E731
    return {"median_step_ms": med("step_s") * 1e3, "median_all_in_ms": med("all_in_s") * 1e3,
            "median_solver_ms": med("solver_s") * 1e3, "median_iterations": med("iterations"),
            "setup_ms": rows[0]["setup_s"] * 1e3, "failed": sum(not r["success"] for r in rows), "solves": len(rows),
            "max_obstacle_violation": max((r["obstacle_violation"] or 0.0) for r in rows),
            "median_objective": float(np.median([r["objective"] for r in rows if r["objective"] is not None]))}


def latency(problem_set: ProblemSet, pairs: list[tuple[str, str]], peer: bool = False) -> list[dict]:
    entries = problem_set.sequences()[f"{SCENARIO}/closed-loop"]
    problems = [lambda e=e: problem_set.problem(e, HORIZON) for e in entries]
    names = pairs + ([PEER] if peer else [])
    sequences = [Sequence(f, b) for f, b in pairs] + ([PeerSequence()] if peer else [])
    out = []
    for (formulation, backend), rows in zip(names, in_turns(sequences, problems)):
        row = {"formulation": formulation, "backend": backend, **summarise(rows)}
        out.append(row)
        print(f"{formulation}/{backend}: step {row['median_step_ms']:.3f} ms, all-in {row['median_all_in_ms']:.3f} ms, "
              f"{row['median_iterations']:.0f} iterations, {row['failed']} failed", flush=True)
    base = next((r for r in out if (r["formulation"], r["backend"]) == BASELINE), None)
    for r in out:
        r["step_ratio"] = None if base is None else base["median_step_ms"] / r["median_step_ms"]
        r["all_in_ratio"] = None if base is None else base["median_all_in_ms"] / r["median_all_in_ms"]
    return out


def team(scenario, attacker: np.ndarray, size: int):
    """``scenario`` with ``size`` defenders, placed evenly on a circle of 0.6 R_agg around ``attacker``."""
    angles = 2 * np.pi * np.arange(size) / size
    radius = 0.6 * scenario.attacker.perception_radius
    positions = attacker + radius * np.column_stack([np.cos(angles), np.sin(angles)])
    speed = scenario.defenders[0].max_speed
    return replace(scenario, defenders=tuple(Defender(start=tuple(p), max_speed=speed) for p in positions)), positions


def fit(sizes, times) -> float:
    return float(np.polyfit(np.log(sizes), np.log(times), 1)[0])


def growth(problem_set: ProblemSet, pairs: list[tuple[str, str]]) -> dict:
    """The step of each pair for each N and each N_d, the pairs taking turns on each state."""
    entries = problem_set.sequences()[f"{SCENARIO}/closed-loop"][:GROWTH_STATES]
    first, base = entries[0].state, problem_set.scenarios[SCENARIO]
    cases = [("horizon", "N", N, [lambda e=e, N=N: problem_set.problem(e, N) for e in entries]) for N in HORIZONS]
    for size in TEAM_SIZES:
        scenario, positions = team(base, first.attacker, size)
        cases.append(("team", "N_d", size, _team_sequence(scenario, first.attacker, positions)))
    result = {"horizon": [], "team": []}
    for table, key, value, problems in cases:
        for (formulation, backend), rows in zip(pairs, in_turns([Sequence(f, b) for f, b in pairs], problems)):
            result[table].append({"formulation": formulation, "backend": backend, key: value, **summarise(rows)})
            print(f"growth {formulation}/{backend} {key}={value}: {result[table][-1]['median_step_ms']:.3f} ms",
                  flush=True)
    for table, sizes in (("horizon", HORIZONS), ("team", TEAM_SIZES)):
        steps = {pair: [r["median_step_ms"] for r in result[table] if (r["formulation"], r["backend"]) == pair]
                 for pair in pairs}
        result[f"{table}_exponent"] = {f"{f}/{b}": fit(sizes, steps[f, b]) for f, b in pairs}
    return result


def _team_sequence(scenario, attacker, defenders) -> list:
    """GROWTH_STATES consecutive states of a capture stage driven by ``rti``/``hpipm`` (the same for every pair)."""
    mpc, states = CaptureMPC("rti", "hpipm"), []
    for _ in range(GROWTH_STATES):
        states.append((attacker.copy(), defenders.copy()))
        problem = CaptureProblem.at_state(scenario, attacker, defenders, HORIZON)
        plan = mpc.step(problem).plan
        attacker = problem.attacker_step(attacker, defenders)
        defenders = plan[0]
    return [lambda a=a, d=d: CaptureProblem.at_state(scenario, a, d, HORIZON) for a, d in states]


def latency_table(rows: list[dict]) -> str:
    def ratio(v: float | None) -> str:
        return "–" if v is None else f"{v:.1f}"

    return "\n".join(markdown.table(
        ["formulation", "backend", "step (ms)", "× faster than nlp/ipopt", "all-in (ms)", "×", "solver call (ms)",
         "iterations", "failed / solves", "set-up (ms)", "max obstacle violation (m)", "median objective"],
        "ll" + "r" * 10,
        ([r["formulation"], r["backend"], f"{r['median_step_ms']:.3f}", ratio(r["step_ratio"]),
          f"{r['median_all_in_ms']:.3f}", ratio(r["all_in_ratio"]), f"{r['median_solver_ms']:.3f}",
          f"{r['median_iterations']:.0f}", f"{r['failed']} / {r['solves']}", f"{r['setup_ms']:.0f}",
          f"{r['max_obstacle_violation']:.1e}", f"{r['median_objective']:.4g}"] for r in rows)))


def peer_note(ran: bool, skipped: bool) -> str:
    if ran:
        return (f"`{'/'.join(PEER)}`: `nlp`'s problem written in do-mpc {version('do-mpc')} "
                "([`studies/do_mpc_peer.py`](../do_mpc_peer.py), which says where it differs), warm-started as do-mpc "
                "does; its *step* includes setting do-mpc's parameters and reading the plan back, its *solver call* "
                "is `make_step`, its set-up do-mpc's `setup()`.")
    if skipped:
        return "The do-mpc peer was skipped (`--no-peer`)."
    return "do-mpc is not installed (`pip install -e .[peers]`): the do-mpc peer's row is skipped."


def growth_tables(result: dict) -> str:
    """The step of each pair against N, then against N_d, with the fitted exponents."""
    pairs = list(result["horizon_exponent"])

    def growth_table(table: str, key: str, values: tuple[int, ...]) -> list[str]:
        steps = {pair: [f"{r['median_step_ms']:.3f}" for r in result[table]
                        if f"{r['formulation']}/{r['backend']}" == pair] for pair in pairs}
        return markdown.table(["pair", *(f"{key} = {v}" for v in values), f"exponent b (step ∝ {key}^b)"],
                              "l" + "r" * (len(values) + 1),
                              ([pair, *steps[pair], f"{result[f'{table}_exponent'][pair]:.2f}"] for pair in pairs))

    return "\n".join([*growth_table("horizon", "N", HORIZONS), "", *growth_table("team", "N_d", TEAM_SIZES)])


CHECK_BELOW_MS = 100      # --check reruns the pairs whose committed step is below this (the rest take minutes)


def check(out: Path) -> list[str]:
    """The committed pairs are the registry's, and rerunning the cheap ones on the committed states gives the
    same failures and median objective (timings are not checked)."""
    committed = read_json_file(out / "results.json", "rerun python studies/step_latency.py")["latency"]
    rows = [r for r in committed if (r["formulation"], r["backend"]) != PEER]
    pairs = [(r["formulation"], r["backend"]) for r in rows]
    if pairs != registry.pairs(objective="paper"):
        return [f"results.json: pairs {pairs}, the registry's are {registry.pairs(objective='paper')}"]
    problem_set = load_problem_set(out / "states.json")
    entries = problem_set.sequences()[f"{SCENARIO}/closed-loop"]
    problems = [lambda e=e: problem_set.problem(e, HORIZON) for e in entries]
    errors = []
    for old in rows:
        if old["median_step_ms"] >= CHECK_BELOW_MS:
            continue
        new = summarise(solve_sequence(old["formulation"], old["backend"], problems))
        key = f"{old['formulation']}/{old['backend']}"
        if new["failed"] != old["failed"]:
            errors.append(f"{key}: failed committed {old['failed']}, now {new['failed']}")
        if abs(new["median_objective"] - old["median_objective"]) > 1e-6 * abs(old["median_objective"]):
            errors.append(f"{key}: median objective committed {old['median_objective']}, now "
                          f"{new['median_objective']}")
    return errors


QP_STEP_MS, QP_RATIO, NLP_RATIO, EXPONENT = 0.3, 30.0, 3.0, 1.1    # the capture stage's targets


def targets(rows: list[dict], growth_result: dict | None, profile: dict | None) -> list[str]:
    """Each target of the capture stage against this run: met, or by how much it is missed and where the time goes."""
    by_pair = {(r["formulation"], r["backend"]): r for r in rows}
    lines = []
    rti = by_pair.get(("rti", "hpipm"))
    if rti is not None and rti["step_ratio"] is not None:
        step, call = rti["median_step_ms"], rti["median_solver_ms"]
        verdict = "met" if step <= QP_STEP_MS else f"missed, {step / QP_STEP_MS:.1f}× over"
        lines.append(f"- **QP step ≤ {QP_STEP_MS} ms** (`rti`/`hpipm`, the recommended capture stage): {step:.3f} ms, "
                     f"{verdict}.")
        if profile is not None:
            lines.append(f"  Where it goes: the one CasADi call takes {call:.3f} ms, the Python that poses the problem "
                         f"and reads the result {step - call:.3f} ms. Timed apart on the same states (fastest of "
                         f"{profile['repeats']} per state, then the median: the least disturbed times), the linearisation alone takes "
                         f"{profile['linearise_ms']:.3f} ms and HPIPM alone {profile['hpipm_ms']:.3f} ms; the rest "
                         "of the call is the plan's read-back and CasADi's own overhead between them."
                         + (" HPIPM alone exceeds the target: meeting it needs a faster QP solve, not only less "
                            "overhead."
                            if profile["hpipm_ms"] > QP_STEP_MS else ""))
        ratio = rti["step_ratio"]
        lines.append(f"- **QP step ≥ {QP_RATIO:.0f}× faster than `nlp`/`ipopt`**: {ratio:.1f}×, "
                     + ("met." if ratio >= QP_RATIO else f"missed by {QP_RATIO / ratio:.2f}×."))
    nlps = [r for r in rows if r["formulation"] in ("nlp", "ms-nlp") and (r["formulation"], r["backend"]) != BASELINE
            and r["step_ratio"] is not None]
    peer = by_pair.get(PEER)
    if nlps:
        best = max(nlps, key=lambda r: r["step_ratio"])
        text = (f"- **Fastest NLP ≥ {NLP_RATIO:.0f}× faster than `nlp`/`ipopt`, and faster than the do-mpc peer**: "
                f"`{best['formulation']}`/`{best['backend']}`, {best['step_ratio']:.1f}×")
        if peer is not None:
            text += f", {peer['median_step_ms'] / best['median_step_ms']:.1f}× faster than the peer"
        met = best["step_ratio"] >= NLP_RATIO and (peer is None or best["median_step_ms"] < peer["median_step_ms"])
        lines.append(text + (": met." if met else ": missed."))
    if growth_result is not None:
        exponents = growth_result["horizon_exponent"]
        for pair in ("rti/hpipm", "ms-nlp/ipopt"):
            if pair in exponents:
                b = exponents[pair]
                lines.append(f"- **Step at most linear in N** (b ≤ {EXPONENT}) for `{pair}`: b = {b:.2f}, "
                             + ("met." if b <= EXPONENT else f"missed by {b - EXPONENT:.2f}."))
    return lines


def pair(text: str) -> tuple[str, str]:
    """An argument type: an installed ``FORMULATION/BACKEND`` pair."""
    formulation, slash, backend = text.partition("/")
    if not slash or not backend:
        raise argparse.ArgumentTypeError(f"expected FORMULATION/BACKEND (such as rti/hpipm), got {text!r}")
    try:
        registry.check_pair(formulation, backend)
    except MpcHuntError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return formulation, backend


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=output_folder, default=Path(__file__).parent / "step_latency")
    parser.add_argument("--states", type=count(MAX_STATES), default=60,
                        help=f"consecutive closed-loop states, 2 to {MAX_STATES}")
    parser.add_argument("--pairs", nargs="+", type=pair, metavar="FORMULATION/BACKEND")
    parser.add_argument("--reuse-states", action="store_true", help="read the states from OUT/states.json")
    parser.add_argument("--no-growth", action="store_true", help="skip the growth with N and N_d")
    parser.add_argument("--no-peer", action="store_true", help="skip the do-mpc peer")
    parser.add_argument("--blasfeo", type=Path, metavar="DIR",
                        help="also time the exported C steps against this BLASFEO (built for this CPU, the wheel's "
                             "version)")
    parser.add_argument("--check", action="store_true",
                        help=f"check the committed results against the code (reruns the pairs under "
                             f"{CHECK_BELOW_MS} ms a step; about a minute)")
    args = parser.parse_args(argv)
    if args.check:
        return check_result(check(args.output), "studies/step_latency", "python studies/step_latency.py --reuse-states")
    if args.blasfeo is not None and not (args.blasfeo / "libblasfeo.so.0").exists():
        parser.error(f"--blasfeo {args.blasfeo}: no libblasfeo.so.0 there")
    if args.states < 2:
        parser.error(f"--states: at least 2 (the first sets up and is not timed), got {args.states}")
    try:
        args.output.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        parser.error(f"--output {args.output}: cannot create ({exc.strerror or exc})")
    try:
        with stop_at_once("step_latency"):            # Ctrl-C: nothing written, the committed files kept
            problem_set, result = run(args)
    except MpcHuntError as exc:
        print(f"step_latency.py: error: {exc}", file=sys.stderr)
        return 2
    if not args.reuse_states:
        save_problem_set(problem_set, args.output / "states.json")
    write_report(args, problem_set, result)
    return 0


def run(args) -> tuple[ProblemSet, dict]:
    """The study's measurements: the states (read or built) and every section's figures."""
    if args.reuse_states:
        problem_set = load_problem_set(args.output / "states.json")
    else:
        problem_set = closed_loop_states(args.states)
    pairs = args.pairs or registry.pairs(objective="paper")
    before = describe_machine()
    peer = DoMPCPeer is not None and not args.no_peer
    rows = latency(problem_set, pairs, peer)
    result = {"machine": before, "latency": rows}
    if not args.no_growth:
        result["growth"] = growth(problem_set, [p for p in GROWTH_PAIRS if p in pairs])
    if ("rti", "hpipm") in pairs:
        entries = problem_set.sequences()[f"{SCENARIO}/closed-loop"]
        posed = [lambda e=e: problem_set.problem(e, HORIZON) for e in entries]
        result["profile"] = rti_profile(posed)
        if registry.installed("daqp"):
            result["floor"] = qp_floor(posed)
    entries = problem_set.sequences()[f"{SCENARIO}/closed-loop"]
    first = [problem_set.problem(e, HORIZON) for e in entries]
    result["exported_c"] = exported_c(first, args.blasfeo)
    result["loop"] = loop_latency([p for p in first if p.structure == first[0].structure])
    result["machine"]["load_average_end"] = load_average()
    return problem_set, result


def write_report(args, problem_set: ProblemSet, result: dict) -> None:
    """``results.json`` and the README of ``args.output``."""
    rows = result["latency"]
    peer = any((r["formulation"], r["backend"]) == PEER for r in rows)
    (args.output / "results.json").write_text(json.dumps(result, indent=1) + "\n")
    m = result["machine"]
    text = ["# Step latency of the capture stage", "",
            "Regenerate with `python studies/step_latency.py` (all pairs, growth included"
            + (", `--blasfeo DIR`: a BLASFEO of the wheel's version built for this CPU" if args.blasfeo else "")
            + "). Measured in one run "
            f"on {m['cpu']} ({m['cores']} cores, shared: load average {m['load_average'][0]:.1f} "
            f"before, {m['load_average_end'][0]:.1f} after), {m['system']}, Python {m['python']}, "
            f"CasADi {m['packages']['casadi']}. Absolute times drift on a shared machine; the ratios are from the same run.", "",
            f"## Latency at N_d = 3, N = {HORIZON}", "",
            f"{problem_set.description} Medians over {len(problem_set.problems) - 1} warm-started steps (the first, "
            "which sets up, excluded). *step*: state in → plan out, the shared evaluator excluded; *all-in*: with "
            "its scoring (`Solution.score_time`); *solver call*: the backend's call alone; *median "
            "objective*: the evaluator's, over every state.", "", latency_table(rows), "",
            peer_note(peer, args.no_peer), ""]
    text += exported_lines(result["exported_c"], rows, BASELINE)
    text += loop_lines(result["loop"], rows)
    if result.get("floor") is not None:
        interpreted = next(r for r in rows if (r["formulation"], r["backend"]) == ("rti", "hpipm"))
        text += floor_lines(result["floor"], result["profile"], interpreted["median_step_ms"],
                            len(problem_set.scenarios[SCENARIO].obstacles), result["exported_c"])
    if "growth" in result:
        text += ["## Growth with the horizon N and the team N_d", "",
                 f"Median step over the first {GROWTH_STATES} states (N) or over {GROWTH_STATES} consecutive "
                 "states of a capture stage with N_d defenders evenly placed around the attacker of the first state, "
                 f"driven by `rti`/`hpipm` (N_d, at N = {HORIZON}); b from a least-squares fit of log step on "
                 "log N (log N_d).", "", growth_tables(result["growth"]), ""]
    text += ["## Targets", "", *targets(rows, result.get("growth"), result.get("profile")),
             *loop_targets(result["loop"], rows, result["exported_c"]), ""]
    (args.output / "README.md").write_text("\n".join(text))
    print(f"wrote {args.output / 'README.md'}")


if __name__ == "__main__":
    sys.exit(run_study(main))

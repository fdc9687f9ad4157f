"""How the capture step grows with the team: the centralised ``rti`` step beside the ``distributed`` one.

For each team size N_d (:data:`SIZES`) the paper's second scenario with N_d
defenders started evenly on a circle :data:`START_RADIUS` from the attacker,
all at the paper's speed; the enclose controller (``enclose``, ``rti`` on
``hpipm``, N = 10) hunts, and its consecutive states from the first in which a
defender pushes the attacker (is within its perception radius) on are posed as
the ``enclose`` capture problem (``posed_problem``). One run, side
by side on one machine, the steps taking turns on each state:

* **centralised**: ``CaptureMPC("rti", "hpipm-codegen").loop_step(problem)`` on its
  :class:`~mpc_hunt.solving.step.CaptureStep`, the state loaded and one step: the team's QP, one call;
* **distributed** (one Jacobi round): ``CaptureMPC("distributed").loop_step(problem)`` (on a
  :class:`~mpc_hunt.solving.team_step.TeamStep`, on the formulation's default backend ``daqp-condensed``: each
  robot's QP condensed to its 2N controls, DAQP from its last active set): the state loaded, the round's
  broadcast, and each robot's step (its inputs from the broadcast, its QP on its own loop) timed apart by the
  loop (``TeamStep.robot_times``), as each robot would run it on its own board; *team*: load + broadcast + the
  slowest robot (the robots in parallel); beside it the same on ``hpipm-codegen`` (HPIPM on the stage form)
  from the same plans, and the largest difference between the two backends' plans;
* **exported C**: one robot's step exported on each backend (``CaptureSolver.export``, built with its Makefile
  at ``-O2``), run on every robot's inputs of every state, robot by robot: the median time of one robot's
  step in C;
* **on ARM** (where the tools are): the default's step cross-compiled for aarch64 Linux and run under
  ``qemu-aarch64``, and built for a bare-metal Cortex-M7 and run on qemu's mps2-an500 board: plans against the
  host's, instructions a step, flash and RAM; with the host's, each target's share of a 50 Hz cycle;
* **rounds**: what each Jacobi or Gauss–Seidel round buys: after k rounds from
  the controller's warm start, the evaluator's objective of the team's plan
  against the centralised ``stage-sqp`` plan (the ``rti`` QP iterated to
  convergence: the team problem's local optimum), relative, and the largest
  distance between the two plans; ``rti`` (one centralised QP) beside it.

Each step is a :class:`~mpc_hunt.solving.mpc.CaptureMPC`'s, warm-started from the plan it applied, shifted,
as the controller does; the ones compared on the same starts (HPIPM's robot step, the rounds) follow the
default's or the optimum's closed loop (``CaptureMPC.follow``). Exponents: the least-squares slope of log(time) on log(N_d).

    python studies/team_size.py [--output studies/team_size] [--sizes 3 6 …] [--states 20] [--reuse-states]
    python studies/team_size.py --check     # the rounds table and the plans agreement, on the committed states
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt.formulations.rti import RTIFormulation
from mpc_hunt import CaptureMPC, CaptureSolver, ControllerSpec, builtin_scenario, evaluate, markdown, simulate
from mpc_hunt.arguments import CommandParser, count, output_folder
from mpc_hunt.bench.machine import describe_machine, load_average
from mpc_hunt.control.posing import posed_problem
from mpc_hunt.errors import DataFileError, MpcHuntError, ScenarioError
from mpc_hunt.solving.backends.conic_step import QP_KEYS
from mpc_hunt.solving.backends.hpipm import HpipmBackend
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.world.hunt_state import STATE_FORM, HuntState, state_from_dict
from mpc_hunt.world.scenario import Defender

from studies.study_check import check_result, read_json_file, run_study

SCENARIO = "paper-obstacles"
REPEATS = 3                 # HPIPM alone: the fastest of this many solves of each QP (the least disturbed)
SIZES = (3, 6, 9, 12, 16, 20)
START_RADIUS = 1.6          # m from the attacker: outside its perception radius, 20 robots 0.5 m apart
STATES = 20
HORIZON = 10
MAX_SIZE, MAX_STATES = 40, 500
ROUNDS = (1, 2, 3, 5, 10)
ROUND_SIZES = (3, 6, 12)    # the rounds table's teams
COMMAND = "python studies/team_size.py"
ROBOT_BACKENDS = ("daqp-condensed", "hpipm-codegen")     # a robot's step: the default first, then HPIPM's
BACKEND_KEYS = {"daqp-condensed": "daqp", "hpipm-codegen": "hpipm"}
AARCH64_CC, AARCH64_SIZE = "aarch64-linux-gnu-gcc", "aarch64-linux-gnu-size"
M7_CC, M7_SIZE = "arm-none-eabi-gcc", "arm-none-eabi-size"
M7_CLOCK_HZ = 480e6         # a Cortex-M7 at 480 MHz (STM32H743's), one instruction a cycle assumed
CYCLE_S = 0.02              # the team's 50 Hz
GAP_TOL = 1e-6              # the check: the rounds table's gaps, relative (HPIPM's tolerance, with margin)


def team_scenario(size: int):
    """The paper's second scenario with ``size`` defenders evenly round the attacker at the paper's speed."""
    base = builtin_scenario(SCENARIO)
    a = np.asarray(base.attacker.start, dtype=float)
    angles = 2 * np.pi * np.arange(size) / size
    defenders = tuple(Defender((float(a[0] + START_RADIUS * np.cos(t)), float(a[1] + START_RADIUS * np.sin(t))),
                               base.defenders[0].max_speed) for t in angles)
    return replace(base, name=f"{SCENARIO}-{size}", defenders=defenders)


def hunt_states(size: int, states: int) -> list[HuntState]:
    """The recommended controller's states from the first in which a defender pushes the attacker (within its
    perception radius) on, ``states`` of them (fewer if the hunt ends first)."""
    scenario = team_scenario(size)
    controller = ControllerSpec("enclose", "rti", "hpipm", HORIZON).build(scenario)
    first = []

    def until(obs) -> bool:
        if not first and np.min(np.hypot(*(obs.defenders - obs.attacker).T)) < scenario.attacker.perception_radius:
            first.append(obs.time)
        return bool(first) and obs.time >= first[0] + (states - 0.5) * scenario.hunt.time_step

    result = simulate(scenario, controller, until=until)
    start = int(np.argmax(np.min(np.hypot(*(result.defenders - result.attacker[:, None]).transpose(2, 0, 1)), axis=1)
                          < scenario.attacker.perception_radius))
    return [HuntState(float(result.times[k]), result.attacker[k], result.defenders[k])
            for k in range(start, min(start + states, len(result.times)))]


def problems_of(size: int, states: list[HuntState]) -> list:
    scenario = team_scenario(size)
    return [posed_problem(scenario, s, HORIZON, "enclose") for s in states]


class HpipmAlone:
    """HPIPM alone on a step's own QP: the stage QP linearised apart (``rti``'s graph for ``structure``) and
    solved by CasADi's ``hpipm`` plugin with the backend's options; the fastest of :data:`REPEATS` solves."""

    def __init__(self, structure):
        self.linearise, self.hpipm = HpipmBackend().linearised(RTIFormulation().built(structure))

    def time(self, theta: np.ndarray, reference: np.ndarray) -> float:
        data = dict(zip(QP_KEYS, self.linearise(theta, reference)))
        best = math.inf
        for _ in range(REPEATS):
            start = time.perf_counter()
            self.hpipm(**data)
            best = min(best, time.perf_counter() - start)
        return best


def timed_sizes(states: dict[int, list[HuntState]]) -> tuple[list[dict], dict]:
    """The growth table's rows, and per size the robots' inputs and both backends' plans (for the exported C)."""
    rows, robots = [], {}
    for size, hunt in states.items():
        problems = problems_of(size, hunt)
        central = CaptureMPC("rti", "hpipm-codegen", score=False)
        c_loop = central.solver.step_for(problems[0])
        d_mpcs = {b: CaptureMPC("distributed", b, score=False) for b in ROBOT_BACKENDS}
        d_loops = {b: mpc.solver.step_for(problems[0]) for b, mpc in d_mpcs.items()}
        leader, d_loop = d_mpcs[ROBOT_BACKENDS[0]], d_loops[ROBOT_BACKENDS[0]]
        alone = {"central": HpipmAlone(problems[0].structure), "robot": HpipmAlone(d_loop.team.robot)}
        times = {k: [] for k in ("central", "team", "broadcast", "central_hpipm", "robot_hpipm",
                                 *(f"robot {b}" for b in ROBOT_BACKENDS))}
        inputs, plans, failed, unseen, difference = [], {b: [] for b in ROBOT_BACKENDS}, 0, 0, 0.0
        for problem in problems:
            start = time.perf_counter()
            central.loop_step(problem)
            times["central"].append(time.perf_counter() - start)
            times["central_hpipm"].append(alone["central"].time(c_loop.theta, c_loop.reference.reshape(-1)))
            # Each robot backend's step from the same plans (the default's closed loop): the same inputs, so
            # their plans compare.
            for backend in reversed(ROBOT_BACKENDS):            # the default last: the team's numbers are its
                mpc = d_mpcs[backend]
                if mpc is not leader:
                    mpc.follow(leader)
                start = time.perf_counter()
                mpc.loop_step(problem)
                stepped = time.perf_counter()
                times[f"robot {backend}"] += d_loops[backend].robot_times
            # The step ran each robot's inputs and QP one after another, timing each (``robot_times``); the rest of
            # the step is the broadcast. On the robots: the load, the broadcast and the slowest robot.
            robot_times = d_loop.robot_times
            times["broadcast"].append(d_loop.broadcast_time)
            times["team"].append(stepped - start - sum(robot_times) + max(robot_times))
            failed += d_loop.extras["failed_robot_qps"]
            unseen = max(unseen, d_loop.unseen_neighbours)
            difference = max(difference, float(np.max(np.abs(d_loop.plan - d_loops["hpipm-codegen"].plan))))
            for i, loop in enumerate(d_loop.robots):
                inputs.append(np.concatenate([loop.theta, loop.reference.reshape(-1)]))
                for backend in ROBOT_BACKENDS:
                    plans[backend].append(d_loops[backend].robots[i].plan.reshape(-1).copy())
                times["robot_hpipm"].append(alone["robot"].time(loop.theta, loop.reference.reshape(-1)))
        first = len(d_loop.robots)            # the first state, which builds, excluded
        row = {"size": size, "states": len(problems), "central_ms": _median(times["central"][1:]),
               "central_hpipm_ms": _median(times["central_hpipm"][1:]),
               "robot_ms": _median(times[f"robot {ROBOT_BACKENDS[0]}"][first:]),
               "robot_hpipm_loop_ms": _median(times["robot hpipm-codegen"][first:]),
               "robot_hpipm_ms": _median(times["robot_hpipm"][first:]),
               "robot_plan_difference_m": difference,
               "broadcast_ms": _median(times["broadcast"][1:]), "team_ms": _median(times["team"][1:]),
               "failed_robot_qps": failed, "unseen_neighbours": unseen,
               "neighbour_slots": d_loop.team.robot.fixed}
        rows.append(row)
        robots[size] = (problems[0], inputs, plans)
        print(f"N_d = {size}: centralised {row['central_ms']:.3f} ms; a robot {row['robot_ms']:.3f} ms "
              f"(HPIPM {row['robot_hpipm_loop_ms']:.3f} ms) team {row['team_ms']:.3f} ms", file=sys.stderr,
              flush=True)
    return rows, robots


def _median(values: list[float]) -> float:
    return float(np.median(values)) * 1e3


def exported(robots: dict) -> list[dict] | None:
    """One robot's step in C per size and robot backend: its median time on every robot's inputs, and the
    largest difference from Python's plans."""
    if shutil.which("make") is None or shutil.which("gcc") is None:
        return None
    rows = []
    for size, (problem, inputs, plans) in robots.items():
        row = {"size": size}
        n = problem.structure.planned
        for backend in ROBOT_BACKENDS:
            run = _run_exported(backend, problem, _robot_major(inputs, n), "host",
                                size_tool="size" if shutil.which("size") else None)
            times = [float(line.split()[1]) for line in run.stderr.splitlines() if line.startswith("time_us")]
            key = BACKEND_KEYS[backend]
            row[f"{key}_c_ms"] = float(np.median(times[1:])) / 1e3
            row[f"{key}_c_max_ms"] = float(np.max(times)) / 1e3
            row[f"{key}_exit"] = run.returncode
            row[f"{key}_footprint"] = run.footprint
            row[f"{key}_plan_difference_m"] = float(np.max(np.abs(np.array(run.stdout.split(), dtype=float)
                                                                  - np.concatenate(_robot_major(plans[backend], n)))))
        rows.append(row)
        print(f"N_d = {size}: a robot's step in C {row['daqp_c_ms']:.3f} ms (HPIPM {row['hpipm_c_ms']:.3f} ms)",
              file=sys.stderr, flush=True)
    return rows


def _run_exported(backend: str, problem, inputs: list, target: str, command: tuple = (),
                  size_tool: str | None = None) -> subprocess.CompletedProcess:
    """Robot 0's step of ``problem`` exported on ``backend`` for ``target``, built by its Makefile at -O2 and run on
    ``inputs`` (``command`` before the program: an emulator); with ``size_tool``, the program's sizes
    (:func:`_sizes`) as the run's ``footprint``."""
    with tempfile.TemporaryDirectory() as folder:
        CaptureSolver("distributed", backend).export(Path(folder), problem, robot=0, target=target)
        subprocess.run(["make", "-s", "-B", "-C", folder, "CFLAGS=-O2"], check=True, capture_output=True,
                       timeout=1800)
        text = "\n".join(" ".join(f"{v:.17g}" for v in x) for x in inputs) + "\n"
        run = subprocess.run([*command, f"{folder}/capture_step", "--time"], capture_output=True, text=True,
                             timeout=3600, input=text)
        run.footprint = _sizes(Path(folder) / "capture_step", size_tool) if size_tool else None
        return run


def _robot_major(values: list, robots: int) -> list:
    """``values`` of every robot at every state (state by state) reordered robot by robot: each robot's steps in
    turn, as its own board runs them (each from its own last working set)."""
    states = len(values) // robots
    return [values[s * robots + i] for i in range(robots) for s in range(states)]


def _sizes(path: Path, tool: str) -> dict:
    """``tool`` (a binutils ``size``)'s text, data and bss of the program at ``path``, in bytes."""
    out = subprocess.run([tool, str(path)], capture_output=True, text=True, check=True).stdout.splitlines()[1].split()
    return {"text": int(out[0]), "data": int(out[1]), "bss": int(out[2])}


def on_arm(robots: dict) -> dict | None:
    """The default backend's robot step on ARM cores, per size, on every robot's inputs (robot by robot): for
    aarch64 Linux under qemu-aarch64, the largest difference from the host's plans; for a bare-metal Cortex-M7
    under qemu-system-arm (mps2-an500, -icount shift=0), the same and each step's instructions (its SysTick count
    times the calibration's instructions a tick), its flash and RAM. None where the tools are missing."""
    tools = {"aarch64": (AARCH64_CC, "qemu-aarch64"), "m7": (M7_CC, "qemu-system-arm")}
    have = {k: shutil.which("make") is not None and all(shutil.which(t) for t in v) for k, v in tools.items()}
    if not any(have.values()):
        return None
    out = {"aarch64": [] if have["aarch64"] else None, "m7": [] if have["m7"] else None}
    for size, (problem, inputs, plans) in robots.items():
        n = problem.structure.planned
        ordered, expected = _robot_major(inputs, n), np.concatenate(_robot_major(plans[ROBOT_BACKENDS[0]], n))
        if have["aarch64"]:
            run = _run_exported(ROBOT_BACKENDS[0], problem, ordered, "aarch64-linux",
                                ("qemu-aarch64", "-L", "/usr/aarch64-linux-gnu"),
                                AARCH64_SIZE if shutil.which(AARCH64_SIZE) else None)
            got = np.array(run.stdout.split(), dtype=float)
            out["aarch64"].append({"size": size, "exit": run.returncode, "steps": len(ordered),
                                   "plan_difference_m": float(np.max(np.abs(got - expected))),
                                   "footprint": run.footprint})
            print(f"N_d = {size}: aarch64 under qemu, plans within {out['aarch64'][-1]['plan_difference_m']:.1e} m",
                  file=sys.stderr, flush=True)
        if have["m7"]:
            out["m7"].append(_on_cortex_m7(size, problem, ordered, expected))
    return out


def _on_cortex_m7(size: int, problem, inputs: list, expected: np.ndarray) -> dict:
    with tempfile.TemporaryDirectory() as folder:
        CaptureSolver("distributed", ROBOT_BACKENDS[0]).export(Path(folder), problem, robot=0, target="cortex-m7")
        subprocess.run(["make", "-s", "-C", folder], check=True, capture_output=True, timeout=3600)
        footprint = _sizes(Path(folder) / "capture_step.elf", M7_SIZE)     # with the export's one state
        single = subprocess.run(["make", "-s", "-C", folder, "run"], capture_output=True, text=True, timeout=600)
        report = dict(line.split(maxsplit=1) for line in single.stderr.splitlines() if not line.startswith("ticks"))
        (Path(folder) / "input.txt").write_text("\n".join(" ".join(f"{v:.17g}" for v in x) for x in inputs) + "\n")
        subprocess.run(["make", "-s", "-C", folder], check=True, capture_output=True, timeout=3600)
        run = subprocess.run(["make", "-s", "-C", folder, "run"], capture_output=True, text=True, timeout=3600)
    calibration = [line.split() for line in run.stderr.splitlines() if line.startswith("calibration")][0]
    per_tick = int(calibration[1]) / int(calibration[2])
    ticks = np.array([int(line.split()[1]) for line in run.stderr.splitlines() if line.startswith("ticks")])
    got = np.array(run.stdout.split(), dtype=float)
    row = {"size": size, "exit": run.returncode, "steps": len(inputs), "instructions_per_tick": per_tick,
           "instructions_median": float(np.median(ticks[1:]) * per_tick),
           "instructions_max": float(ticks.max() * per_tick),
           "plan_difference_m": float(np.max(np.abs(got - expected))), **footprint,
           "heap": int(report["heap"]), "stack": int(report["stack"])}
    print(f"N_d = {size}: Cortex-M7 under qemu, {row['instructions_median']:.0f} instructions a step, plans within "
          f"{row['plan_difference_m']:.1e} m", file=sys.stderr, flush=True)
    return row


def rounds_table(states: dict[int, list[HuntState]]) -> list[dict]:
    """Per size of :data:`ROUND_SIZES`, scheme and k of :data:`ROUNDS`: the gap to the centralised optimum."""
    rows = []
    for size in [s for s in ROUND_SIZES if s in states]:
        problems = problems_of(size, states[size])
        optimum = CaptureMPC("stage-sqp", "hpipm")
        mpcs = {("rti", 1): CaptureMPC("rti", "hpipm")}
        for scheme in ("jacobi", "gauss-seidel"):
            for k in ROUNDS:
                mpcs[(scheme, k)] = CaptureMPC("distributed", "hpipm",
                                               formulation_options={"rounds": k, "scheme": scheme})
        steps, best = {key: [] for key in mpcs}, []
        for index, problem in enumerate(problems):
            for key, mpc in mpcs.items():
                if index:                                     # the first, cold, excluded
                    mpc.follow(optimum)                       # from the optimum's closed loop's start
                    steps[key].append(mpc.step(problem))
            plan = optimum.step(problem).plan
            best.append((plan, evaluate(problem, plan).objective))
        for (scheme, k), taken in steps.items():
            gaps, distances = [], []
            for problem, step, (plan, objective) in zip(problems[1:], taken, best[1:]):
                gaps.append((evaluate(problem, step.plan).objective - objective) / abs(objective))
                distances.append(float(np.max(np.abs(step.plan - plan))))
            rows.append({"size": size, "scheme": scheme, "rounds": k, "median_gap": float(np.median(gaps)),
                         "max_gap": float(np.max(gaps)), "max_distance_m": float(np.max(distances)),
                         "failed": sum(not step.solution.success for step in taken)})
            print(f"N_d = {size} {scheme} {k}: gap median {rows[-1]['median_gap']:.2e}", file=sys.stderr,
                  flush=True)
    return rows


def exponent(sizes: list[int], values: list[float]) -> float:
    """The least-squares slope of log(values) on log(sizes); NaN with fewer than two sizes."""
    if len(set(sizes)) < 2:
        return math.nan
    return float(np.polyfit(np.log(sizes), np.log(values), 1)[0])


def readme(results: dict) -> str:
    m, rows = results["machine"], results["growth"]
    sizes = [r["size"] for r in rows]
    lines = ["# How the capture step grows with the team", "",
             f"Regenerate with `{COMMAND}`. Measured in one run on {m['cpu']} ({m['cores']} cores, shared: load "
             f"average {results['load_before'][0]:.1f} before, {results['load_after'][0]:.1f} after), {m['system']}, "
             f"Python {m['python']}, CasADi {m['packages']['casadi']}. The steps took turns on each state; absolute "
             "times drift on a shared machine, the ratios are from the same run.", "",
             f"States: the paper's second scenario with N_d defenders started evenly {START_RADIUS} m from the "
             f"attacker, hunted by the enclose controller (`enclose`, `rti`/`hpipm`, N = {HORIZON}); "
             f"{rows[0]['states']} consecutive states from the first in which a defender pushes the attacker "
             "(within its perception radius), posed as the `enclose` problem. "
             "Medians, the first state (which builds) excluded. *a robot*: its inputs from the round's broadcast "
             "and its step on its loop (`TeamStep.robots[i]`) on the `distributed` formulation's default backend, "
             "`daqp-condensed` (its QP condensed to its 2N controls, DAQP from its last active set, compiled); "
             "*on HPIPM*: the same on `hpipm-codegen` (the stage form, compiled), from the same inputs (both loops "
             "step from the default's plans), and *plans within*: the largest difference between the two loops' "
             "plans; *its HPIPM alone*: the step's own QP linearised apart "
             f"and solved by CasADi's `hpipm` plugin, the fastest of {REPEATS} solves (what the step's QP costs at "
             "best "
             "through CasADi, from Python); *team*: the "
             "state loaded, the broadcast and the slowest robot (the robots in parallel, one Jacobi round); "
             "*centralised*: `CaptureSolver(\"rti\", \"hpipm-codegen\").step_for(problem)`, the state loaded and one "
             "`step()`.", "",
             *markdown.table(
                 ["N_d", "centralised (ms)", "its HPIPM alone (ms)", "ratio", "a robot (ms)", "on HPIPM (ms)",
                  "its HPIPM alone (ms)", "on HPIPM / a robot", "plans within (m)", "broadcast (ms)", "team (ms)",
                  "centralised / team", "neighbour slots", "unseen neighbours", "failed robot QPs"], "r" * 15,
                 ([r["size"], f"{r['central_ms']:.3f}", f"{r['central_hpipm_ms']:.3f}",
                   f"{r['central_ms'] / r['central_hpipm_ms']:.2f}", f"{r['robot_ms']:.3f}",
                   f"{r['robot_hpipm_loop_ms']:.3f}", f"{r['robot_hpipm_ms']:.3f}",
                   f"{r['robot_hpipm_loop_ms'] / r['robot_ms']:.2f}", f"{r['robot_plan_difference_m']:.1e}",
                   f"{r['broadcast_ms']:.3f}", f"{r['team_ms']:.3f}", f"{r['central_ms'] / r['team_ms']:.1f}",
                   r["neighbour_slots"], r["unseen_neighbours"], r["failed_robot_qps"]] for r in rows))]
    lines += ["", "Exponents b of time ∝ N_d^b over N_d = " + ", ".join(map(str, sizes)) + ": centralised "
              f"{exponent(sizes, [r['central_ms'] for r in rows]):.2f}; a robot "
              f"{exponent(sizes, [r['robot_ms'] for r in rows]):.2f}; team "
              f"{exponent(sizes, [r['team_ms'] for r in rows]):.2f}.", ""]
    c = results["exported"]
    if c is None:
        lines += ["A robot's exported step was not measured: no `make` or `gcc` here.", ""]
    else:
        lines += ["**A robot's step exported as C** (`CaptureSolver(\"distributed\", backend).export(folder, "
                  "problem, robot=0)`, built with its Makefile at `-O2`: on `daqp-condensed` with DAQP's own "
                  "sources, on `hpipm-codegen` against CasADi's HPIPM and BLASFEO, the wheel's generic build), run on "
                  "every robot's inputs of every state: median time of one robot's step in pure C, and the largest "
                  "difference from Python's plans on the same backend.", "",
                  *markdown.table(["N_d", "DAQP condensed (ms)", "plans within (m)", "exit", "HPIPM (ms)",
                                   "plans within (m)", "exit", "HPIPM / DAQP"], "r" * 8,
                                  ([r["size"], f"{r['daqp_c_ms']:.4f}", f"{r['daqp_plan_difference_m']:.1e}",
                                    r["daqp_exit"], f"{r['hpipm_c_ms']:.4f}", f"{r['hpipm_plan_difference_m']:.1e}",
                                    r["hpipm_exit"], f"{r['hpipm_c_ms'] / r['daqp_c_ms']:.1f}"] for r in c))]
        slope = exponent([r["size"] for r in c], [r["daqp_c_ms"] for r in c])
        lines += ["", f"Exponent of a robot's C step (DAQP): {slope:.2f}.", ""]
    lines += on_the_board(results)
    lines += targets(results)
    lines += ["## What each round buys", "",
              "From the controller's warm start (the first state, cold, excluded), each step's plan after k "
              "rounds, against the centralised "
              "`stage-sqp` plan (the team's `rti` QP iterated to convergence, in its own closed loop: the team "
              "problem's local optimum): the evaluator's objective, relative gap (negative: lower than the "
              "optimum's, which the linearised steps can reach where their plans break no constraint the "
              "evaluator scores), and the largest distance between the plans. `rti`: one centralised QP. Each "
              "on `hpipm`, on the same states.", "",
              *markdown.table(["N_d", "scheme", "rounds", "median gap", "largest gap", "largest distance (m)",
                               "failed"], "rlrrrrr",
                              ([r["size"], r["scheme"], r["rounds"], f"{r['median_gap']:.2e}", f"{r['max_gap']:.2e}",
                                f"{r['max_distance_m']:.1e}", r["failed"]] for r in results["rounds"]))]
    return "\n".join(lines) + "\n"


def _kib(n: float) -> str:
    return f"{n / 1024:.0f} KiB"


def _memory(footprint: dict | None) -> list[str]:
    """A program's size (text + data) and memory (data + bss) cells; the heap is not in a program's sizes."""
    if footprint is None:
        return ["—", "—"]
    return [_kib(footprint["text"] + footprint["data"]), f"{_kib(footprint['data'] + footprint['bss'])} + heap"]


def on_the_board(results: dict) -> list[str]:
    """The README's ARM sections: the Cortex-M7 per size, and the 50 Hz budget per target."""
    c, arm = results["exported"], results.get("arm")
    lines = []
    m7 = arm and arm.get("m7")
    if m7:
        lines += ["**The same step on a bare-metal Cortex-M7** (`--target cortex-m7`: `arm-none-eabi-gcc -O2 "
                  "-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard`, newlib, no operating system), run by `make run` "
                  "on qemu's mps2-an500 board with `-icount shift=0` on every robot's inputs, robot by robot (each "
                  "step from the last one's working set): each step's instructions (its SysTick count times the "
                  f"instructions a tick of a calibration loop of known length, {m7[0]['instructions_per_tick']:.0f}), "
                  f"and that count as time at {M7_CLOCK_HZ / 1e6:.0f} MHz (an STM32H743's clock) assuming one "
                  "instruction a cycle: an estimate, as an emulator counts instructions, not cycles (the M7 issues "
                  "up to two a cycle; a double division or square root takes several, a cache miss or a flash wait "
                  "state more).", "",
                  *markdown.table(["N_d", "robot steps", "instructions a step (median)", "largest",
                                   f"at {M7_CLOCK_HZ / 1e6:.0f} MHz (ms, median)", "largest (ms)",
                                   "plans within the host's (m)", "exit"], "r" * 8,
                                  ([r["size"], r["steps"], f"{r['instructions_median']:.0f}",
                                    f"{r['instructions_max']:.0f}",
                                    f"{r['instructions_median'] / M7_CLOCK_HZ * 1e3:.3f}",
                                    f"{r['instructions_max'] / M7_CLOCK_HZ * 1e3:.3f}", f"{r['plan_difference_m']:.1e}",
                                    r["exit"]] for r in m7)), ""]
    lines += ["## On the board: the 50 Hz budget", "",
              f"A robot's step on each target, the slowest team size's median (and the largest step of any size), "
              f"its share of a {CYCLE_S * 1e3:.0f} ms cycle, its program's size (text + data) and memory (data + bss; "
              "on the Cortex-M7 also the heap DAQP allocates and the stack's high-water mark, measured on the "
              "board), and its plans' largest difference from the host's (Python's on the host).", ""]
    budget = []
    if c is not None:
        worst = max(r["daqp_c_ms"] for r in c)
        budget.append(["x86-64 (this machine), C", "wall time", f"{worst:.4f} ms",
                       f"{max(r['daqp_c_max_ms'] for r in c):.4f} ms", f"{worst / (CYCLE_S * 1e3):.2%}",
                       *_memory(c[0].get("daqp_footprint")), f"{max(r['daqp_plan_difference_m'] for r in c):.1e}"])
    a64 = arm and arm.get("aarch64")
    if a64:
        budget.append(["aarch64 Linux, qemu-aarch64", "plans only (an emulator's time is not the core's)", "—", "—",
                       "—", *_memory(a64[0].get("footprint")), f"{max(r['plan_difference_m'] for r in a64):.1e}"])
    if m7:
        worst = max(r["instructions_median"] for r in m7) / M7_CLOCK_HZ
        largest = max(r["instructions_max"] for r in m7) / M7_CLOCK_HZ
        budget.append(["Cortex-M7 bare metal, qemu mps2-an500",
                       f"instructions at {M7_CLOCK_HZ / 1e6:.0f} MHz, one a cycle", f"{worst * 1e3:.3f} ms",
                       f"{largest * 1e3:.3f} ms", f"{worst / CYCLE_S:.2%}",
                       f"{_kib(max(x['text'] + x['data'] for x in m7))} flash",
                       f"{_kib(max(x['data'] + x['bss'] + x['heap'] + x['stack'] for x in m7))} RAM",
                       f"{max(x['plan_difference_m'] for x in m7):.1e}"])
    if not (a64 or m7):
        budget.append(["ARM", "not run: no cross compiler or qemu here", *["—"] * 6])
    return lines + markdown.table(["target", "measured as", "a robot's step", "largest", "share of 20 ms", "program",
                                   "memory", "plans within (m)"], "ll" + "r" * 6, budget) + [""]


# The capture stage's targets for teams (N = 10): a robot's step through the loop API, a robot's step in C, the
# growth of a robot's step with the team, the team's step at N_d = 12 with the robots in parallel, and the
# centralised compiled step against HPIPM alone on its own QP.
ROBOT_MS, ROBOT_C_MS, ROBOT_EXPONENT, TEAM_MS, TEAM_SIZE, CENTRAL_OVER_HPIPM = 0.25, 0.1, 0.3, 2.0, 12, 1.3


def targets(results: dict) -> list[str]:
    """The README's targets section: each target, the measured value, met or missed by how much."""
    rows, c = results["growth"], results["exported"]
    sizes = [r["size"] for r in rows]

    def line(what: str, value: float, limit: float, unit: str = " ms") -> str:
        verdict = "met" if value <= limit else f"missed by {value / limit:.3g}×"
        return markdown.row([what, f"≤ {limit:g}{unit}", f"{value:.3f}{unit}", verdict])

    out = ["## Targets", "", *markdown.table(["target", "bound", "measured", ""], "lrrl"),
           line("a robot's step through the loop API, the slowest team size", max(r["robot_ms"] for r in rows),
                ROBOT_MS),
           line("exponent of a robot's step in N_d", exponent(sizes, [r["robot_ms"] for r in rows]),
                ROBOT_EXPONENT, "")]
    if c is not None:
        out.append(line("a robot's step in C, the slowest team size", max(r["daqp_c_ms"] for r in c), ROBOT_C_MS))
    team = [r for r in rows if r["size"] == TEAM_SIZE]
    if team:
        out.append(line(f"the team's step at N_d = {TEAM_SIZE}, the robots in parallel", team[0]["team_ms"], TEAM_MS))
    out.append(line("the centralised compiled step over HPIPM alone on its QP, the largest ratio",
                    max(r["central_ms"] / r["central_hpipm_ms"] for r in rows), CENTRAL_OVER_HPIPM, "×"))
    return out + [""]


def save_states(path: Path, states: dict[int, list[HuntState]]) -> None:
    path.write_text(json.dumps({str(n): [s.to_dict() for s in hunt] for n, hunt in states.items()}) + "\n",
                    encoding="utf-8")


def load_states(path: Path) -> dict[int, list[HuntState]]:
    """The states :func:`save_states` wrote to ``path``, each checked against its team's scenario; a missing or
    damaged file is a one-line DataFileError naming it and the field."""
    fix = f"run {COMMAND} without --reuse-states to draw the states again"
    data = read_json_file(path, fix)
    if not isinstance(data, dict) or not data:
        raise DataFileError(f"{path}: expected a JSON object of team sizes, each a list of states {STATE_FORM}; "
                            f"{fix}")
    states = {}
    for key, hunt in data.items():
        if not (key.isdecimal() and 1 <= int(key) <= MAX_SIZE):
            raise DataFileError(f"{path}: team size {key!r}: not a whole number from 1 to {MAX_SIZE}; {fix}")
        if not (isinstance(hunt, list) and 2 <= len(hunt) <= MAX_STATES):
            raise DataFileError(f"{path}: team size {key}: expected a list of 2 to {MAX_STATES} states; {fix}")
        scenario = team_scenario(int(key))
        states[int(key)] = []
        for i, state in enumerate(hunt):
            try:
                states[int(key)].append(state_from_dict(state, scenario))
            except ScenarioError as exc:
                raise DataFileError(f"{path}: team size {key}, state {i}: {exc}; {fix}") from None
    return states


def plan_agreement(states: dict[int, list[HuntState]]) -> dict[int, float]:
    """Per size, the largest difference between a robot's plans on the default backend and on HPIPM (interpreted:
    its compiled step's plans to the bit) from the same plans, along the default's closed loop: what the growth
    table's *plans within* reports, without the timing."""
    out = {}
    for size, hunt in states.items():
        problems = problems_of(size, hunt)
        mpcs = [CaptureMPC("distributed", b, score=False) for b in (ROBOT_BACKENDS[0], "hpipm")]
        loops = [mpc.solver.step_for(problems[0]) for mpc in mpcs]
        difference = 0.0
        for problem in problems:
            mpcs[1].follow(mpcs[0])                     # the same plans to start from: the default's closed loop
            for mpc in mpcs:
                mpc.loop_step(problem)
            difference = max(difference, float(np.max(np.abs(loops[0].plan - loops[1].plan))))
        out[size] = difference
    return out


CHECKED_FIELDS = {"rounds": ("size", "scheme", "rounds", "median_gap", "max_gap"),
                  "growth": ("size", "robot_plan_difference_m")}   # what --check reads of each row


def results_shape_error(data: object) -> str | None:
    """What keeps ``data`` from being results.json as this study writes it, as far as --check reads it (None: it is
    of that shape)."""
    if not isinstance(data, dict):
        return "expected a JSON object with 'rounds' and 'growth'"
    for key, fields in CHECKED_FIELDS.items():
        rows = data.get(key)
        if not isinstance(rows, list) or not all(isinstance(row, dict) for row in rows):
            return f"{key}: expected a list of objects"
        for i, row in enumerate(rows):
            missing = [name for name in fields if name not in row]
            if missing:
                return f"{key}[{i}]: no {missing[0]!r}"
            if not all(isinstance(row[name], (int, float)) and not isinstance(row[name], bool)
                       for name in fields if name not in ("scheme",)):
                return f"{key}[{i}]: {', '.join(fields)} are numbers (but scheme)"
    return None


def check(out: Path) -> int:
    """The committed rounds table, rerun on the committed states (deterministic, machine-independent: HPIPM on
    the wheel's BLASFEO); the timings are the run's, not checked."""
    fix = f"run {COMMAND} --output {out} to make the results to check"
    committed = read_json_file(out / "results.json", fix)
    wrong = results_shape_error(committed)
    if wrong:
        raise DataFileError(f"{out / 'results.json'}: {wrong}; {fix}")
    states = load_states(out / "states.json")
    errors = []
    fresh = rounds_table(states)
    for old, new in zip(committed["rounds"], fresh):
        for key in ("median_gap", "max_gap"):
            if not math.isclose(old[key], new[key], rel_tol=GAP_TOL, abs_tol=GAP_TOL):
                errors.append(f"rounds N_d = {old['size']} {old['scheme']} {old['rounds']}: {key} {old[key]:.6e} "
                              f"committed, {new[key]:.6e} now")
    for size, difference in plan_agreement({r["size"]: states[r["size"]] for r in committed["growth"]}).items():
        old = next(r["robot_plan_difference_m"] for r in committed["growth"] if r["size"] == size)
        if not (difference <= 10 * old + 1e-12 and old <= 10 * difference + 1e-12):   # the same order: solver tolerance
            errors.append(f"N_d = {size}: a robot's plans on {ROBOT_BACKENDS[0]} within {old:.1e} m of HPIPM's "
                          f"committed, {difference:.1e} m now")
    if len(fresh) != len(committed["rounds"]):
        errors.append(f"rounds: {len(committed['rounds'])} rows committed, {len(fresh)} now")
    try:
        rendered = readme(committed)
    except (KeyError, TypeError, ValueError, IndexError) as exc:     # a field the table reads beyond --check's own
        errors.append(f"results.json: its README does not render ({type(exc).__name__}: {exc})")
    else:
        if rendered != (out / "README.md").read_text(encoding="utf-8"):
            errors.append("README.md is not what results.json renders")
    return check_result(errors, "team_size", COMMAND)


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=output_folder, default=Path(__file__).resolve().parent / "team_size")
    parser.add_argument("--sizes", type=count(MAX_SIZE), nargs="+", default=list(SIZES))
    parser.add_argument("--states", type=count(MAX_STATES), default=STATES,
                        help=f"consecutive states per team size, 2 to {MAX_STATES} (the first sets up and is not timed)")
    parser.add_argument("--reuse-states", action="store_true", help="the states in OUT/states.json")
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args(argv)
    if args.states < 2:
        parser.error(f"--states: at least 2 (the first sets up and is not timed), got {args.states}")
    with stop_at_once("team_size"):             # Ctrl-C: nothing written, the committed files kept
        try:
            if args.check:
                return check(args.output)
            if args.reuse_states:
                states = load_states(args.output / "states.json")
            else:
                states = {n: hunt_states(n, args.states) for n in args.sizes}
            before = load_average()
            growth, robots = timed_sizes(states)
            c = exported(robots)
            results = {"machine": describe_machine(), "load_before": before, "growth": growth, "exported": c,
                       "arm": on_arm(robots), "rounds": rounds_table(states)}
            results["load_after"] = load_average()
        except MpcHuntError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
    args.output.mkdir(parents=True, exist_ok=True)
    save_states(args.output / "states.json", states)
    (args.output / "results.json").write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")
    (args.output / "README.md").write_text(readme(results), encoding="utf-8")
    print(readme(results))
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

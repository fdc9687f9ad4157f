"""The batched engine: why its rules are compiled per hunt, and its speed against the engine before it.

First the choice: one rule both ways, the ``gap`` attacker's heading (the bisector of the widest angular gap
between the defenders it senses), for batches of ``SIZES`` hunts of ``DEFENDERS`` defenders each, some out of
sensing range: (a) NumPy on arrays with a leading hunt axis, the missing defenders masked; (b) the package's
compiled rules (``near`` and ``widest_gap``) called hunt by hunt from a compiled loop over the batch. The two
must agree to 1e-12; the time is µs a hunt, best of ``REPEATS``.

Then the speed: rule-based hunts, ``voronoi`` defenders (3 to 5) against the ``gap`` attacker on the sweep's random scenarios
of seed ``SEED`` (``studies/engine_worker.py``). The engine before the batched one (commit ``BEFORE``, its
``mpc_hunt/`` unpacked from git into a temporary folder) runs ``HUNTS`` of them one by one, as its sweeps did;
the batched engine runs the same hunts in batches of ``BATCH`` (the sweep's, ``mpc_hunt.sweep.runner.BATCH``),
then ``MORE`` hunts for its steady rate. Each engine runs on ``WORKERS`` processes at once, each timed inside
the process once warm (imports, compiled code's cache and a short hunt before the clock starts); a rate is the
hunts of all processes over the slowest process's seconds. The two engines' hunts must end alike (how, and
when): the study stops if one differs. Beside them, a process running one hunt with the compiled rules' cache empty
(compiling them), then one with that cache. Last, ``mpc-hunt sweep`` runs ``SWEEP`` such hunts on ``WORKERS``
processes into a temporary results file, timed whole (the command, start to end) with its rows' exceptions
counted. Then the recommended controller (``TRAP``, a solving one) on ``TRAP_HUNTS`` of the same hunts, one by one on
both engines, and on this one again with the capture step of ``ROUTE``; on this engine each hunt's capture steps
are solved again alone after it (``engine_worker.py --qps``), only the step Function's evaluations timed (the
linearisation and the QP in compiled code: what an engine solving a batch's steps in one call into compiled code,
with no Python per step, would still run), so that a hunt's whole cost is set against its capture steps' (the
most any engine could gain on them is the hunts' seconds before over their steps alone); all of it ``TRAP_RUNS``
times over, one run after another, so that its ratios come with their range (the table is the first run's).
The two engines' ``trap`` hunts are compared, not required to end alike: its reference's sums and powers are
now the C library's in a compiled loop, not NumPy's array operations (whose powers differ from it in the last
bit on this machine), and a hunt is chaotic.
Writes ``studies/engine/results.json`` and README.md, and the three tables in docs/engine.md.

    python studies/engine.py            # measure (about fifteen minutes on two cores), write the results
    python studies/engine.py --check    # the docs' tables and the report are the committed results'
"""

from __future__ import annotations

import io
import json
import math
import os
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser, count
from mpc_hunt.bench.machine import describe_machine, machine_lines
from mpc_hunt.compiled import kernel
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.errors import DataFileError
from mpc_hunt.sweep.runner import BATCH
from mpc_hunt.sweep.store import stored_rows
from mpc_hunt.world.behaviours.base import near
from mpc_hunt.world.behaviours.gap import widest_gap

from studies.docs_block import read_block, write_block
from studies.study_check import check_result, read_json_file, run_study

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "studies" / "engine"
DOCS = ROOT / "docs" / "engine.md"
COMMAND = "python studies/engine.py"
BEFORE = "aba2141bca054dda51a67e3c13d827a12d78ede4"     # the last commit of the engine before the batched one
SEED, HUNTS, MORE, WORKERS, SWEEP, TRAP_HUNTS = 46, 64, 2048, 2, 10_000, 16
TRAP_RUNS = 3       # the solving controller's hunts run this many times over, so its ratios come with their spread
TRAP = ControllerSpec().label       # the recommended controller, a solving one
ROUTE = "trap:rti:daqp-condensed:10"     # its capture stage on the compiled, warm-started DAQP step
REPLAYED = 1e-9     # m: a capture step solved alone plans as in its hunt, to this (the same inputs, the same code)
MAX_HUNTS = 10_000
SIZES, DEFENDERS, SENSING, REPEATS, CHOICE_SEED = (1, 16, 256, 4096), 5, 3.0, 5, 0
WORK = 200_000      # hunt-evaluations a timing of the choice aims at (fewer for a batch of one)


def by_arrays(p_a: np.ndarray, p_d: np.ndarray, radius: float) -> np.ndarray:
    """(a): the heading of every hunt, NumPy on the whole batch."""
    B, n, _ = p_d.shape
    offsets = p_d - p_a[:, None, :]
    seen = np.sqrt(np.sum(offsets**2, axis=-1)) < radius
    bearings = np.sort(np.where(seen, np.arctan2(offsets[..., 1], offsets[..., 0]), np.inf), axis=1)
    k = seen.sum(axis=1)
    following = np.concatenate([bearings[:, 1:], np.full((B, 1), np.inf)], axis=1)
    last = np.arange(n)[None, :] == np.maximum(k - 1, 0)[:, None]
    following = np.where(last, bearings[:, :1] + 2 * math.pi, following)
    with np.errstate(invalid="ignore"):
        widths = np.where(np.arange(n)[None, :] < k[:, None], following - bearings, -np.inf)
    j = np.argmax(widths, axis=1)
    rows = np.arange(B)
    with np.errstate(invalid="ignore"):  # a hunt sensing nobody: inf − inf, masked
        return np.where(k > 0, bearings[rows, j] + 0.5 * widths[rows, j], np.nan)


@kernel
def by_hunt(p_a: np.ndarray, p_d: np.ndarray, radius: float) -> np.ndarray:
    """(b): the heading of every hunt, the package's compiled rules hunt by hunt."""
    out = np.full(p_a.shape[0], np.nan)
    for b in range(p_a.shape[0]):
        sensed = near(p_a[b], p_d[b], radius)
        if sensed.shape[0]:
            start, width = widest_gap(p_a[b], sensed)
            out[b] = start + 0.5 * width
    return out


def best_time(rule, p_a, p_d, repeats: int) -> float:
    """µs a hunt of ``rule`` on the batch, best of ``repeats``."""
    calls = max(1, WORK // len(p_a))
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            rule(p_a, p_d, SENSING)
        best = min(best, (time.perf_counter() - start) / calls / len(p_a))
    return 1e6 * best


def choice(repeats: int) -> dict:
    rng = np.random.default_rng(CHOICE_SEED)
    rows = []
    for size in SIZES:
        p_a = rng.uniform(-5, 5, (size, 2))
        p_d = p_a[:, None, :] + rng.uniform(-4, 4, (size, DEFENDERS, 2))
        a, b = by_arrays(p_a, p_d, SENSING), by_hunt(p_a, p_d, SENSING)
        if not np.allclose(a, b, rtol=0, atol=1e-12, equal_nan=True):
            raise DataFileError("the choice: the two ways of the gap attacker's heading disagree")
        arrays, hunt = best_time(by_arrays, p_a, p_d, repeats), best_time(by_hunt, p_a, p_d, repeats)
        rows.append({"batch": size, "arrays_us": arrays, "compiled_us": hunt})
        print(f"{size}: arrays {arrays:.3f} us, compiled {hunt:.3f} us a hunt", file=sys.stderr, flush=True)
    return {"settings": {"sizes": list(SIZES), "defenders": DEFENDERS, "repeats": repeats, "seed": CHOICE_SEED},
            "rows": rows}


def choice_table(results: dict) -> str:
    rows = [[f"{r['batch']}", f"{r['arrays_us']:.3f}", f"{r['compiled_us']:.3f}",
             f"{r['arrays_us'] / r['compiled_us']:.1f}"] for r in results["rows"]]
    s = results["settings"]
    return "\n".join([f"`{COMMAND}` (the choice: the `gap` attacker's heading, {s['defenders']} defenders a hunt; µs a hunt, "
                      f"best of {s['repeats']}):", "",
                      *markdown.table(["hunts in the batch", "NumPy, hunt axis", "compiled, hunt by hunt",
                                       "NumPy / compiled"], "rrrr", rows)]) + "\n"


def unpacked(commit: str, folder: Path) -> Path:
    """``mpc_hunt/`` of ``commit`` written into ``folder`` (from this repository's git history)."""
    try:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", commit, "mpc_hunt"], capture_output=True,
                                 check=True).stdout
    except (OSError, subprocess.CalledProcessError) as exc:
        raise DataFileError(f"git archive {commit[:12]}: {exc}; the study needs this repository's git history "
                            "(a full clone)") from None
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(folder, filter="data")
    return folder


def side_by_side(path: Path, mode: str, first: int, hunts: int, batch: int, controller: str = "voronoi",
                 qps: bool = False) -> dict:
    """``hunts`` hunts of ``controller`` from ``first`` on ``WORKERS`` processes with ``path`` first on the path:
    their rate and ends (and, with ``qps``, the seconds of their capture steps solved again alone)."""
    share = -(-hunts // WORKERS)
    env = {**os.environ, "PYTHONPATH": str(path)}
    runs = [subprocess.Popen([sys.executable, str(ROOT / "studies" / "engine_worker.py"), "--mode", mode, "--seed",
                              str(SEED), "--first", str(first + k * share + 1), "--count",
                              str(min(share, hunts - k * share)), "--batch", str(batch), "--controller", controller,
                              *(["--qps"] if qps else [])],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
            for k in range(WORKERS) if k * share < hunts]
    outputs = []
    try:
        for r in runs:
            out, err = r.communicate()
            if r.returncode:
                raise DataFileError(f"a {mode} process failed: {err.strip().splitlines()[-1] if err.strip() else '?'}")
            outputs.append(json.loads(out))
    finally:
        for r in runs:
            r.kill()
    seconds = max(o["seconds"] for o in outputs)
    out = {"hunts": hunts, "seconds": seconds, "steps": sum(o["steps"] for o in outputs),
           "hunts_per_s": hunts / seconds, "steps_per_s": sum(o["steps"] for o in outputs) / seconds,
           "process_seconds": sum(o["seconds"] for o in outputs), "ends": [e for o in outputs for e in o["ends"]]}
    if qps:
        calls = [o["one_call"] for o in outputs]
        out |= {"qp_seconds": sum(o["qp_seconds"] for o in outputs), "qps": sum(o["qps"] for o in outputs),
                "replay_difference": max(o["replay_difference"] for o in outputs),
                "qp_seconds_in_hunts": sum(o["qp_seconds_in_hunts"] for o in outputs),
                "one_call": None if None in calls else {"seconds": sum(c["seconds"] for c in calls),
                                                         "difference": max(c["difference"] for c in calls)}}
        if max(out["replay_difference"], 0.0 if out["one_call"] is None else out["one_call"]["difference"]) > REPLAYED:
            raise DataFileError(f"{controller}: a capture step solved alone or in one call planned otherwise than in "
                                "its hunt")
    return out


def outcomes(run: dict) -> None:
    """``run``'s ends replaced by how many hunts ended each way."""
    ends = run.pop("ends")
    run["outcomes"] = {end: sum(e[0] == end for e in ends) for end in
                       ("captured", "attacker_escaped", "time_limit", "non_finite_state")}


def trap_hunts(before_path: Path, hunts: int) -> dict:
    """The recommended controller's hunts (``TRAP``) on both engines, one by one, and on this one the same hunts
    with the capture step of ``ROUTE``; on this engine each hunt's capture steps solved again alone."""
    before = side_by_side(before_path, "one", 0, hunts, 1, TRAP)
    print(f"trap before: {before['hunts_per_s']:.3f} hunts/s", file=sys.stderr, flush=True)
    now = side_by_side(ROOT, "one", 0, hunts, 1, TRAP, qps=True)
    route = side_by_side(ROOT, "one", 0, hunts, 1, ROUTE, qps=True)
    print(f"trap now: {now['hunts_per_s']:.3f} hunts/s, {ROUTE}: {route['hunts_per_s']:.3f}", file=sys.stderr,
          flush=True)
    alike = sum(a == b for a, b in zip(before["ends"], now["ends"]))
    same_outcome = sum(a[0] == b[0] for a, b in zip(before["ends"], now["ends"]))
    route_alike = sum(a == b for a, b in zip(now["ends"], route["ends"]))
    for run in (before, now, route):
        outcomes(run)
    return {"controller": TRAP, "route": ROUTE, "before": before, "now": now, "on_route": route,
            "alike": alike, "same_outcome": same_outcome, "route_alike": route_alike}


def ratios(trap: dict) -> dict:
    """One run's ratios (:func:`trap_hunts`): against the engine before, whole over the steps alone, and the bound
    (the hunts' seconds before over the steps alone now), on the recommended step and on ``ROUTE``'s."""
    before = trap["before"]
    return {f"{prefix}{name}": value for prefix, run in (("", trap["now"]), ("route_", trap["on_route"]))
            for name, value in (("vs_before", run["hunts_per_s"] / before["hunts_per_s"]),
                                ("whole_over_alone", run["process_seconds"] / run["qp_seconds"]),
                                ("bound", before["process_seconds"] / run["qp_seconds"]))} | {
        "alone_over_one_call": trap["now"]["qp_seconds"] / trap["now"]["one_call"]["seconds"]}


def trap_runs(before_path: Path, hunts: int, runs: int) -> dict:
    """:func:`trap_hunts` ``runs`` times over: the first run whole, and every run's :func:`ratios`."""
    every = [trap_hunts(before_path, hunts) for _ in range(runs)]
    return every[0] | {"runs": [ratios(t) for t in every]}


def first_runs() -> dict:
    """Seconds of a process running one short hunt (``engine_worker.py``, one hunt, batch mode) with an empty cache
    of compiled rules (its own ``NUMBA_CACHE_DIR``), then of a second process with that cache: compiling against
    loading."""
    with tempfile.TemporaryDirectory() as folder:
        env = {**os.environ, "PYTHONPATH": str(ROOT), "NUMBA_CACHE_DIR": folder}
        seconds = []
        for _ in range(2):
            start = time.perf_counter()
            subprocess.run([sys.executable, str(ROOT / "studies" / "engine_worker.py"), "--seed", str(SEED)], env=env,
                           check=True, capture_output=True)  # fmt: skip
            seconds.append(time.perf_counter() - start)
    return {"cold_s": seconds[0], "cached_s": seconds[1]}


def sweep(hunts: int) -> dict:
    """``mpc-hunt sweep`` of ``hunts`` of the study's hunts on ``WORKERS`` processes: its seconds, its rows'
    exceptions (cause ``error``) and captures."""
    with tempfile.TemporaryDirectory() as folder:
        db = Path(folder) / "sweep.db"
        start = time.perf_counter()
        run = subprocess.run([sys.executable, "-m", "mpc_hunt.cli", "sweep", "--strategy", "voronoi", "--attacker",
                              "gap", "--hunts", str(hunts), "--seed", str(SEED), "--set", "n_defenders=[3, 5]",
                              "--workers", str(WORKERS), "--output", str(db)], capture_output=True, text=True)
        seconds = time.perf_counter() - start
        if run.returncode:
            raise DataFileError(f"mpc-hunt sweep failed: {run.stderr.strip().splitlines()[-1:]}")
        rows = stored_rows(db)
    return {"hunts": len(rows), "seconds": seconds, "errors": sum(r["cause"] == "error" for r in rows),
            "captured": sum(r["outcome"] == "captured" for r in rows)}


def measure(hunts: int, more: int, swept: int, trapped: int) -> dict:
    with tempfile.TemporaryDirectory() as folder:
        before = side_by_side(unpacked(BEFORE, Path(folder)), "one", 0, hunts, 1)
        print(f"before: {before['hunts_per_s']:.2f} hunts/s", file=sys.stderr, flush=True)
        trap = trap_runs(Path(folder), trapped, TRAP_RUNS)
    now = side_by_side(ROOT, "batch", 0, hunts, BATCH)
    if now["ends"] != before["ends"]:
        differ = [i for i, (a, b) in enumerate(zip(before["ends"], now["ends"])) if a != b]
        raise DataFileError(f"hunts {differ[:10]} end otherwise in the batched engine than before it")
    steady = side_by_side(ROOT, "batch", hunts, more, BATCH)
    print(f"batched: {now['hunts_per_s']:.1f} hunts/s on the same hunts, {steady['hunts_per_s']:.1f} on {more} "
          "more", file=sys.stderr, flush=True)
    for run in (before, now, steady):
        outcomes(run)
    swept_run = sweep(swept)
    print(f"sweep: {swept_run['hunts']} hunts in {swept_run['seconds']:.0f} s, {swept_run['errors']} exceptions",
          file=sys.stderr, flush=True)
    return {"settings": {"seed": SEED, "hunts": hunts, "more": more, "workers": WORKERS, "batch": BATCH,
                         "before": BEFORE, "pair": "voronoi against gap, 3 to 5 defenders"},
            "before": before, "batched": now, "batched_more": steady, "sweep": swept_run, "trap": trap}


def report(results: dict, machine: dict) -> str:
    """The study's README."""
    return "\n".join(["# The batched engine", "", "## The choice: arrays with a hunt axis, or compiled per hunt", "",
                      choice_table(results["choice"]), "## Against the engine before it", "", headline(results),
                      "## Hunts that solve: the trap controller", "", trap_table(results), *machine_lines(machine), ""])


def trap_table(results: dict) -> str:
    """The solving controller's hunts on both engines, beside the time of their capture steps alone."""
    t, s = results["trap"], results["settings"]
    before = t["before"]
    rows = []
    for name, controller, run in (("before the batched engine", t["controller"], before),
                                  ("batched engine", t["controller"], t["now"]),
                                  ("batched engine", t["route"], t["on_route"])):
        alone = run.get("qp_seconds")
        rows.append([name, f"`{controller}`", f"{run['hunts']}", f"{run['seconds']:.1f}", f"{run['hunts_per_s']:.3f}",
                     f"{run['hunts_per_s'] / before['hunts_per_s']:.2f}x",
                     "" if alone is None else f"{1e3 * run['qp_seconds_in_hunts'] / run['qps']:.3f}",
                     "" if alone is None else f"{1e3 * alone / run['qps']:.3f}",
                     "" if alone is None else f"{run['process_seconds'] / alone:.2f}",
                     f"{run['outcomes']['captured']}"])
    now, route = t["now"], t["on_route"]
    replayed = max(now["replay_difference"], route["replay_difference"])
    lines = [f"`{COMMAND}` (the recommended controller against `gap`, 3 to 5 defenders, the first {now['hunts']} "
             f"of the same hunts, {s['workers']} processes, one hunt after another; *step alone*: each hunt's capture "
             "steps solved again after it, alone, from the inputs and warm start each had, only the step Function's "
             "evaluations timed (the linearisation and its QP in compiled code, no Python); *step in the hunt*: the same steps as the hunts timed them; "
             "*whole / steps alone*: the processes' hunting seconds over the steps alone):", "",
             *markdown.table(["engine", "controller", "hunts", "s", "hunts/s", "vs before", "step in the hunt (ms)",
                              "step alone (ms)", "whole / steps alone", "captured"], "llrrrrrrrr", rows), "",
             f"Solved alone, the steps planned as in their hunts (to {replayed:.1g} m). {t['alike']} of "
             f"{now['hunts']} hunts end alike on both engines (how and when), {t['same_outcome']} the same way; on "
             f"the DAQP step {t['route_alike']} end as on HPIPM's. No engine running these capture steps, not even one "
             f"solving a batch's steps in one call into compiled code, can make these hunts more than {before['process_seconds'] / now['qp_seconds']:.1f}x quicker (the hunts' "
             f"seconds before over their steps alone now), {before['process_seconds'] / route['qp_seconds']:.1f}x "
             "on the DAQP step.", "", one_call(now), "", spread(t["runs"])]
    return "\n".join(lines) + "\n"


def one_call(run: dict) -> str:
    """The recommended step's QPs solved alone one by one against the same QPs in one call into compiled code."""
    together = run["one_call"]
    return (f"The same steps solved once more in one call into compiled code, all of a hunt's steps of one structure "
            "at once (CasADi's `map` of the step Function: no Python between them, the most an engine solving a "
            f"batch's QPs in one call could group): {1e3 * together['seconds'] / run['qps']:.3f} ms a step against "
            f"{1e3 * run['qp_seconds'] / run['qps']:.3f} ms one by one ({run['qp_seconds'] / together['seconds']:.2f}x"
            f"), the plans the same to {together['difference']:.0g} m. What one call saves is the call from Python "
            "of each QP, a few microseconds of steps taking milliseconds; so the Python left in a hunt is not the "
            "QPs' calls but the controller around them (its reference, posing, fallbacks and records), which runs "
            "hunt by hunt.")


def spread(runs: list[dict]) -> str:
    """The ratios' range over the study's runs of the same hunts (:func:`ratios`)."""
    def span(key: str, unit: str = "", digits: int = 2) -> str:
        values = [r[key] for r in runs]
        return f"{min(values):.{digits}f}{unit} to {max(values):.{digits}f}{unit}"

    return (f"Over {len(runs)} runs of these hunts in this study, one after another: `{TRAP}` against before "
            f"{span('vs_before', 'x')}, whole / steps alone {span('whole_over_alone')}, the bound "
            f"{span('bound', 'x', 1)}; on the DAQP step {span('route_vs_before', 'x')}, "
            f"{span('route_whole_over_alone')} and {span('route_bound', 'x', 1)}; one by one over one call "
            f"{span('alone_over_one_call')}. The table is the first run.")


def headline(results: dict) -> str:
    s, before = results["settings"], results["before"]
    rows = []
    for name, run in (("before the batched engine, one by one", before),
                      (f"batched ({s['batch']} hunts a batch), the same hunts", results["batched"]),
                      (f"batched, {s['more']} more hunts", results["batched_more"])):
        rows.append([name, f"{run['hunts']}", f"{run['seconds']:.2f}", f"{run['hunts_per_s']:.2f}",
                     f"{run['steps_per_s']:.0f}", f"{run['hunts_per_s'] / before['hunts_per_s']:.0f}x",
                     f"{run['outcomes']['captured']}"])
    lines = [f"`{COMMAND}` ({s['pair']}, the sweep's random scenarios of seed {s['seed']}; {s['workers']} "
             f"processes at once; before: commit `{s['before'][:12]}`; the same hunts end alike in both):", "",
             *markdown.table(["engine", "hunts", "s", "hunts/s", "steps/s", "vs before", "captured"], "lrrrrrr",
                             rows)]
    f = results["first_runs"]
    lines += ["", f"A process running one hunt with the compiled rules' cache empty took {f['cold_s']:.0f} s (compiling "
              f"them), the next, with that cache, {f['cached_s']:.1f} s."]
    w = results["sweep"]
    lines += ["", f"`mpc-hunt sweep --strategy voronoi --attacker gap --hunts {w['hunts']} --seed {s['seed']} --set "
              f"\"n_defenders=[3, 5]\" --workers {s['workers']}`, the whole command: {w['seconds']:.0f} s "
              f"({w['seconds'] / 60:.1f} min) for {w['hunts']} hunts, {w['errors']} exceptions, {w['captured']} "
              "captures."]
    return "\n".join(lines) + "\n"


def write(results: dict, machine: dict) -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "results.json").write_text(json.dumps({"machine": machine, **results}, indent=1) + "\n", encoding="utf-8")
    (OUT / "README.md").write_text(report(results, machine), encoding="utf-8")
    write_block("engine-choice", choice_table(results["choice"]), DOCS)
    write_block("engine-speed", headline(results), DOCS)
    write_block("engine-trap", trap_table(results), DOCS)


def check() -> list[str]:
    committed = read_json_file(OUT / "results.json", f"rerun {COMMAND}")
    if not isinstance(committed, dict) or not {"settings", "before", "batched", "batched_more", "sweep", "choice",
                                               "first_runs", "machine", "trap"} <= set(committed) \
            or not isinstance(committed["trap"], dict) or "runs" not in committed["trap"]:
        return [f"studies/engine/results.json: not the study's results (rerun {COMMAND})"]
    errors = []
    s = committed["settings"]
    if (s.get("seed"), s.get("workers"), s.get("batch"), s.get("before")) != (SEED, WORKERS, BATCH, BEFORE):
        errors.append("results.json: measured with other settings than the study's")
    if read_block("engine-speed", DOCS) != headline(committed):
        errors.append("docs/engine.md: its table of the speed is not the committed results'")
    if read_block("engine-trap", DOCS) != trap_table(committed):
        errors.append("docs/engine.md: its table of the trap controller's hunts is not the committed results'")
    if read_block("engine-choice", DOCS) != choice_table(committed["choice"]):
        errors.append("docs/engine.md: its table of the choice is not the committed results'")
    if (OUT / "README.md").read_text(encoding="utf-8") != report(committed, committed["machine"]):
        errors.append("studies/engine/README.md: not the committed results' report")
    return errors


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hunts", type=count(MAX_HUNTS), default=HUNTS,
                        help=f"hunts run by both engines (default {HUNTS})")
    parser.add_argument("--more", type=count(MAX_HUNTS), default=MORE,
                        help=f"more hunts for the batched engine's steady rate (default {MORE})")
    parser.add_argument("--sweep", type=count(MAX_HUNTS), default=SWEEP,
                        help=f"hunts of the timed sweep (default {SWEEP})")
    parser.add_argument("--trap-hunts", type=count(MAX_HUNTS), default=TRAP_HUNTS,
                        help=f"hunts of the recommended controller run by both engines (default {TRAP_HUNTS})")
    parser.add_argument("--check", action="store_true", help="check the docs' table against the committed results")
    args = parser.parse_args(argv)
    if args.check:
        return check_result(check(), "studies/engine", COMMAND)
    chosen, first = choice(REPEATS), first_runs()
    print(f"first run {first['cold_s']:.1f} s, cached {first['cached_s']:.1f} s", file=sys.stderr, flush=True)
    measured = measure(args.hunts, args.more, args.sweep, args.trap_hunts)
    write({"choice": chosen, "first_runs": first, **measured}, describe_machine())
    print(f"wrote {OUT / 'README.md'} and the table of docs/engine.md")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

"""The machine's own noise in CPU time: one fixed piece of work, timed as the own loop times a step, again and again.

The own loop (studies/realtime.py) counts a step past its limit "on the CPU" when the time the process ran exceeds
the limit, its time off the CPU and the hypervisor's steal apart. That reading is only as steady as the machine:
this study times one fixed workload (``WORK``: about 15 ms, NumPy products and a Python loop, as a control step
mixes them; ``time.thread_time``, as mpc_hunt/solving/step_timing.py reads it) for ``SECONDS`` seconds, first in
one process, then in two side by side (as the realtime study runs its hunts, two workers on the two cores), and
reports how far above its median the same work's CPU time went. Writes ``studies/cpu_noise/results.json`` and
README.md, and the line of docs/benchmarks.md that quotes it.

    python studies/cpu_noise.py [--seconds 60]    # measure (2 x --seconds), write the results and the docs' line
    python studies/cpu_noise.py --check           # the README and the docs' line are the committed results'
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser, count
from mpc_hunt.bench.machine import describe_machine, machine_lines
from mpc_hunt.interrupt import stop_at_once
from mpc_hunt.workers import run_local
from studies.docs_block import read_block, write_block
from studies.study_check import check_result, read_json_file, run_study

OUT = Path(__file__).resolve().parent / "cpu_noise"
COMMAND = "python studies/cpu_noise.py"
SECONDS = 60
PROCESSES = (1, 2)
WORK = (60, 720, 150)     # matrix size, products, Python additions between two products
COLUMNS = ("processes", "runs", "median ms", "p99 − median ms", "max − median ms", "> +1 ms", "> +5 ms")


def work(size: int, products: int, additions: int) -> float:
    """The fixed workload; its result, so that nothing is optimised away."""
    rng = np.random.default_rng(0)
    a, b = rng.standard_normal((size, size)), rng.standard_normal((size, size))
    total = 0.0
    for _ in range(products):
        a = np.tanh(a @ b * 0.01)
        for v in range(additions):
            total += v * 0.5
    return total + float(a[0, 0])


def timed(seconds: float) -> list[float]:
    """The workload's CPU times (s), run again and again for ``seconds`` of the wall clock."""
    for _ in range(3):
        work(*WORK)
    times, end = [], time.perf_counter() + seconds
    while time.perf_counter() < end:
        start = time.thread_time()
        work(*WORK)
        times.append(time.thread_time() - start)
    return times


def measure(seconds: int) -> list[dict]:
    rows = []
    for processes in PROCESSES:
        times = np.concatenate(list(run_local([seconds] * processes, timed, processes)))
        median = float(np.median(times))
        rows.append({
            "processes": processes, "runs": int(times.size), "median_s": median,
            "p99_over_s": float(np.percentile(times, 99) - median), "max_over_s": float(times.max() - median),
            "share_over_1ms": float(np.mean(times > median + 1e-3)),
            "share_over_5ms": float(np.mean(times > median + 5e-3)),
        })
    return rows


def table(rows: list[dict]) -> list[str]:
    return markdown.table(COLUMNS, "rrrrrrr", ([
        r["processes"], r["runs"], f"{r['median_s'] * 1e3:.1f}", f"{r['p99_over_s'] * 1e3:.1f}",
        f"{r['max_over_s'] * 1e3:.1f}", f"{r['share_over_1ms']:.0%}", f"{r['share_over_5ms']:.1%}"] for r in rows))


def headline(results: dict) -> str:
    """The docs' line: the two-process row, the realtime study's setting."""
    r = next(r for r in results["rows"] if r["processes"] == 2)
    return (f"the same {r['median_s'] * 1e3:.0f} ms of work, timed the same way two at a time, took more than 5 ms "
            f"more CPU time than its median in {r['share_over_5ms']:.1%} of {r['runs']:,} runs, up to "
            f"{r['max_over_s'] * 1e3:.0f} ms more")


def readme(results: dict) -> str:
    s = results["settings"]
    return "\n".join([
        "# The machine's own noise in CPU time", "",
        f"Regenerate with `{COMMAND} --seconds {s['seconds']}`. One fixed workload (NumPy products of "
        f"{s['work'][0]} x {s['work'][0]} matrices and a Python loop, {s['work'][1]} rounds) timed with "
        f"`time.thread_time` for {s['seconds']} s, in one process, then in two side by side; each row: how far "
        "above its median the same work's CPU time went.", "",
        "## Machine", "", *machine_lines(results["machine"]), "", "## Results", "", *table(results["rows"]), "",
        f"In the realtime study's setting: {headline(results)}.", "",
    ])


def write(results: dict) -> None:
    OUT.mkdir(exist_ok=True)
    (OUT / "results.json").write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")
    (OUT / "README.md").write_text(readme(results), encoding="utf-8")
    write_block("cpu-noise", headline(results))


def check() -> list[str]:
    committed = read_json_file(OUT / "results.json", f"rerun {COMMAND}")
    try:
        if [r["processes"] for r in committed["rows"]] != list(PROCESSES) or committed["settings"]["work"] != list(WORK):
            return ["results.json: not the processes and workload the study measures"]
        text, line = readme(committed), headline(committed)
    except (KeyError, TypeError, StopIteration) as exc:     # a file of another form, or damaged
        return [f"results.json: not this study's results ({type(exc).__name__}: {exc})"]
    errors = []
    if (OUT / "README.md").read_text(encoding="utf-8") != text:
        errors.append("studies/cpu_noise/README.md: not the committed results' text")
    if read_block("cpu-noise") != line:
        errors.append("docs/benchmarks.md: its line on the machine's noise is not the committed results'")
    return errors


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=count(3600), default=SECONDS, help="seconds each setting runs (1 to 3600)")
    parser.add_argument("--check", action="store_true", help="check the README and the docs' line")
    args = parser.parse_args(argv)
    if args.check:
        return check_result(check(), "studies/cpu_noise", COMMAND)
    with stop_at_once("cpu_noise study"):   # nothing is written before the measurement has ended
        rows = measure(args.seconds)
    results = {"machine": describe_machine(), "settings": {"seconds": args.seconds, "work": list(WORK)}, "rows": rows}
    write(results)
    print("\n".join(table(results["rows"])))
    print(f"wrote {OUT / 'README.md'} and the line of docs/benchmarks.md")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

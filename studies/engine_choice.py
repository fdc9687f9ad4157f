"""Why the engine's rules are compiled per hunt (Numba) rather than written as NumPy arrays with a hunt axis.

One rule both ways, the ``gap`` attacker's heading (the bisector of the widest angular gap between the defenders
it senses, :mod:`mpc_hunt.world.behaviours.gap`), for batches of ``SIZES`` hunts of ``DEFENDERS`` defenders each,
some out of sensing range: (a) NumPy on arrays with a leading hunt axis, the missing defenders masked (sorted
bearings, the gaps, their widest, all as whole-batch array operations); (b) the package's compiled rules
(``near`` and ``widest_gap``) called hunt by hunt from a compiled loop over the batch. The two must agree to
1e-12; the time is µs a hunt, best of ``REPEATS``. Writes ``studies/engine_choice/results.json`` and the table
in docs/engine.md.

    python studies/engine_choice.py           # measure (about ten seconds)
    python studies/engine_choice.py --check   # the docs' table is the committed results'
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

if __name__ == "__main__":      # run as a script: the studies import one another as the package `studies`
    sys.path[0] = str(Path(__file__).resolve().parents[1])

import numpy as np

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser
from mpc_hunt.bench.machine import describe_machine, machine_lines
from mpc_hunt.compiled import kernel
from mpc_hunt.world.behaviours.base import near
from mpc_hunt.world.behaviours.gap import widest_gap

from studies.docs_block import read_block, write_block
from studies.study_check import check_result, read_json_file, run_study

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "studies" / "engine_choice"
DOCS = ROOT / "docs" / "engine.md"
COMMAND = "python studies/engine_choice.py"
SIZES, DEFENDERS, SENSING, REPEATS, SEED = (1, 16, 256, 4096), 5, 3.0, 5, 0
WORK = 200_000      # hunt-evaluations a measurement aims at (fewer for a batch of one)


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


def measure(repeats: int) -> dict:
    rng = np.random.default_rng(SEED)
    rows = []
    for size in SIZES:
        p_a = rng.uniform(-5, 5, (size, 2))
        p_d = p_a[:, None, :] + rng.uniform(-4, 4, (size, DEFENDERS, 2))
        a, b = by_arrays(p_a, p_d, SENSING), by_hunt(p_a, p_d, SENSING)
        if not np.allclose(a, b, rtol=0, atol=1e-12, equal_nan=True):
            raise SystemExit("the two ways disagree")
        arrays, hunt = best_time(by_arrays, p_a, p_d, repeats), best_time(by_hunt, p_a, p_d, repeats)
        rows.append({"batch": size, "arrays_us": arrays, "compiled_us": hunt})
        print(f"{size}: arrays {arrays:.3f} us, compiled {hunt:.3f} us a hunt", file=sys.stderr, flush=True)
    return {"settings": {"sizes": list(SIZES), "defenders": DEFENDERS, "repeats": repeats, "seed": SEED},
            "rows": rows}


def headline(results: dict) -> str:
    rows = [[f"{r['batch']}", f"{r['arrays_us']:.3f}", f"{r['compiled_us']:.3f}",
             f"{r['arrays_us'] / r['compiled_us']:.1f}"] for r in results["rows"]]
    s = results["settings"]
    return "\n".join([f"`{COMMAND}` (the `gap` attacker's heading, {s['defenders']} defenders a hunt; µs a hunt, "
                      f"best of {s['repeats']}):", "",
                      *markdown.table(["hunts in the batch", "NumPy, hunt axis", "compiled, hunt by hunt",
                                       "NumPy / compiled"], "rrrr", rows)]) + "\n"


def check() -> list[str]:
    committed = read_json_file(OUT / "results.json", f"rerun {COMMAND}")
    if not isinstance(committed, dict) or "rows" not in committed or "settings" not in committed:
        return ["studies/engine_choice/results.json: not the study's results"]
    return [] if read_block("engine-choice", DOCS) == headline(committed) else \
        ["docs/engine.md: its table of the choice is not the committed results'"]


def main(argv: list[str] | None = None) -> int:
    parser = CommandParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="check the docs' table against the committed results")
    args = parser.parse_args(argv)
    if args.check:
        return check_result(check(), "studies/engine_choice", COMMAND)
    results = measure(REPEATS)
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "results.json").write_text(json.dumps({"machine": describe_machine(), **results}, indent=1) + "\n",
                                      encoding="utf-8")
    (OUT / "README.md").write_text("\n".join(["# Arrays with a hunt axis, or compiled hunt by hunt", "",
                                              headline(results), *machine_lines(describe_machine()), ""]),
                                   encoding="utf-8")
    write_block("engine-choice", headline(results), DOCS)
    print(f"wrote {OUT / 'results.json'} and the table of docs/engine.md")
    return 0


if __name__ == "__main__":
    sys.exit(run_study(main))

"""What the sweep studies (``attackers.py``, ``team_sweep.py``) share: their common options, running hunts into a
results file, the end of a run (a stop's exit status, or the report with the machine: ``sweep.py``'s too), and the
hunts their --check reruns."""

from __future__ import annotations

import statistics
import sys
from pathlib import Path
from typing import Callable

from mpc_hunt import markdown
from mpc_hunt.arguments import CommandParser, cores_count, count, output_folder, seed as seed_number
from mpc_hunt.bench.machine import describe_machine, load_average
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.sweep.runner import Hunt, run_hunt
from mpc_hunt.sweep.store import SweepStore, self_contained
from mpc_hunt.sweep.stored_run import run_into
from mpc_hunt.world.behaviours import BEHAVIOURS

from studies.previous_rows import keep, kept_path

PROGRESS_EVERY = 20     # hunts between two progress lines
NOTHING_RAN = "no hunt ran: nothing to report"      # why a study whose results file stays empty stops
MAX_HUNTS = 1000        # the most hunts a sweep study's --hunts asks for


def add_study_options(parser: CommandParser, hunts: int, what: str, seed: int, out: Path) -> None:
    """A sweep study's --hunts (default ``hunts``, ``what`` they are), --seed (default ``seed``), --output (default
    ``out``, a folder of studies/), --workers (default: one a core), --check and --keep-previous."""
    parser.add_argument("--hunts", type=count(MAX_HUNTS), default=hunts, help=f"{what} (default {hunts})")
    parser.add_argument("--workers", type=cores_count, default=None,
                        help="worker processes (default: one a core; 1 leaves the other cores free)")
    parser.add_argument("--seed", type=seed_number, default=seed, help=f"the sweep's seed (default {seed})")
    parser.add_argument("--output", type=output_folder, default=out,
                        help=f"the folder to write (default studies/{out.name})")
    what = parser.add_mutually_exclusive_group()
    what.add_argument("--check", action="store_true", help="check the committed results against the code")
    what.add_argument("--keep-previous", action="store_true",
                        help="keep the rows of the output folder's results files beside them (before a rerun at "
                             "another size replaces them), for the rerun's report to set beside its own")


def keep_previous(dbs: list[Path]) -> int:
    """--keep-previous: the rows of the results files ``dbs`` kept (:func:`studies.previous_rows.keep`), one line
    each; 0."""
    for db, count in zip(dbs, keep(dbs)):
        print(f"kept {count} rows of {db} in {kept_path(db)}")
    return 0


def run_file(db: Path, arguments: dict, hunts: list[Hunt], workers: int | None = None) -> str | None:
    """The hunts of ``hunts`` not yet in ``db`` (a sweep results file of ``arguments``, resumed if it exists) run
    into it on ``workers`` processes (None: one a core); then the file made self-contained. None when all finished, else why it stopped
    (:func:`mpc_hunt.sweep.stored_run.run_into`; NOTHING_RAN when the file holds no hunt, so that a study that ran
    nothing never reports success)."""
    store = SweepStore(db, arguments, resume=db.exists())
    try:
        work = missing(hunts, store.done())
        print(f"{db.name}: {len(work)} hunts to run", file=sys.stderr)

        def progress(finished: int) -> None:
            if finished % PROGRESS_EVERY == 0:
                print(f"{db.name}: {finished} / {len(work)}", file=sys.stderr, flush=True)

        stopped = run_into(store, work, workers, update=progress)
        if not stopped and not store.done():
            stopped = NOTHING_RAN
    finally:
        store.close()
    self_contained(db)
    return stopped


def measured_run(output: Path, run: Callable[[], int], write: Callable[[dict], None], wrote: str | Path,
                 error: str = "error") -> int:
    """A sweep study's run and report into the folder ``output`` (made if need be): ``run()`` gives an exit status
    (0: every hunt finished); on 0, ``write(machine)`` of the report, the machine described before the run and its
    load average after, then "wrote ``wrote``". An error of the toolkit's in the run is one line on stderr
    ("``error``: the message"), status 2."""
    output.mkdir(parents=True, exist_ok=True)
    machine = describe_machine()
    try:
        code = run()
    except MpcHuntError as exc:
        print(f"{error}: {exc}", file=sys.stderr)
        return 2
    if code:
        return code
    machine["load_average_end"] = load_average()
    write(machine)
    print(f"wrote {wrote}")
    return 0


def stop_status(stopped: str | None, script: str, where: Path) -> int:
    """The exit status of a run that stopped for ``stopped`` (:func:`run_file`'s; None: every hunt finished, 0).
    No hunt ran: one line on stderr, ``script`` naming the study, 2; else one line saying the finished hunts are in
    ``where``, 130 when interrupted, else 2."""
    if stopped == NOTHING_RAN:
        print(f"{script}: error: {stopped}", file=sys.stderr)
        return 2
    if stopped:
        print(f"{stopped}: finished hunts are in {where}; rerun to continue", file=sys.stderr)
        return 130 if stopped == "interrupted" else 2
    return 0


def missing(hunts: list[Hunt], done: set[tuple]) -> list[Hunt]:
    """The hunts whose key (strategy, attacker, belief, seed, index: :meth:`SweepStore.done`) is not in ``done``."""
    return [h for h in hunts if (h.strategy, h.attacker, h.belief, h.seed, h.index) not in done]


def keys(rows: list[dict]) -> set[tuple]:
    """The keys of stored rows, as :meth:`SweepStore.done` gives them."""
    return {(r["strategy"], r["attacker"], r["belief"], r["seed"], r["index"]) for r in rows}


def quickest_captures(rows: list[dict], strategy: str, belief: str = "exact") -> list[dict]:
    """Per attacker, ``strategy``'s quickest capture with ``belief``: the hunts a --check reruns. The quickest is
    the farthest from the time limit, so a last-bit difference moves its time, not its outcome (an exact rerun
    of every figure would need the ensemble the sweep study keeps)."""
    out = []
    for attacker in BEHAVIOURS:
        won = [r for r in rows if (r["strategy"], r["attacker"], r["belief"], r["outcome"]) ==
               (strategy, attacker, belief, "captured")]
        if won:
            out.append(min(won, key=lambda r: (r["capture_time_s"], r["index"])))
    return out


def still_captured(rows: list[dict], seed: int, ranges: dict, file: str) -> list[str]:
    """Each of ``rows`` (captures) run again: what no longer captures."""
    errors = []
    for row in rows:
        new = run_hunt(Hunt(row["strategy"], seed, row["index"], ranges, attacker=row["attacker"],
                            belief=row["belief"]))
        if new["outcome"] != "captured":
            errors.append(f"{row['strategy']} against {row['attacker']}, hunt {row['index']}: captured at "
                          f"{row['capture_time_s']:.1f} s in {file}, now {new['outcome']} ({new['cause']})")
    return errors


def costs(rows: list[dict], whole: str = "the study") -> list[str]:
    """What a cell costs: the mean seconds of one core a hunt (its ``wall_time_s``; a batched controller's hunt, its
    share of its batch by steps), strategy × attacker, exact belief; then each strategy's total and that of every row
    of ``rows`` (``whole``: what they are, in the last sentence)."""
    cells: dict[tuple[str, str], list[float]] = {}
    for r in rows:
        if r["belief"] == "exact":
            cells.setdefault((r["strategy"], r["attacker"]), []).append(r["wall_time_s"])
    strategies = sorted({s for s, _ in cells})
    body = [[a, *(f"{statistics.fmean(cells[s, a]):.2f}" if (s, a) in cells else "" for s in strategies)]
            for a in BEHAVIOURS if any((s, a) in cells for s in strategies)]
    totals = {s: sum(sum(v) for (t, _), v in cells.items() if t == s) for s in strategies}
    return ["Seconds of one core a hunt (mean of the cell's hunts, exact belief; a batched controller's hunt is its "
            "share of its batch's time by its steps):", "",
            *markdown.table(["attacker", *(f"`{s}`" for s in strategies)], "l" + "r" * len(strategies), body), "",
            "Each strategy's hunts, exact belief, in core-hours: " +
            ", ".join(f"`{s}` {totals[s] / 3600:.2f}" for s in strategies) +
            f"; every row of {whole}: {sum(r['wall_time_s'] for r in rows) / 3600:.2f}.", ""]

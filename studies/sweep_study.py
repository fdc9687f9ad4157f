"""What the sweep studies (``attackers.py``, ``team_sweep.py``) share: running hunts into a results file, and the
hunts their --check reruns."""

from __future__ import annotations

import sys
from pathlib import Path

from mpc_hunt.sweep.runner import Hunt, run_hunt
from mpc_hunt.sweep.store import SweepStore, self_contained
from mpc_hunt.sweep.stored_run import run_into
from mpc_hunt.world.behaviours import BEHAVIOURS

PROGRESS_EVERY = 20     # hunts between two progress lines
NOTHING_RAN = "no hunt ran: nothing to report"      # why a study whose results file stays empty stops


def run_file(db: Path, arguments: dict, hunts: list[Hunt]) -> str | None:
    """The hunts of ``hunts`` not yet in ``db`` (a sweep results file of ``arguments``, resumed if it exists) run
    into it; then the file made self-contained. None when all finished, else why it stopped
    (:func:`mpc_hunt.sweep.stored_run.run_into`; NOTHING_RAN when the file holds no hunt, so that a study that ran
    nothing never reports success)."""
    store = SweepStore(db, arguments, resume=db.exists())
    try:
        work = missing(hunts, store.done())
        print(f"{db.name}: {len(work)} hunts to run", file=sys.stderr)

        def progress(finished: int) -> None:
            if finished % PROGRESS_EVERY == 0:
                print(f"{db.name}: {finished} / {len(work)}", file=sys.stderr, flush=True)

        stopped = run_into(store, work, update=progress)
        if not stopped and not store.done():
            stopped = NOTHING_RAN
    finally:
        store.close()
    self_contained(db)
    return stopped


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

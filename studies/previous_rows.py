"""A sweep study's last run kept beside its rerun: the rows of the hunts both ran, set side by side.

Before a study is rerun at another size (or on a changed engine) and its results file replaced, ``keep`` writes
the old file's rows, the fields of :data:`FIELDS` only, beside it (:func:`kept_path`: ``sweep.db``'s in
``sweep.previous.json``). The rerun's report then counts, per strategy, the hunts both runs ran (same strategy,
attacker, belief, seed and draw): those alike to the last bit in every field, those with the same outcome, and
those whose outcome changed, listed (:data:`WHY` a row can differ); and sets the paired differences of the
study's pairs of strategies on the last run beside this run's (:func:`against_last_run`).
"""

from __future__ import annotations

import json
from pathlib import Path

from mpc_hunt import markdown
from mpc_hunt.errors import DataFileError
from mpc_hunt.sweep.paired import cell, paired_counts, summary
from mpc_hunt.sweep.store import stored_rows

from studies.study_check import read_json_file

KEY = ("strategy", "attacker", "belief", "seed", "index")
FIELDS = (*KEY, "comfortable", "outcome", "cause", "capture_time_s", "path_length_m", "min_obstacle_clearance_m",
          "min_defender_separation_m", "steps")
LISTED = 12     # the changed outcomes listed by name; the rest counted
WHY = ("A hunt is deterministic given its seed, so a row that differs comes from a change of the code (a rule, or "
       "the order of its floating-point operations), not from chance.")


def kept_path(db: Path) -> Path:
    """Where the rows of the results file ``db`` are kept."""
    return db.with_name(f"{db.stem}.previous.json")


def keep(dbs: list[Path]) -> list[int]:
    """Each results file's rows (:data:`FIELDS`) written to its :func:`kept_path`; how many each. Refused, before
    any is written, where a file is missing or rows are kept already (a DataFileError: those may be the only copy
    of a run's rows)."""
    for db in dbs:
        if kept_path(db).exists():
            raise DataFileError(f"{kept_path(db)} already holds a run's rows; move it away first")
        if not db.exists():
            raise DataFileError(f"{db} does not exist; nothing to keep")
    counts = []
    for db in dbs:
        rows = sorted(([r[f] for f in FIELDS] for r in stored_rows(db)), key=lambda r: [str(v) for v in r[:5]])
        kept_path(db).write_text(json.dumps({"fields": list(FIELDS), "rows": rows}) + "\n", encoding="utf-8")
        counts.append(len(rows))
    return counts


def read(db: Path) -> list[dict] | None:
    """The rows kept of the results file ``db`` (None: none kept); a damaged file is a one-line DataFileError."""
    path = kept_path(db)
    if not path.exists():
        return None
    data = read_json_file(path, "write it again with --keep-previous from the last run's sweep.db, or remove it")
    try:
        fields, rows = data["fields"], data["rows"]
        if list(fields) != list(FIELDS) or any(len(r) != len(FIELDS) for r in rows):
            raise ValueError
        return [dict(zip(FIELDS, r)) for r in rows]
    except (KeyError, TypeError, ValueError):
        raise DataFileError(f"{path}: not a previous run's rows (fields {', '.join(FIELDS)}); write it again with "
                            "--keep-previous from the last run's sweep.db") from None


def _key(row: dict) -> tuple:
    return tuple(row[k] for k in KEY)


def _alike(a: dict, b: dict) -> bool:
    return all(a[f] == b[f] for f in FIELDS)


def again(rows: list[dict], previous: list[dict]) -> list[str]:
    """Markdown: per strategy, the hunts both runs ran, how many alike to the last bit, how many with the same
    outcome and the capture times' largest move among those captured both times, how many outcomes changed each
    way; then the changed hunts (the first :data:`LISTED` by name)."""
    now = {_key(r): r for r in rows}
    both = [(p, now[_key(p)]) for p in previous if _key(p) in now]
    if not both:
        return ["No hunt of the last run was run again.", ""]
    body, changed = [], []
    for strategy in dict.fromkeys(p["strategy"] for p, _ in both):
        mine = [(p, n) for p, n in both if p["strategy"] == strategy]
        same = [(p, n) for p, n in mine if p["outcome"] == n["outcome"]]
        moves = [abs(n["capture_time_s"] - p["capture_time_s"]) for p, n in same if p["outcome"] == "captured"]
        won = sum(p["outcome"] != "captured" and n["outcome"] == "captured" for p, n in mine)
        lost = sum(p["outcome"] == "captured" and n["outcome"] != "captured" for p, n in mine)
        changed += [(p, n) for p, n in mine if p["outcome"] != n["outcome"]]
        body.append([f"`{strategy}`", len(mine), sum(_alike(p, n) for p, n in mine), len(same),
                     f"{max(moves):.2f} s" if moves else "–", won, lost])
    lines = markdown.table(["strategy", "hunts run again", "alike to the last bit", "same outcome",
                            "largest capture-time move (captured both times)", "now captured", "no longer captured"],
                           "lrrrrrr", body) + [""]
    if changed:
        shown = [f"`{p['strategy']}` against `{p['attacker']}` ({p['belief']}), draw {p['index']}: "
                 f"{_outcome(p)} then, {_outcome(n)} now" for p, n in changed[:LISTED]]
        more = len(changed) - LISTED
        lines += ["Outcomes changed:", "", *(f"- {s}" for s in shown),
                  *([f"- and {more} more (the kept rows against the results file)"] if more > 0 else []), ""]
    return lines


def _outcome(row: dict) -> str:
    if row["outcome"] == "captured":
        return f"captured at {row['capture_time_s']:.1f} s"
    return f"{row['outcome']} ({row['cause']})"


def against_last_run(rows: list[dict], previous: list[dict], pairs: list[tuple[str, str]], attackers,
                     where) -> list[str]:
    """Markdown: per attacker, each pair's (first, second) paired difference (:mod:`mpc_hunt.sweep.paired`) on
    the last run's rows (``previous``) and on this run's, among the rows ``where(attacker)`` keeps: what the rerun
    tells apart that the last did not."""
    body = [[attacker, *(cell(summary(paired_counts(run, first, second, where(attacker))))
                         for first, second in pairs for run in (previous, rows))] for attacker in attackers]
    return markdown.table(["attacker", *(f"`{first}` − `{second}`, {when}" for first, second in pairs
                                         for when in ("last run", "now"))], "l" * (1 + 2 * len(pairs)), body) + [""]

"""A sweep's results file: SQLite, one row per finished hunt, written as each hunt finishes.

Tables: ``sweep`` (one row: ``arguments``, the JSON of what the sweep runs,
and ``numpy``, the version that drew its scenarios) and ``hunts`` (one row per
hunt, the columns of :data:`COLUMNS`, key (strategy, attacker, belief, seed,
"index"); see docs/robustness.md). WAL mode and one commit per row: a killed
process loses at most the hunts still running, and a resumed sweep (``resume``) skips
every key present.

A file of the previous version (no ``attacker`` and ``belief`` columns, no
``attackers`` and ``beliefs`` arguments) ran the paper's attacker with the
exact belief only: it is read, and resumed, as such (:data:`LEGACY`).

    sqlite3 sweep.db "select strategy, outcome, count(*) from hunts group by 1, 2"
"""

from __future__ import annotations

import json
import sqlite3
from dataclasses import fields
from pathlib import Path

import numpy as np

from mpc_hunt.errors import MpcHuntError, SettingError, field_name
from mpc_hunt.world.behaviours import DEFAULT_BEHAVIOUR
from mpc_hunt.world.belief import Belief
from mpc_hunt.world.scenario import HuntParameters

KEY = ("strategy", "attacker", "belief", "seed", "index")
LEGACY = {"attacker": DEFAULT_BEHAVIOUR, "belief": Belief().label()}  # what a previous version's rows ran
ARGUMENTS = {"strategies": list, "attackers": list, "beliefs": list, "hunts": int, "seed": int, "ranges": dict}

SCENARIO_COLUMNS = {  # mpc_hunt.sweep.scenario_row.scenario_row
    "name": "text",
    "seed": "integer",
    "index": "integer",
    "n_defenders": "integer",
    "n_obstacles": "integer",
    "capturable_by_definition": "integer",
    "reachable": "integer",
    "comfortable": "integer",
    "edge_race_lost": "integer",
    "defender_speed_min": "real",
    "defender_speed_max": "real",
    "attacker_speed": "real",
    "speed_ratio": "real",
    "perception_radius": "real",
    "attacker_heading": "real",
    "attacker_start_x": "real",
    "attacker_start_y": "real",
    "obstacle_radius_min": "real",
    "obstacle_radius_max": "real",
    "arena_x_min": "real",
    "arena_y_min": "real",
    "arena_x_max": "real",
    "arena_y_max": "real",
    "failed_defender": "integer",
    "fails_at": "real",
    **{f"hunt_{f.name}": "real" for f in fields(HuntParameters)},
    "scenario_toml": "text",
}
RESULT_COLUMNS = {  # mpc_hunt.sweep.runner.run_hunt; an error row leaves all but the first three and the last null
    "outcome": "text",
    "cause": "text",
    "message": "text",
    "termination": "text",
    "capture_time_s": "real",
    "path_length_m": "real",
    "min_obstacle_clearance_m": "real",
    "min_defender_separation_m": "real",
    "min_attacker_distance_m": "real",
    "min_arena_margin_m": "real",
    "safety_breach_approach": "integer",
    "safety_breach_capture": "integer",
    "steps": "integer",
    "solves": "integer",
    "failed_solves": "integer",
    "fallbacks": "integer",
    "longest_failure_streak": "integer",
    "solve_time_p50_s": "real",
    "solve_time_p95_s": "real",
    "solve_time_max_s": "real",
    "solves_over_time_step": "integer",
    "wall_time_s": "real",
}
COLUMNS = {"strategy": "text", "attacker": "text", "belief": "text", **SCENARIO_COLUMNS, **RESULT_COLUMNS}
ADDED = ("edge_race_lost",)  # columns a previous version did not write: read as None
LEGACY_COLUMNS = [c for c in COLUMNS if c not in LEGACY and c not in ADDED]  # a file of the previous version


EXTENSIBLE = ("strategies", "attackers", "beliefs")  # a resumed sweep may add to these (its rows stay valid)


def extends(new: dict, old: dict) -> bool:
    """Whether the sweep ``new`` is ``old`` with more strategies, attackers or beliefs and nothing else changed:
    every hunt of ``old`` is one of ``new`` (the same scenario, seed and generators), so its rows stay."""
    return (
        new.keys() == old.keys()
        and all(new[k] == old[k] for k in new if k not in EXTENSIBLE)
        and all(set(old[k]) <= set(new[k]) for k in EXTENSIBLE)
    )


def current_arguments(arguments: dict) -> dict:
    """A sweep's arguments as this version writes them: a previous version's have no ``attackers`` and
    ``beliefs``, and ran only :data:`LEGACY`'s."""
    return {f"{k}s": [v] for k, v in LEGACY.items()} | arguments


class SweepStore:
    """An open results file: new (``arguments`` given), resumed (and ``resume``), or read (neither).

    ``legacy`` is true for a file of the previous version; its rows read with :data:`LEGACY`'s attacker and
    belief, and a resumed one gets only such rows.
    """

    def __init__(self, path: str | Path, arguments: dict | None = None, resume: bool = False):
        self.path = Path(path)
        exists = self.path.exists()
        if exists and arguments is not None and not resume:
            raise SettingError(
                "path",
                f"{self.path} exists (use {field_name('resume')} to continue it, or another {field_name('path')})",
            )
        if not exists and arguments is None:
            raise MpcHuntError(f"{self.path}: no such results file")
        arguments = None if arguments is None else current_arguments(arguments)
        try:
            self.db = sqlite3.connect(self.path)
            if not exists and arguments is not None:  # (a new file always has them: refused above)
                self._create(arguments)
            stored = self.db.execute("select arguments, numpy from sweep").fetchone()
            self.columns = [r[1] for r in self.db.execute('pragma table_info("hunts")')]
        except sqlite3.DatabaseError as exc:
            raise MpcHuntError(f"{self.path}: not a sweep results file ({exc})") from None
        if stored is None or self.columns not in (list(COLUMNS), LEGACY_COLUMNS):
            raise MpcHuntError(
                f"{self.path}: not a results file of this version of mpc-hunt's sweep (docs/robustness.md)"
            )
        self.legacy = self.columns == LEGACY_COLUMNS
        self.arguments: dict = (  # a file read: checked
            self._stored_arguments(stored) if exists or arguments is None else arguments
        )
        if arguments is not None:
            self._check_resumable(arguments, stored)
            self.db.execute("pragma journal_mode=wal")

    def _check_resumable(self, arguments: dict, stored: tuple) -> None:
        """Refuse to continue the file with other arguments, or another numpy, than its own."""
        if self.legacy and any(arguments[f"{k}s"] != [v] for k, v in LEGACY.items()):
            raise SettingError(
                ("attackers", "beliefs"),
                f"{self.path} was written by an earlier mpc-hunt, whose "
                f"sweeps ran only the attacker {LEGACY['attacker']} with the "
                f"belief {LEGACY['belief']}: continue it with those alone, "
                f"or give another {field_name('path')}",
            )
        if self.arguments != arguments and (self.legacy or not extends(arguments, self.arguments)):
            raise SettingError(
                "resume",
                f"other arguments than the sweep in {self.path} ({stored[0]}); only more "
                f"{', '.join(map(field_name, EXTENSIBLE))} may be added",
            )
        if stored[1] != np.__version__:
            raise MpcHuntError(
                f"{self.path}: its scenarios were drawn with numpy {stored[1]}; this is numpy "
                f"{np.__version__}, which may draw others from the same seeds"
            )
        if self.arguments != arguments:  # extended: the file now holds the larger sweep
            with self.db:
                self.db.execute("update sweep set arguments = ?", (json.dumps(arguments, sort_keys=True),))
            self.arguments = arguments

    def _stored_arguments(self, stored: tuple) -> dict:
        """The sweep's arguments as the file holds them, checked to be what the code writes (a previous
        version's without ``attackers`` and ``beliefs``), as this version writes them."""
        try:
            value = json.loads(stored[0])
        except (TypeError, ValueError):
            value = None
        shape = {k: kind for k, kind in ARGUMENTS.items() if not (self.legacy and k[:-1] in LEGACY)}
        if (
            not isinstance(value, dict)
            or set(value) != set(shape)
            or not isinstance(stored[1], str)
            or any(not isinstance(value[k], kind) or isinstance(value[k], bool) for k, kind in shape.items())
            or not all(isinstance(s, str) for k, kind in shape.items() if kind is list for s in value[k])
        ):
            raise MpcHuntError(
                f"{self.path}: its stored arguments are not what mpc-hunt's sweep writes "
                f"({str(stored[0])[:80]!r}); it was changed by hand or by another program"
            )
        return current_arguments(value)

    def _create(self, arguments: dict) -> None:
        """Both tables and the sweep's row, in one transaction."""
        columns = ", ".join(f'"{name}" {kind}' for name, kind in COLUMNS.items())
        key = ", ".join(f'"{k}"' for k in KEY)
        with self.db:
            self.db.execute("begin")
            self.db.execute("create table sweep (arguments text not null, numpy text not null)")
            self.db.execute(f"create table hunts ({columns}, primary key ({key}))")
            self.db.execute("insert into sweep values (?, ?)", (json.dumps(arguments, sort_keys=True), np.__version__))

    def add(self, row: dict) -> None:
        """Store one finished hunt, committed at once; a key already present is left as it is."""
        unknown = set(row) - set(COLUMNS)
        if unknown:
            raise MpcHuntError(f"a sweep row has columns the results file does not: {', '.join(sorted(unknown))}")
        if self.legacy and any(row.get(k, v) != v for k, v in LEGACY.items()):
            raise MpcHuntError(
                f"{self.path}: a file of an earlier mpc-hunt holds only attacker "
                f"{LEGACY['attacker']} with belief {LEGACY['belief']}, not {row.get('attacker')} "
                f"with {row.get('belief')}"
            )
        placeholders = ", ".join("?" for _ in self.columns)
        with self.db:
            self.db.execute(f"insert or ignore into hunts values ({placeholders})", [row.get(c) for c in self.columns])

    def forget(self, strategy: str) -> int:
        """Delete one strategy's hunts (its controller changed): a resumed sweep runs them again. How many."""
        if strategy not in self.arguments["strategies"]:
            raise MpcHuntError(
                f"strategy: {strategy!r} is not one of this sweep's ({', '.join(self.arguments['strategies'])})"
            )
        with self.db:
            return self.db.execute('delete from hunts where "strategy" = ?', (strategy,)).rowcount

    def done(self) -> set[tuple]:
        """The keys (strategy, attacker, belief, seed, index) of the hunts in the file."""
        return {(r["strategy"], r["attacker"], r["belief"], r["seed"], r["index"]) for r in self._read(KEY)}

    def rows(self) -> list[dict]:
        """Every hunt, by index, strategy, attacker and belief; every column of :data:`COLUMNS`."""
        return self._read(COLUMNS)

    def _read(self, columns) -> list[dict]:
        """These columns of every row, ordered as ``rows``; a previous version's rows get :data:`LEGACY`'s."""
        stored = [c for c in columns if c in self.columns]
        names = ", ".join(f'"{c}"' for c in stored)
        order = ", ".join(f'"{c}"' for c in ("index", *KEY[:3]) if c in self.columns)
        rows = (dict(zip(stored, r)) for r in self.db.execute(f"select {names} from hunts order by {order}"))
        return [{c: row.get(c, LEGACY.get(c)) for c in columns} for row in rows]

    def close(self) -> None:
        self.db.close()


def stored_rows(path: str | Path) -> list[dict]:
    """Every hunt of the results file at ``path`` (:meth:`SweepStore.rows`), the file closed again."""
    store = SweepStore(path)
    try:
        return store.rows()
    finally:
        store.close()


def self_contained(path: str | Path) -> None:
    """The results file at ``path`` as one self-contained file (to commit), not a write-ahead log beside it."""
    db = sqlite3.connect(path)
    try:
        db.execute("pragma journal_mode=delete")
    finally:
        db.close()

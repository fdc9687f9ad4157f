"""Capture-stage problems as files: states of a hunt, with the scenarios they belong to.

A problem set is one JSON document that any tool can read::

    {"format": "mpc-hunt problem set", "version": 1, "description": "...",
     "scenarios": {"<name>": {<the scenario, as in its TOML file>}},
     "problems": [{"id": "...", "scenario": "<name>", "time": t,
                   "attacker": [x, y], "defenders": [[x, y], ...],
                   "sequence": "<id of a run of consecutive states>" or null,
                   "tags": ["default", ...]}]}

A problem is a state; the horizon is chosen when it is solved
(:meth:`ProblemSet.problem`). Problems of one ``sequence`` are consecutive
closed-loop states (one time step apart), in order, for warm-started solving.
Tags are free strings; the builders use ``default``, ``closed-loop``,
``random``, ``case:<family>`` and ``active:<family>`` (docs/benchmarks.md). The
package ships the set ``default`` (``mpc_hunt/bench/problems/default.json``), which
holds, tagged ``default``, the state ``mpc-hunt solve`` starts from for each
built-in scenario. Files are written one problem per line
(:func:`dumps_problem_set`), so they stay small and diff well.
"""

from __future__ import annotations

import json
import os
from collections import Counter
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path

import numpy as np

from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.control.posing import posed_problem
from mpc_hunt.errors import ScenarioError, UnknownNameError
from mpc_hunt.world.hunt_state import HuntState, read_json, state_from_dict
from mpc_hunt.world.names import shipped_name
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.scenario_io import scenario_from_dict, scenario_to_dict

FORMAT, VERSION = "mpc-hunt problem set", 1
_ENTRY_KEYS = frozenset({"id", "scenario", "sequence", "tags"})  # beside a state's own keys


@dataclass(frozen=True)
class ProblemEntry:
    """One state of a problem set, named by ``id``, in scenario ``scenario``."""

    id: str
    scenario: str
    state: HuntState
    sequence: str | None = None
    tags: tuple[str, ...] = ()


@dataclass(frozen=True)
class ProblemSet:
    """Problems and the scenarios they refer to."""

    scenarios: dict[str, Scenario]
    problems: tuple[ProblemEntry, ...]
    description: str = ""

    def problem(self, entry: ProblemEntry, horizon: int = 1, objective: str = "paper") -> CaptureProblem:
        """The capture problem the strategy poses at ``entry``'s state, over ``horizon`` steps."""
        return posed_problem(self.scenarios[entry.scenario], entry.state, horizon, objective)

    def tagged(self, tag: str) -> list[ProblemEntry]:
        return [p for p in self.problems if tag in p.tags]

    def sequences(self) -> dict[str, list[ProblemEntry]]:
        """The consecutive runs, each in order, by sequence id."""
        runs: dict[str, list[ProblemEntry]] = {}
        for entry in self.problems:
            if entry.sequence is not None:
                runs.setdefault(entry.sequence, []).append(entry)
        return runs

    def default_state(self, scenario: str) -> HuntState | None:
        """The state tagged ``default`` of ``scenario``, if the set holds one."""
        found = [p.state for p in self.tagged("default") if p.scenario == scenario]
        return found[0] if found else None

    def units(self) -> list[tuple[ProblemEntry, ...]]:
        """The set in order as units that are solved together: each sequence whole, each other problem alone."""
        out: list[tuple[ProblemEntry, ...]] = []
        runs = self.sequences()
        for entry in self.problems:
            if entry.sequence is None:
                out.append((entry,))
            elif runs[entry.sequence][0] is entry:
                out.append(tuple(runs[entry.sequence]))
        return out

    def select(
        self, tags: tuple[str, ...] = (), limit: int | None = None, rng: np.random.Generator | None = None
    ) -> "ProblemSet":
        """The problems carrying every tag in ``tags``; then, if ``limit`` is given, at most that many, drawn
        with ``rng`` (sequences taken whole or not at all), in the set's order."""
        kept = [p for p in self.problems if all(t in p.tags for t in tags)]
        chosen = replace(self, problems=tuple(kept))
        if limit is None:
            return chosen
        if rng is None:
            raise ValueError("rng: a numpy.random.Generator is needed to draw a limited selection")
        units = chosen.units()
        picked, count = set(), 0
        for i in rng.permutation(len(units)):
            if count + len(units[i]) <= limit:
                picked.add(int(i))
                count += len(units[i])
        return replace(self, problems=tuple(p for i, unit in enumerate(units) if i in picked for p in unit))

    def describe(self) -> list[str]:
        """A summary: description, scenarios, counts by tag and the sequences."""
        tags = Counter(t for p in self.problems for t in p.tags)
        runs = self.sequences()
        lines = [
            self.description,
            f"{len(self.problems)} problems in {len(self.scenarios)} scenarios; "
            f"{len(runs)} sequences ({sum(map(len, runs.values()))} problems)",
        ]
        lines += [f"tag {tag}: {count}" for tag, count in sorted(tags.items())]
        return lines

    def to_dict(self) -> dict:
        return {
            "format": FORMAT,
            "version": VERSION,
            "description": self.description,
            "scenarios": {name: scenario_to_dict(s) for name, s in self.scenarios.items()},
            "problems": [
                {"id": p.id, "scenario": p.scenario, **p.state.to_dict(), "sequence": p.sequence, "tags": list(p.tags)}
                for p in self.problems
            ],
        }


def dumps_problem_set(problem_set: ProblemSet) -> str:
    """The JSON text of a set: scenarios indented, each problem on one line."""
    data = problem_set.to_dict()
    problems = data.pop("problems")
    head = json.dumps(data, indent=1, ensure_ascii=False)[:-2]
    body = ",\n  ".join(json.dumps(p, ensure_ascii=False) for p in problems)
    return f'{head},\n "problems": [\n  {body}\n ]\n}}\n' if problems else f'{head},\n "problems": []\n}}\n'


def problem_set_from_dict(data: object, source: str = "<data>") -> ProblemSet:
    """Build a problem set from plain data (as read from JSON); every key is checked."""
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise ScenarioError(f'{source}: not a problem set (expected "format": "{FORMAT}")')
    if data.get("version") != VERSION:
        raise ScenarioError(f"{source}: version: expected {VERSION}, got {data.get('version')!r}")
    raw_scenarios = data.get("scenarios")
    if not isinstance(raw_scenarios, dict):
        raise ScenarioError(f"{source}: scenarios: expected an object of scenarios by name")
    scenarios = {}
    for name, raw in raw_scenarios.items():
        try:
            scenarios[name] = scenario_from_dict(raw)
        except ScenarioError as exc:
            raise ScenarioError(f"{source}: scenarios.{name}: {exc}") from None
    raw_problems = data.get("problems")
    if not isinstance(raw_problems, list):
        raise ScenarioError(f"{source}: problems: expected a list")
    problems = []
    for i, raw in enumerate(raw_problems):
        where = f"{source}: problems[{i}]"
        if not isinstance(raw, dict):
            raise ScenarioError(f"{where}: expected an object")
        name = raw.get("scenario")
        if not isinstance(name, str) or name not in scenarios:
            raise ScenarioError(f"{where}: scenario: {name!r} is not among the set's scenarios")
        tags = raw.get("tags", [])
        if not (isinstance(tags, list) and all(isinstance(t, str) for t in tags)):
            raise ScenarioError(f"{where}: tags: expected a list of strings")
        try:
            state = state_from_dict(raw, scenarios[name], _ENTRY_KEYS)
        except ScenarioError as exc:
            raise ScenarioError(f"{where}: {exc}") from None
        sequence = raw.get("sequence")
        if sequence is not None and not isinstance(sequence, str):
            raise ScenarioError(f"{where}: sequence: expected a string or null")
        problems.append(ProblemEntry(str(raw.get("id", i)), name, state, sequence, tuple(tags)))
    ids = [p.id for p in problems]
    if len(set(ids)) < len(ids):
        repeated = next(i for i in ids if ids.count(i) > 1)
        raise ScenarioError(f"{source}: problems: id {repeated!r} appears more than once")
    return ProblemSet(scenarios, tuple(problems), str(data.get("description", "")))


def load_problem_set(path: str | Path) -> ProblemSet:
    """Read a problem set file (JSON, see the module's docstring), checked when loaded: a damaged file is a
    one-line ScenarioError naming it."""
    path = Path(path)
    return problem_set_from_dict(read_json(path, f'a problem set, {{"format": "{FORMAT}", ...}}'), str(path))


def save_problem_set(problem_set: ProblemSet, path: str | Path) -> None:
    """Write a set as JSON (:func:`dumps_problem_set`); :func:`load_problem_set` reads it back unchanged.

    Written whole or not at all: into a temporary file beside ``path``, then renamed over it.
    """
    path = Path(path)
    temporary = path.with_name(f".{path.name}.partial")
    try:
        temporary.write_text(dumps_problem_set(problem_set), encoding="utf-8")
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


def builtin_problem_sets() -> list[str]:
    """Names of the problem sets shipped with the package."""
    files = resources.files("mpc_hunt.bench.problems")
    return sorted(p.name.removesuffix(".json") for p in files.iterdir() if p.name.endswith(".json"))


def builtin_problem_set(name: str = "default") -> ProblemSet:
    """A problem set shipped with the package."""
    files = resources.files("mpc_hunt.bench.problems")
    available = builtin_problem_sets()
    if name not in available:
        raise UnknownNameError(f"unknown problem set {name!r} (available: {', '.join(available)})")
    with resources.as_file(files.joinpath(f"{name}.json")) as path:  # checked as any problem set file
        return load_problem_set(path)


def resolve_problem_set(name_or_file: str | Path) -> ProblemSet:
    """A shipped set by name, or a problem set file."""
    name = shipped_name(name_or_file, builtin_problem_sets(), "problem set", ".json")
    return load_problem_set(name_or_file) if name is None else builtin_problem_set(name)

"""A hunt's state (everybody's position at one time) as data: checked, read from and written to JSON.

The form is {"time": t, "attacker": [x, y], "defenders": [[x, y], …]}; a
problem set (:mod:`mpc_hunt.bench.problem_set`) holds many, ``mpc-hunt solve``
reads and writes one (``--state``, ``--save-state``), and the capture problem
the strategy poses at one is :func:`mpc_hunt.control.posing.posed_problem`.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mpc_hunt.errors import ScenarioError
from mpc_hunt.world.scenario import Scenario, check_positions, checked_number, checked_vector, key_shown, shown
from mpc_hunt.world.scenario_io import read_input_file

STATE_FORM = '{"time": t, "attacker": [x, y], "defenders": [[x, y], ...]}'


@dataclass(frozen=True)
class HuntState:
    """Where everybody is at one time of a hunt."""

    time: float
    attacker: np.ndarray
    defenders: np.ndarray

    def to_dict(self) -> dict:
        return {"time": self.time, "attacker": self.attacker.tolist(), "defenders": self.defenders.tolist()}


def read_json(path: Path, expected: str = f"a JSON object {STATE_FORM}") -> object:
    """A JSON file's data; every way it can fail to be JSON is a one-line ScenarioError naming the file
    (``expected``: what an empty file should have held, for the message)."""
    text = read_input_file(path)
    if not text.strip():
        raise ScenarioError(f"{path}: empty (expected {expected})")

    def unique_keys(pairs: list[tuple[str, object]]) -> dict:
        keys = [k for k, _ in pairs]
        repeated = sorted({k for k in keys if keys.count(k) > 1})
        if repeated:
            raise ScenarioError(f"{key_shown(repeated[0])}: given more than once (in {path})")
        return dict(pairs)

    try:
        return json.loads(text, object_pairs_hook=unique_keys)
    except json.JSONDecodeError as exc:
        raise ScenarioError(f"{path}: not valid JSON ({exc})") from None
    except ScenarioError:
        raise
    except ValueError:  # Python converts whole numbers of at most sys.get_int_max_str_digits() digits
        raise ScenarioError(f"{path}: not valid JSON (a whole number with too many digits)") from None
    except RecursionError:
        raise ScenarioError(f"{path}: not valid JSON (arrays or objects nested too deeply)") from None


def state_from_dict(data: object, scenario: Scenario, other_keys: frozenset[str] = frozenset()) -> HuntState:
    """A state checked against ``scenario`` as its starts are; a ScenarioError names the field.

    Rejected: unknown keys (beyond ``other_keys``), a position that is not
    [x, y] of finite numbers within the input limits, a negative time, the
    wrong number of defenders, a robot inside an obstacle or on another
    robot's spot, the attacker outside the scenario's arena.
    """
    if not isinstance(data, dict):
        raise ScenarioError(f"expected a JSON object {STATE_FORM}, got {type(data).__name__}")
    known = {"time", "attacker", "defenders"} | other_keys
    unknown = sorted(set(data) - known)
    if unknown:
        raise ScenarioError(f"{key_shown(unknown[0])}: unknown key (known: {', '.join(sorted(known))})")
    for key in ("attacker", "defenders"):
        if key not in data:
            raise ScenarioError(f"{key}: missing")
    time = checked_number(data.get("time", 0.0), "time", non_negative=True, unit=" s")
    p_a = checked_vector(data["attacker"], "attacker")
    n = len(scenario.defenders)
    raw = data["defenders"]
    if not isinstance(raw, list) or len(raw) != n:
        got = f"{len(raw)}" if isinstance(raw, list) else shown(raw)
        raise ScenarioError(f"defenders: expected {n} positions [x, y] for scenario {shown(scenario.name)}, got {got}")
    p_d = [checked_vector(p, f"defenders[{i}]") for i, p in enumerate(raw)]
    check_positions(scenario, ("attacker", p_a), [(f"defenders[{i}]", p) for i, p in enumerate(p_d)])
    return HuntState(time, np.array(p_a), np.array(p_d, dtype=float).reshape(n, 2))


def load_state(path: str | Path, scenario: Scenario) -> HuntState:
    """Read a state file, checked against ``scenario`` as its starts are (docs/robustness.md).

    Every problem is a one-line ScenarioError naming the file and the field
    (see :func:`state_from_dict`).
    """
    path = Path(path)
    data = read_json(path)
    try:
        return state_from_dict(data, scenario)
    except ScenarioError as exc:
        raise ScenarioError(f"{exc} (in {path})") from None


def save_state(state: HuntState, path: str | Path) -> None:
    Path(path).write_text(json.dumps(state.to_dict(), indent=2) + "\n", encoding="utf-8")

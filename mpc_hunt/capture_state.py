"""States at which a single capture-stage problem is posed (``mpc-hunt solve``).

The default is reproducible from the scenario alone: the first state of its
closed-loop run under the paper's strategy (one-step NLP, prediction on) at
which every defender is in the capture stage and the hunting circle has formed,
i.e. the defenders' distances to the attacker differ by at most 2 r_d (so
Eq. 14 can hold from the first step). A state can also be read from, and
written to, a JSON file: {"time": t, "attacker": [x, y], "defenders": [[x, y], …]}.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mpc_hunt import attacker
from mpc_hunt.errors import MpcHuntError, ScenarioError
from mpc_hunt.geometry import norm
from mpc_hunt.scenario import Scenario
from mpc_hunt.simulator import simulate
from mpc_hunt.strategy import Observation


@dataclass(frozen=True)
class HuntState:
    """Where everybody is at one time."""

    time: float
    attacker: np.ndarray
    defenders: np.ndarray

    def to_dict(self) -> dict:
        return {"time": self.time, "attacker": self.attacker.tolist(), "defenders": self.defenders.tolist()}


def circle_formed(scenario: Scenario, obs: Observation) -> bool:
    """Every defender within R_agg, their distances to the attacker within 2 r_d of each other."""
    d = norm(obs.attacker - obs.defenders)
    r_d = float(np.min(scenario.defender_max_speeds)) * scenario.hunt.time_step
    return bool(attacker.perceives(scenario, obs.attacker, obs.defenders).all() and d.max() - d.min() <= 2 * r_d)


def first_formed_circle(scenario: Scenario) -> HuntState:
    """The default state of ``mpc-hunt solve`` (see the module's docstring)."""
    found: list[Observation] = []

    def until(obs: Observation) -> bool:
        if circle_formed(scenario, obs):
            found.append(obs)
            return True
        return False

    simulate(scenario, until=until)
    if not found:
        raise MpcHuntError(f"scenario {scenario.name!r}: the hunting circle never formed in its closed-loop run")
    obs = found[0]
    return HuntState(obs.time, obs.attacker, obs.defenders)


def load_state(path: str | Path, scenario: Scenario) -> HuntState:
    """Read a state file; its shapes are checked against ``scenario``."""
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot read ({exc.strerror or exc})") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"{path}: not valid JSON ({exc})") from None
    if not isinstance(data, dict):
        raise ScenarioError(f"{path}: expected a JSON object with 'attacker' and 'defenders'")
    unknown = sorted(set(data) - {"time", "attacker", "defenders"})
    if unknown:
        raise ScenarioError(f"{path}: {unknown[0]}: unknown key (known: attacker, defenders, time)")
    n = len(scenario.defenders)
    try:
        attacker = np.array(data["attacker"], dtype=float)
        defenders = np.array(data["defenders"], dtype=float)
        time = float(data.get("time", 0.0))
    except KeyError as exc:
        raise ScenarioError(f"{path}: {exc.args[0]}: missing") from None
    except (TypeError, ValueError):
        raise ScenarioError(f"{path}: attacker, defenders and time must be numbers") from None
    if attacker.shape != (2,):
        raise ScenarioError(f"{path}: attacker: expected [x, y], got shape {attacker.shape}")
    if defenders.shape != (n, 2):
        raise ScenarioError(f"{path}: defenders: expected {n} positions [x, y] for scenario "
                            f"{scenario.name!r}, got shape {defenders.shape}")
    if not (np.all(np.isfinite(attacker)) and np.all(np.isfinite(defenders)) and np.isfinite(time)):
        raise ScenarioError(f"{path}: positions and time must be finite")
    return HuntState(time, attacker, defenders)


def save_state(state: HuntState, path: str | Path) -> None:
    Path(path).write_text(json.dumps(state.to_dict(), indent=2) + "\n", encoding="utf-8")

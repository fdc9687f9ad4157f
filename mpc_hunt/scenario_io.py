"""Scenarios to and from TOML files, and the built-in scenarios shipped as TOML."""

from __future__ import annotations

import tomllib
from dataclasses import asdict, fields
from importlib import resources
from pathlib import Path

import tomli_w

from mpc_hunt.errors import ScenarioError, UnknownNameError
from mpc_hunt.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario

DEFAULT_SCENARIO = "paper-obstacles"
_TOP_KEYS = {"name", "description", "attacker", "defenders", "obstacles", "hunt"}


def _keys(table: object, cls: type, where: str, required: bool = True) -> dict:
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}: expected a table, got {type(table).__name__}")
    known = {f.name for f in fields(cls)}
    unknown = sorted(set(table) - known)
    if unknown:
        raise ScenarioError(f"{where}.{unknown[0]}: unknown key (known: {', '.join(sorted(known))})")
    if required:
        missing = sorted(f.name for f in fields(cls) if f.name not in table)
        if missing:
            raise ScenarioError(f"{where}.{missing[0]}: missing")
    return table


def _table_list(data: dict, key: str) -> list:
    value = data.get(key, [])
    if not isinstance(value, list):
        raise ScenarioError(f"{key}: expected an array of tables ([[{key}]]), got {type(value).__name__}")
    return value


def scenario_from_dict(data: dict) -> Scenario:
    """Build a scenario from plain data (as read from TOML); every key is checked."""
    if not isinstance(data, dict):
        raise ScenarioError("scenario: expected a table at the top level")
    unknown = sorted(set(data) - _TOP_KEYS)
    if unknown:
        raise ScenarioError(f"{unknown[0]}: unknown key (known: {', '.join(sorted(_TOP_KEYS))})")
    if "name" not in data:
        raise ScenarioError("name: missing")
    if "attacker" not in data:
        raise ScenarioError("attacker: missing")
    defenders = tuple(Defender(**_keys(d, Defender, f"defenders[{i}]"))
                      for i, d in enumerate(_table_list(data, "defenders")))
    obstacles = tuple(Obstacle(**_keys(o, Obstacle, f"obstacles[{i}]"))
                      for i, o in enumerate(_table_list(data, "obstacles")))
    return Scenario(
        name=data["name"],
        description=data.get("description", ""),
        attacker=Attacker(**_keys(data["attacker"], Attacker, "attacker")),
        defenders=defenders,
        obstacles=obstacles,
        hunt=HuntParameters(**_keys(data.get("hunt", {}), HuntParameters, "hunt", required=False)),
    )


def scenario_to_dict(scenario: Scenario) -> dict:
    """Plain data for TOML: vectors as lists, every hunt parameter written out."""
    def plain(obj):
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(obj).items()}

    data = {"name": scenario.name, "description": scenario.description,
            "attacker": plain(scenario.attacker),
            "defenders": [plain(d) for d in scenario.defenders]}
    if scenario.obstacles:
        data["obstacles"] = [plain(o) for o in scenario.obstacles]
    data["hunt"] = plain(scenario.hunt)
    return data


def loads_scenario(text: str, source: str = "<string>") -> Scenario:
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{source}: not valid TOML ({exc})") from None
    return scenario_from_dict(data)


def dumps_scenario(scenario: Scenario) -> str:
    return tomli_w.dumps(scenario_to_dict(scenario))


def load_scenario(path: str | Path) -> Scenario:
    """Read a scenario from a TOML file."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot read ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise ScenarioError(f"{path}: not a UTF-8 text file") from None
    return loads_scenario(text, str(path))


def save_scenario(scenario: Scenario, path: str | Path) -> None:
    """Write a scenario to a TOML file (``load_scenario`` reads it back unchanged)."""
    Path(path).write_text(dumps_scenario(scenario), encoding="utf-8")


def builtin_names() -> list[str]:
    """Names of the scenarios shipped with the package."""
    folder = resources.files("mpc_hunt") / "scenarios"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def builtin_scenario(name: str) -> Scenario:
    names = builtin_names()
    if name not in names:
        raise UnknownNameError(f"unknown scenario {name!r} (built-in: {', '.join(names)})")
    text = (resources.files("mpc_hunt") / "scenarios" / f"{name}.toml").read_text(encoding="utf-8")
    return loads_scenario(text, f"built-in scenario {name}")


def resolve_scenario(name_or_file: str | Path | None = None) -> Scenario:
    """A built-in name, or a path to a TOML file; ``None`` gives the default scenario."""
    if name_or_file is None:
        return builtin_scenario(DEFAULT_SCENARIO)
    text = str(name_or_file)
    if text in builtin_names():
        return builtin_scenario(text)
    if text.endswith(".toml") or Path(text).exists():
        return load_scenario(text)
    raise UnknownNameError(f"unknown scenario {text!r}: neither a built-in "
                           f"({', '.join(builtin_names())}) nor an existing .toml file")

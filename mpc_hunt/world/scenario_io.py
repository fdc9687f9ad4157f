"""Scenarios to and from TOML files, and the built-in scenarios shipped as TOML.

Every problem with a scenario file is a :class:`~mpc_hunt.errors.ScenarioError`
of one line that names the file: ``FILE: problem`` when the file itself cannot
be read or parsed, ``FIELD: problem (in FILE)`` when a value is wrong
(docs/robustness.md).
"""

from __future__ import annotations

import stat
import tomllib
from dataclasses import MISSING, asdict, fields
from importlib import resources
from pathlib import Path
from typing import Any

import tomli_w

from mpc_hunt.errors import ScenarioError, UnknownNameError
from mpc_hunt.world.names import shipped_name
from mpc_hunt.world.scenario import LIMITS_DOC, Attacker, Defender, HuntParameters, Obstacle, Scenario, key_shown

DEFAULT_SCENARIO = "paper-obstacles"
MAX_FILE_BYTES = 1 << 20  # a scenario or state file is a few kB at most
_TOP_KEYS = {"name", "description", "arena", "attacker", "defenders", "obstacles", "hunt"}


def read_input_file(path: str | Path) -> str:
    """The text of a small UTF-8 input file (a leading byte-order mark is dropped).

    A missing or unreadable path, a directory or other non-regular file, a
    file larger than ``MAX_FILE_BYTES`` or one that is not UTF-8 is a
    ScenarioError naming the file.
    """
    path = Path(path)
    try:
        mode = path.stat().st_mode
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if stat.S_ISDIR(mode):
        raise ScenarioError(f"{path}: cannot read (a directory, not a file)")
    if not stat.S_ISREG(mode):
        raise ScenarioError(f"{path}: cannot read (not a regular file)")
    try:
        with path.open("rb") as f:
            data = f.read(MAX_FILE_BYTES + 1)
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if len(data) > MAX_FILE_BYTES:
        raise ScenarioError(f"{path}: larger than the limit of {MAX_FILE_BYTES} bytes ({LIMITS_DOC})")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ScenarioError(
            f"{path}: not a UTF-8 text file (byte 0x{data[exc.start]:02x} at offset {exc.start})"
        ) from None


def parse_toml(text: str, source: str) -> dict:
    """TOML text as a table; a syntax error, or a file with nothing in it, is a ScenarioError naming ``source``."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{source}: not valid TOML ({exc})") from None
    except ValueError:  # Python converts whole numbers of at most sys.get_int_max_str_digits() digits
        raise ScenarioError(f"{source}: not valid TOML (a whole number with too many digits)") from None
    except RecursionError:
        raise ScenarioError(f"{source}: not valid TOML (arrays or tables nested too deeply)") from None
    if not data:
        raise ScenarioError(f"{source}: empty (no keys, only blank lines or comments)")
    return data


def _keys(table: object, cls: type, where: str, required: bool = True) -> dict:
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}: expected a table, got {type(table).__name__}")
    known = {f.name for f in fields(cls)}
    unknown = sorted(set(table) - known)
    if unknown:
        raise ScenarioError(f"{where}.{key_shown(unknown[0])}: unknown key (known: {', '.join(sorted(known))})")
    if required:
        missing = sorted(f.name for f in fields(cls) if f.name not in table and f.default is MISSING)
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
        raise ScenarioError(f"{key_shown(unknown[0])}: unknown key (known: {', '.join(sorted(_TOP_KEYS))})")
    if "name" not in data:
        raise ScenarioError("name: missing")
    if "attacker" not in data:
        raise ScenarioError("attacker: missing")
    defenders = tuple(
        Defender(**_keys(d, Defender, f"defenders[{i}]")) for i, d in enumerate(_table_list(data, "defenders"))
    )
    obstacles = tuple(
        Obstacle(**_keys(o, Obstacle, f"obstacles[{i}]")) for i, o in enumerate(_table_list(data, "obstacles"))
    )
    return Scenario(
        name=data["name"],
        description=data.get("description", ""),
        attacker=Attacker(**_keys(data["attacker"], Attacker, "attacker")),
        defenders=defenders,
        obstacles=obstacles,
        hunt=HuntParameters(**_keys(data.get("hunt", {}), HuntParameters, "hunt", required=False)),
        arena=data.get("arena"),
    )


def scenario_to_dict(scenario: Scenario) -> dict:
    """Plain data for TOML: vectors as lists, every hunt parameter written out, the arena if there is one."""

    def plain(obj):
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(obj).items() if v is not None}

    data: dict[str, Any] = {"name": scenario.name, "description": scenario.description}
    if scenario.arena is not None:
        data["arena"] = list(scenario.arena)
    data["attacker"] = plain(scenario.attacker)
    data["defenders"] = [plain(d) for d in scenario.defenders]
    if scenario.obstacles:
        data["obstacles"] = [plain(o) for o in scenario.obstacles]
    data["hunt"] = plain(scenario.hunt)
    return data


def loads_scenario(text: str, source: str | None = None) -> Scenario:
    """A scenario from TOML text; ``source`` (a file name) is named in every error."""
    data = parse_toml(text, source or "<string>")
    try:
        return scenario_from_dict(data)
    except ScenarioError as exc:
        if source is None:
            raise
        raise ScenarioError(f"{exc} (in {source})") from None


def dumps_scenario(scenario: Scenario) -> str:
    return tomli_w.dumps(scenario_to_dict(scenario))


def load_scenario(path: str | Path) -> Scenario:
    """Read a scenario from a TOML file."""
    return loads_scenario(read_input_file(path), str(path))


def save_scenario(scenario: Scenario, path: str | Path) -> None:
    """Write a scenario to a TOML file (``load_scenario`` reads it back unchanged)."""
    Path(path).write_text(dumps_scenario(scenario), encoding="utf-8")


def builtin_names() -> list[str]:
    """Names of the scenarios shipped with the package."""
    folder = resources.files("mpc_hunt.world.scenarios")
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def builtin_scenario(name: str) -> Scenario:
    """The built-in scenario ``name`` (one of :func:`builtin_names`), read from its TOML file shipped with the
    package; an :class:`~mpc_hunt.errors.UnknownNameError` listing the built-in names for any other name."""
    names = builtin_names()
    if name not in names:
        raise UnknownNameError(f"unknown scenario {name!r} (built-in: {', '.join(names)})")
    text = (resources.files("mpc_hunt.world.scenarios") / f"{name}.toml").read_text(encoding="utf-8")
    return loads_scenario(text, f"built-in scenario {name}")


def builtin_name(name_or_file: str | Path) -> str | None:
    """The built-in scenario ``name_or_file`` names, or None when it is a TOML file; else an unknown name."""
    return shipped_name(name_or_file, builtin_names(), "scenario", ".toml", "a built-in")


def resolve_scenario(name_or_file: str | Path | None = None) -> Scenario:
    """A built-in name, or a path to a TOML file; ``None`` gives the default scenario."""
    if name_or_file is None:
        return builtin_scenario(DEFAULT_SCENARIO)
    name = builtin_name(name_or_file)
    return load_scenario(str(name_or_file)) if name is None else builtin_scenario(name)

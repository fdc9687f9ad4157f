"""Seeded random scenarios for sweeps: ranges, one scenario per random generator, scenario i of sweep s.

Everything not drawn is the paper's: its defender speed (0.08 m/s), its hunt
parameters (``HuntParameters()``) but a 300 s time limit. Starts are drawn
uniformly in the arena, obstacles uniformly inside it, the attacker's heading
uniformly; rejection sampling keeps obstacles apart and starts clear
(docs/robustness.md gives the ranges, their defaults and the rules).

Scenario ``i`` of a sweep with seed ``s`` is drawn from child ``i`` of
``numpy.random.SeedSequence(s)``, i.e. ``SeedSequence(s).spawn(i + 1)[i]``.
Spawned children are numpy's designed way to get independent streams; any one
of them can be made without the others (``spawn_key=(i,)``); and a child's
spawn key keeps its stream apart from every plain seed, whereas
``default_rng([s, i])`` is the stream of anyone who seeds with the list [s, i].
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np
import tomli_w

from mpc_hunt.errors import ScenarioError
from mpc_hunt.world.scenario import (
    MAX_DEFENDERS,
    MAX_MAGNITUDE,
    MAX_OBSTACLES,
    MAX_SPEED,
    Attacker,
    Defender,
    HuntParameters,
    Obstacle,
    Scenario,
    Vector,
    checked_arena,
    checked_number,
    key_shown,
    shown,
)
from mpc_hunt.world.scenario_io import parse_toml, read_input_file

MAX_SPEED_RATIO = 0.99  # strictly below 1, with room for rounding: the attacker is slower than every defender
MAX_TRIES = 1_000_000


@dataclass(frozen=True)
class ScenarioRanges:
    """What a random scenario is drawn from (docs/robustness.md). A pair (lo, hi) is a closed range; lo == hi
    fixes the value, and so does a single number in a file or an override."""

    arena: tuple[float, float, float, float] = (0.0, 0.0, 20.0, 20.0)  # (x_min, y_min, x_max, y_max), m
    n_defenders: tuple[int, int] = (2, 5)
    n_obstacles: tuple[int, int] = (0, 5)
    obstacle_radius: tuple[float, float] = (0.3, 1.2)  # m
    defender_speed: tuple[float, float] = (0.08, 0.08)  # m/s, each defender's max_speed (the paper's)
    speed_ratio: tuple[float, float] = (0.25, 0.75)  # v_a / the slowest defender's speed (paper: 0.375)
    perception_radius: tuple[float, float] = (0.5, 1.5)  # R_agg, m (paper: 1)
    min_spacing: float = 1.0  # m, between any two robots' starts, the attacker's included
    margin: float = 0.2  # m, between obstacles; and beyond R_safe around obstacles for a start
    time_limit: float = 300.0  # s
    max_tries: int = 1000  # draws per obstacle or robot before giving up
    defender_failure: float = 0.0  # chance that one random defender fails mid-hunt
    failure_time: tuple[float, float] = (30.0, 150.0)  # s, when it fails (Defender.fails_at)

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "arena", checked_arena(self.arena, "ranges.arena"))
        set_(self, "n_defenders", _count_range(self.n_defenders, "ranges.n_defenders", 1, MAX_DEFENDERS))
        set_(self, "n_obstacles", _count_range(self.n_obstacles, "ranges.n_obstacles", 0, MAX_OBSTACLES))
        set_(self, "obstacle_radius", _real_range(self.obstacle_radius, "ranges.obstacle_radius", unit=" m"))
        set_(
            self,
            "defender_speed",
            _real_range(self.defender_speed, "ranges.defender_speed", limit=MAX_SPEED, unit=" m/s"),
        )
        set_(self, "speed_ratio", _real_range(self.speed_ratio, "ranges.speed_ratio", limit=MAX_SPEED_RATIO))
        set_(self, "perception_radius", _real_range(self.perception_radius, "ranges.perception_radius", unit=" m"))
        set_(self, "min_spacing", checked_number(self.min_spacing, "ranges.min_spacing", positive=True, unit=" m"))
        set_(self, "margin", checked_number(self.margin, "ranges.margin", non_negative=True, unit=" m"))
        set_(self, "time_limit", checked_number(self.time_limit, "ranges.time_limit", positive=True, unit=" s"))
        set_(self, "max_tries", _whole(self.max_tries, "ranges.max_tries", 1, MAX_TRIES))
        set_(
            self,
            "defender_failure",
            checked_number(self.defender_failure, "ranges.defender_failure", non_negative=True, limit=1.0),
        )
        set_(self, "failure_time", _real_range(self.failure_time, "ranges.failure_time", unit=" s"))
        self._check_fit()

    def hunt(self) -> HuntParameters:
        """The paper's hunt parameters with this time limit."""
        return HuntParameters(time_limit=self.time_limit)

    def _check_fit(self) -> None:
        hunt = self.hunt()
        if self.time_limit < hunt.time_step:
            raise ScenarioError(
                f"ranges.time_limit: must be at least the time step {hunt.time_step} s, got {self.time_limit}"
            )
        closest = max(hunt.min_separation, hunt.min_attacker_distance)
        if self.min_spacing < closest:
            raise ScenarioError(
                f"ranges.min_spacing: must be at least {closest} m, the hunt's smallest "
                f"allowed robot distance, got {self.min_spacing}"
            )
        x_min, y_min, x_max, y_max = self.arena
        if 2 * self.obstacle_radius[1] > min(x_max - x_min, y_max - y_min):
            raise ScenarioError(
                f"ranges.obstacle_radius: an obstacle of radius {self.obstacle_radius[1]} m does "
                f"not fit in the arena ({x_max - x_min} m × {y_max - y_min} m)"
            )


def _pair(value: object, where: str) -> tuple[object, object]:
    if isinstance(value, (list, tuple)):
        if len(value) != 2:
            raise ScenarioError(f"{where}: expected a value or [min, max], got {shown(value)}")
        return value[0], value[1]
    return value, value


def _count_range(value: object, where: str, low: int, high: int) -> tuple[int, int]:
    """A whole number or [min, max] of whole numbers within [low, high]."""
    lo, hi = (_whole(x, where, low, high) for x in _pair(value, where))
    if lo > hi:
        raise ScenarioError(f"{where}: min {lo} exceeds max {hi}")
    return lo, hi


def _real_range(value: object, where: str, *, limit: float = MAX_MAGNITUDE, unit: str = "") -> tuple[float, float]:
    """A positive number or [min, max] of positive numbers, at most ``limit``."""
    lo, hi = (checked_number(x, where, positive=True, limit=limit, unit=unit) for x in _pair(value, where))
    if lo > hi:
        raise ScenarioError(f"{where}: min {lo} exceeds max {hi}")
    return lo, hi


def _whole(value: object, where: str, low: int = 0, high: int | None = None) -> int:
    """A whole number in [low, high] (no upper bound when ``high`` is None)."""
    if not isinstance(value, (int, np.integer)) or isinstance(value, (bool, np.bool_)):
        raise ScenarioError(f"{where}: expected a whole number, got {shown(value)}")
    if value < low or (high is not None and value > high):
        raise ScenarioError(f"{where}: must lie within [{low}, {'∞' if high is None else high}], got {value}")
    return int(value)


# --- ranges as data: TOML files and overrides ---------------------------------------------------


def ranges_to_dict(ranges: ScenarioRanges) -> dict:
    """Plain data, as under ``[ranges]`` in a TOML file: every field, pairs as lists."""
    return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(ranges).items()}


def ranges_from_dict(data: Mapping[str, Any]) -> ScenarioRanges:
    """Ranges from plain data: any subset of the fields; the others keep their defaults."""
    if not isinstance(data, Mapping):
        raise ScenarioError(f"ranges: expected a table, got {type(data).__name__}")
    known = [f.name for f in fields(ScenarioRanges)]
    unknown = sorted(set(data) - set(known), key=str)
    if unknown:
        raise ScenarioError(f"ranges.{key_shown(unknown[0])}: unknown key (known: {', '.join(sorted(known))})")
    return ScenarioRanges(**data)


def ranges_with(ranges: ScenarioRanges, overrides: Mapping[str, object]) -> ScenarioRanges:
    """``ranges`` with some fields replaced (say, from command-line flags), each checked as in a file."""
    return ranges_from_dict({**ranges_to_dict(ranges), **overrides})


def loads_ranges(text: str, source: str | None = None) -> ScenarioRanges:
    """Ranges from TOML text holding one ``[ranges]`` table; ``source`` is named in every error."""
    data = parse_toml(text, source or "<string>")
    try:
        unknown = sorted(set(data) - {"ranges"})
        if unknown:
            raise ScenarioError(f"{key_shown(unknown[0])}: unknown key (a ranges file holds one [ranges] table)")
        return ranges_from_dict(data["ranges"])
    except ScenarioError as exc:
        if source is None:
            raise
        raise ScenarioError(f"{exc} (in {source})") from None


def load_ranges(path: str | Path) -> ScenarioRanges:
    """Read ranges from a TOML file with a ``[ranges]`` table."""
    return loads_ranges(read_input_file(path), str(path))


def dumps_ranges(ranges: ScenarioRanges) -> str:
    return tomli_w.dumps({"ranges": ranges_to_dict(ranges)})


# --- drawing a scenario -------------------------------------------------------------------------


def random_scenario(
    rng: np.random.Generator,
    ranges: ScenarioRanges = ScenarioRanges(),
    name: str = "random",
    description: str = "random scenario (mpc_hunt.sweep.random_scenario)",
) -> Scenario:
    """A valid scenario drawn from ``ranges`` with ``rng``; the same generator state gives the same scenario.

    Obstacles lie inside the arena, their surfaces at least ``margin`` apart.
    Every start lies in the arena, farther than radius + R_safe + ``margin``
    from every obstacle's centre, and at least ``min_spacing`` from every other
    start. If ``max_tries`` draws cannot place one of them, the ranges are
    (nearly) impossible: a ScenarioError names the count to lower.
    """
    hunt = ranges.hunt()
    n_defenders = int(rng.integers(*ranges.n_defenders, endpoint=True))
    n_obstacles = int(rng.integers(*ranges.n_obstacles, endpoint=True))
    obstacles = _place_obstacles(rng, ranges, n_obstacles)
    clearance = hunt.safety_distance + ranges.margin

    def clear(p: Vector) -> bool:
        return all(math.dist(p, o.centre) > o.radius + clearance for o in obstacles)

    advice = "lower n_obstacles or obstacle_radius, or enlarge the arena"
    p_a = _draw(
        rng,
        ranges.arena,
        clear,
        ranges.max_tries,
        f"ranges.n_obstacles: no start for the attacker clear of {n_obstacles} obstacles in "
        f"{ranges.max_tries} draws; {advice}",
    )
    heading = float(rng.uniform(0.0, 2.0 * math.pi))
    ratio = float(rng.uniform(*ranges.speed_ratio))
    perception_radius = float(rng.uniform(*ranges.perception_radius))
    speeds = [float(rng.uniform(*ranges.defender_speed)) for _ in range(n_defenders)]
    starts: list[Vector] = []
    for k in range(n_defenders):
        starts.append(
            _draw(
                rng,
                ranges.arena,
                lambda p: clear(p) and all(math.dist(p, q) >= ranges.min_spacing for q in [p_a, *starts]),
                ranges.max_tries,
                f"ranges.n_defenders: no start for defender {k + 1} of {n_defenders} at least min_spacing "
                f"{ranges.min_spacing} m from the other robots and clear of {n_obstacles} obstacles in "
                f"{ranges.max_tries} draws; lower n_defenders, min_spacing or n_obstacles, or enlarge the arena",
            )
        )
    v_a = ratio * min(speeds)
    attacker = Attacker(p_a, (v_a * math.cos(heading), v_a * math.sin(heading)), v_a, perception_radius)
    # Drawn last and always, so that the failure settings never change the rest of the scenario.
    fails, failing, fails_at = (
        rng.random() < ranges.defender_failure,
        rng.integers(n_defenders),
        float(rng.uniform(*ranges.failure_time)),
    )
    defenders = tuple(
        Defender(p, v, fails_at if fails and k == failing else None) for k, (p, v) in enumerate(zip(starts, speeds))
    )
    return Scenario(
        name=name,
        description=description,
        attacker=attacker,
        defenders=defenders,
        obstacles=obstacles,
        hunt=hunt,
        arena=ranges.arena,
    )


def _place_obstacles(rng: np.random.Generator, ranges: ScenarioRanges, n: int) -> tuple[Obstacle, ...]:
    x_min, y_min, x_max, y_max = ranges.arena
    placed: list[Obstacle] = []
    for k in range(n):
        r = float(rng.uniform(*ranges.obstacle_radius))
        centre = _draw(
            rng,
            (x_min + r, y_min + r, x_max - r, y_max - r),
            lambda c: all(math.dist(c, o.centre) >= r + o.radius + ranges.margin for o in placed),
            ranges.max_tries,
            f"ranges.n_obstacles: no place for obstacle {k + 1} of {n} (radius {r:.3g} m) at least "
            f"margin {ranges.margin} m from the others in {ranges.max_tries} draws; lower n_obstacles "
            f"or obstacle_radius, or enlarge the arena",
        )
        placed.append(Obstacle(centre, r))
    return tuple(placed)


def _draw(
    rng: np.random.Generator,
    box: tuple[float, float, float, float],
    accept: Callable[[Vector], bool],
    tries: int,
    failure: str,
) -> Vector:
    """A point uniform in ``box`` that ``accept``s, by rejection; ``failure`` after ``tries`` draws."""
    x_min, y_min, x_max, y_max = box
    for _ in range(tries):
        p = (float(rng.uniform(x_min, x_max)), float(rng.uniform(y_min, y_max)))
        if accept(p):
            return p
    raise ScenarioError(failure)


# --- sweeps ---------------------------------------------------------------------------------------


def sweep_rng(seed: int, index: int) -> np.random.Generator:
    """The generator of scenario ``index`` of the sweep ``seed``: child ``index`` of ``SeedSequence(seed)``."""
    sequence = np.random.SeedSequence(_whole(seed, "seed"), spawn_key=(_whole(index, "index"),))
    return np.random.default_rng(sequence)


def sweep_scenario(seed: int, index: int, ranges: ScenarioRanges = ScenarioRanges()) -> Scenario:
    """Scenario ``index`` of the sweep ``seed``, named ``random-<seed>-<index>``."""
    return random_scenario(
        sweep_rng(seed, index),
        ranges,
        name=f"random-{seed}-{index}",
        description=f"random scenario {index} of the sweep with seed {seed} (mpc_hunt.sweep.random_scenario)",
    )

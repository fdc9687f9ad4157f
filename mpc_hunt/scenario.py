"""A hunt declared as data: defenders, attacker, obstacles and the hunt's parameters.

A scenario is checked when it is built: every number finite, every radius and
speed positive, no start inside an obstacle, every defender faster than the
attacker (the paper's assumption max|v_a| < max|v_d|). A failed check raises
:class:`~mpc_hunt.errors.ScenarioError` whose message names the field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np

from mpc_hunt.errors import ScenarioError

Vector = tuple[float, float]


def _is_number(value: object) -> bool:
    """A real number, not a bool (a TOML ``true``) and not a numeric string."""
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def _vector(value: object, where: str) -> Vector:
    if not (isinstance(value, (list, tuple, np.ndarray)) and len(value) == 2 and all(map(_is_number, value))):
        raise ScenarioError(f"{where}: expected two numbers [x, y], got {value!r}")
    x, y = float(value[0]), float(value[1])
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ScenarioError(f"{where}: must be finite, got [{x}, {y}]")
    return (x, y)


def _number(value: object, where: str, *, positive: bool = False, non_negative: bool = False) -> float:
    if not _is_number(value):
        raise ScenarioError(f"{where}: expected a number, got {value!r}")
    x = float(value)  # type: ignore[arg-type]
    if not math.isfinite(x):
        raise ScenarioError(f"{where}: must be finite, got {x}")
    if positive and x <= 0:
        raise ScenarioError(f"{where}: must be positive, got {x}")
    if non_negative and x < 0:
        raise ScenarioError(f"{where}: must not be negative, got {x}")
    return x


@dataclass(frozen=True)
class Defender:
    """A defender robot: single integrator (Eq. 1) starting at ``start``, speed ≤ ``max_speed``."""

    start: Vector
    max_speed: float

    def validated(self, where: str) -> "Defender":
        return Defender(_vector(self.start, f"{where}.start"),
                        _number(self.max_speed, f"{where}.max_speed", positive=True))


@dataclass(frozen=True)
class Attacker:
    """The attacker (Eq. 2): nominal velocity, speed limit and perception radius R_agg."""

    start: Vector
    nominal_velocity: Vector
    max_speed: float
    perception_radius: float

    def validated(self, where: str) -> "Attacker":
        return Attacker(_vector(self.start, f"{where}.start"),
                        _vector(self.nominal_velocity, f"{where}.nominal_velocity"),
                        _number(self.max_speed, f"{where}.max_speed", positive=True),
                        _number(self.perception_radius, f"{where}.perception_radius", positive=True))


@dataclass(frozen=True)
class Obstacle:
    """A circular obstacle; it repels like a stationary defender (Eq. 3, measured from its surface)."""

    centre: Vector
    radius: float

    def validated(self, where: str) -> "Obstacle":
        return Obstacle(_vector(self.centre, f"{where}.centre"),
                        _number(self.radius, f"{where}.radius", positive=True))


@dataclass(frozen=True)
class HuntParameters:
    """The hunt's parameters (names follow the paper; see docs/model.md for each choice)."""

    hunt_radius: float = 0.5            # R_hunt, Eq. 5
    centre_tolerance: float = 0.25      # how far from the members' centroid still counts as Eq. 4
    eta: float = 1.0                    # η, the field's gain (Eq. 2)
    k_d: float = 1.0                    # weight of the defenders' field in the resultant (Eq. 9)
    k_o: float = 1.0                    # weight of the obstacles' field in the resultant (Eq. 9)
    omega: float = 0.5                  # ω, intercept vs obstacle-avoidance blend (Eq. 6)
    protective_distance: float = 1.0    # range of an obstacle's field, from its surface
    safety_distance: float = 0.1        # R_safe, Eq. 15, from an obstacle's surface
    min_separation: float = 0.2         # smallest defender–defender distance in the capture stage
    min_attacker_distance: float = 0.1  # smallest defender–attacker distance (H is singular at 0)
    time_step: float = 0.1              # T, the sampling time of Eq. 13 and of the simulator
    time_limit: float = 600.0           # a hunt not captured by then has failed
    hold_time: float = 2.0              # how long Eqs. 4–5 must hold to count as a capture

    def validated(self, where: str) -> "HuntParameters":
        values = {}
        for f in fields(self):
            name = f.name
            non_negative = name in ("safety_distance", "min_separation", "hold_time")
            values[name] = _number(getattr(self, name), f"{where}.{name}",
                                   positive=not non_negative, non_negative=non_negative)
        if values["omega"] > 1:
            raise ScenarioError(f"{where}.omega: must lie in (0, 1], got {values['omega']}")
        if values["time_step"] > values["time_limit"]:
            raise ScenarioError(f"{where}.time_step: must not exceed time_limit ({values['time_limit']})")
        return HuntParameters(**values)


@dataclass(frozen=True)
class Scenario:
    """One hunt: who starts where, how fast, among which obstacles, under which parameters."""

    name: str
    defenders: tuple[Defender, ...]
    attacker: Attacker
    obstacles: tuple[Obstacle, ...] = ()
    hunt: HuntParameters = field(default_factory=HuntParameters)
    description: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise ScenarioError(f"name: must be a non-empty string, got {self.name!r}")
        if not isinstance(self.description, str):
            raise ScenarioError(f"description: must be a string, got {self.description!r}")
        if not isinstance(self.defenders, (tuple, list)) or len(self.defenders) == 0:
            raise ScenarioError("defenders: at least one defender is needed")
        set_ = object.__setattr__  # frozen dataclass: normalise in place once
        set_(self, "defenders", tuple(_as(Defender, d, f"defenders[{i}]").validated(f"defenders[{i}]")
                                      for i, d in enumerate(self.defenders)))
        set_(self, "attacker", _as(Attacker, self.attacker, "attacker").validated("attacker"))
        set_(self, "obstacles", tuple(_as(Obstacle, o, f"obstacles[{i}]").validated(f"obstacles[{i}]")
                                      for i, o in enumerate(self.obstacles)))
        set_(self, "hunt", _as(HuntParameters, self.hunt, "hunt").validated("hunt"))
        self._check_geometry()

    def _check_geometry(self) -> None:
        for i, d in enumerate(self.defenders):
            if d.max_speed <= self.attacker.max_speed:
                raise ScenarioError(
                    f"defenders[{i}].max_speed: {d.max_speed} m/s is not faster than the attacker's "
                    f"max_speed {self.attacker.max_speed} m/s (the strategy assumes max|v_a| < max|v_d|)")
        starts = [(f"defenders[{i}].start", d.start) for i, d in enumerate(self.defenders)]
        starts.append(("attacker.start", self.attacker.start))
        for where, p in starts:
            for j, o in enumerate(self.obstacles):
                if math.dist(p, o.centre) <= o.radius:
                    raise ScenarioError(f"{where}: {list(p)} lies inside obstacles[{j}] "
                                        f"(centre {list(o.centre)}, radius {o.radius})")
        for i in range(len(starts)):
            for j in range(i + 1, len(starts)):
                if starts[i][1] == starts[j][1]:
                    raise ScenarioError(f"{starts[j][0]}: coincides with {starts[i][0]}")

    # Array views used by the model and the simulator.
    @property
    def defender_starts(self) -> np.ndarray:
        return np.array([d.start for d in self.defenders], dtype=float)

    @property
    def defender_max_speeds(self) -> np.ndarray:
        return np.array([d.max_speed for d in self.defenders], dtype=float)

    @property
    def obstacle_centres(self) -> np.ndarray:
        return np.array([o.centre for o in self.obstacles], dtype=float).reshape(-1, 2)

    @property
    def obstacle_radii(self) -> np.ndarray:
        return np.array([o.radius for o in self.obstacles], dtype=float)


def _as(cls: type, value: object, where: str):
    if isinstance(value, cls):
        return value
    raise ScenarioError(f"{where}: expected a {cls.__name__}, got {type(value).__name__}")

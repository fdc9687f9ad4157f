"""A hunt declared as data: defenders, attacker, obstacles, the hunt's parameters, an optional arena.

A scenario is checked when it is built: every number finite and within the
input limits below, every radius and speed positive, the attacker's start
inside the arena, no start inside an obstacle, no two robots starting on the
same spot, every defender faster than the attacker (the paper's assumption
max|v_a| < max|v_d|). A failed check raises
:class:`~mpc_hunt.errors.ScenarioError` whose message names the field.
docs/robustness.md lists the limits and the reason for each.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from functools import cached_property

import numpy as np

from mpc_hunt.errors import ScenarioError
from mpc_hunt.world.arena import Arena, beyond_edge
from mpc_hunt.world.behaviours import BEHAVIOURS
from mpc_hunt.world.packed import parameters

Vector = tuple[float, float]

LIMITS_DOC = "docs/robustness.md"
MAX_MAGNITUDE = 1e6  # any number: coordinates and lengths (m), times (s), gains, velocities (m/s)
MAX_SPEED = 1e3  # m/s, a robot's max_speed
MAX_STEPS = 10_000_000  # time_limit / time_step: simulator steps in one hunt
MAX_DEFENDERS = 20
MAX_OBSTACLES = 100
MAX_DISTURBANCE = 10.0  # of the attacker's max_speed: the noisy attacker's largest disturbance


def shown(value: object, width: int = 60) -> str:
    """``repr(value)`` cut to ``width`` characters, so an error message stays one short line."""
    text = repr(value)
    return text if len(text) <= width else text[: width - 3] + "..."


def key_shown(key: object) -> str:
    """A key read from a file, as an error message names it: bare when it is a plain name, else quoted."""
    return key if isinstance(key, str) and key.isidentifier() else shown(key)


def _is_number(value: object) -> bool:
    """A real number, not a bool (a TOML ``true``) and not a numeric string."""
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def _limit_error(where: str, value: object, limit: float, unit: str) -> ScenarioError:
    return ScenarioError(f"{where}: {shown(value)} is beyond the limit of {limit:g}{unit} ({LIMITS_DOC})")


def _finite(value: object, where: str, limit: float, unit: str) -> float:
    """A number as a float, finite and within ±``limit``."""
    try:
        x = float(value)  # type: ignore[arg-type]
    except OverflowError:  # a whole number beyond the range of a float
        raise _limit_error(where, value, limit, unit) from None
    if not math.isfinite(x):
        raise ScenarioError(f"{where}: must be finite, got {x}")
    if abs(x) > limit:
        raise _limit_error(where, x, limit, unit)
    return x


def checked_number(
    value: object,
    where: str,
    *,
    positive: bool = False,
    non_negative: bool = False,
    limit: float = MAX_MAGNITUDE,
    unit: str = "",
) -> float:
    """``value`` as a finite float within ±``limit``, optionally positive or non-negative."""
    if not _is_number(value):
        raise ScenarioError(f"{where}: expected a number, got {shown(value)}")
    x = _finite(value, where, limit, unit)
    if positive and x <= 0:
        raise ScenarioError(f"{where}: must be positive, got {x}")
    if non_negative and x < 0:
        raise ScenarioError(f"{where}: must not be negative, got {x}")
    return x


def _numbers(value: object, count: int, where: str, form: str, limit: float, unit: str) -> tuple[float, ...]:
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not (isinstance(value, (list, tuple)) and len(value) == count and all(map(_is_number, value))):
        raise ScenarioError(f"{where}: expected {form}, got {shown(value)}")
    xs = []
    for x in value:
        try:
            xs.append(float(x))
        except OverflowError:
            raise _limit_error(where, value, limit, unit) from None
    if not all(map(math.isfinite, xs)):
        raise ScenarioError(f"{where}: must be finite, got {xs}")
    if any(abs(x) > limit for x in xs):
        raise _limit_error(where, xs, limit, unit)
    return tuple(xs)


def checked_vector(value: object, where: str, *, limit: float = MAX_MAGNITUDE, unit: str = " m") -> Vector:
    """``value`` as two finite floats [x, y], each within ±``limit``."""
    return _numbers(value, 2, where, "two numbers [x, y]", limit, unit)  # type: ignore[return-value]


def checked_arena(value: object, where: str = "arena") -> Arena:
    """``value`` as an arena [x_min, y_min, x_max, y_max] with x_min < x_max and y_min < y_max."""
    x_min, y_min, x_max, y_max = _numbers(
        value, 4, where, "four numbers [x_min, y_min, x_max, y_max]", MAX_MAGNITUDE, " m"
    )
    if not (x_min < x_max and y_min < y_max):
        raise ScenarioError(
            f"{where}: expected x_min < x_max and y_min < y_max, got [{x_min}, {y_min}, {x_max}, {y_max}]"
        )
    return (x_min, y_min, x_max, y_max)


@dataclass(frozen=True)
class Defender:
    """A defender robot: single integrator (Eq. 1) starting at ``start``, speed ≤ ``max_speed``.

    ``fails_at`` (s), if given, is when the robot stops for good: from then on it
    stands still, is never commanded, and stays a member of the hunting circle
    (a stationary defender, as an obstacle is).
    """

    start: Vector
    max_speed: float
    fails_at: float | None = None

    def validated(self, where: str) -> "Defender":
        fails_at = (
            None
            if self.fails_at is None
            else checked_number(self.fails_at, f"{where}.fails_at", non_negative=True, unit=" s")
        )
        return Defender(
            checked_vector(self.start, f"{where}.start"),
            checked_number(self.max_speed, f"{where}.max_speed", positive=True, limit=MAX_SPEED, unit=" m/s"),
            fails_at,
        )


@dataclass(frozen=True)
class Attacker:
    """The attacker (Eq. 2): nominal velocity, speed limit and perception radius R_agg, and how the world moves
    it: ``behaviour`` (:mod:`mpc_hunt.world.behaviours`; the paper's ``apf`` by default), the radius within
    which an evader senses defenders (``sensing_radius``; ``apf`` senses at R_agg) and the ``noisy``
    attacker's ``disturbance`` (a fraction of ``max_speed``)."""

    start: Vector
    nominal_velocity: Vector
    max_speed: float
    perception_radius: float
    behaviour: str = "apf"
    sensing_radius: float | None = None
    disturbance: float | None = None

    def validated(self, where: str) -> "Attacker":
        if not isinstance(self.behaviour, str) or self.behaviour not in BEHAVIOURS:
            raise ScenarioError(
                f"{where}.behaviour: unknown {shown(self.behaviour)} (available: {', '.join(BEHAVIOURS)})"
            )
        sensing = disturbance = None
        if self.sensing_radius is not None:
            if self.behaviour == "apf" or self.behaviour == "noisy":
                raise ScenarioError(
                    f"{where}.sensing_radius: the {self.behaviour} attacker senses at its "
                    "perception_radius; set that instead"
                )
            sensing = checked_number(self.sensing_radius, f"{where}.sensing_radius", positive=True, unit=" m")
        if self.disturbance is not None:
            if self.behaviour != "noisy":
                raise ScenarioError(f"{where}.disturbance: only the noisy attacker takes one, not {self.behaviour}")
            disturbance = checked_number(
                self.disturbance, f"{where}.disturbance", non_negative=True, limit=MAX_DISTURBANCE
            )
        return Attacker(
            checked_vector(self.start, f"{where}.start"),
            checked_vector(self.nominal_velocity, f"{where}.nominal_velocity", unit=" m/s"),
            checked_number(self.max_speed, f"{where}.max_speed", positive=True, limit=MAX_SPEED, unit=" m/s"),
            checked_number(self.perception_radius, f"{where}.perception_radius", positive=True, unit=" m"),
            self.behaviour,
            sensing,
            disturbance,
        )


@dataclass(frozen=True)
class Obstacle:
    """A circular obstacle; it repels like a stationary defender (Eq. 3, measured from its surface)."""

    centre: Vector
    radius: float

    def validated(self, where: str) -> "Obstacle":
        return Obstacle(
            checked_vector(self.centre, f"{where}.centre"),
            checked_number(self.radius, f"{where}.radius", positive=True, unit=" m"),
        )


_SECONDS = ("time_step", "time_limit", "hold_time")
_GAINS = ("eta", "k_d", "k_o", "omega")


@dataclass(frozen=True)
class HuntParameters:
    """The hunt's parameters (names follow the paper; see docs/model.md for each choice)."""

    hunt_radius: float = 0.5  # R_hunt, Eq. 5
    centre_tolerance: float = 0.25  # how far from the members' centroid still counts as Eq. 4
    eta: float = 1.0  # η, the field's gain (Eq. 2)
    k_d: float = 1.0  # weight of the defenders' field in the resultant (Eq. 9)
    k_o: float = 1.0  # weight of the obstacles' field in the resultant (Eq. 9)
    omega: float = 0.5  # ω, intercept vs obstacle-avoidance blend (Eq. 6)
    protective_distance: float = 1.0  # range of an obstacle's field, from its surface
    safety_distance: float = 0.1  # R_safe, Eq. 15, from an obstacle's surface
    min_separation: float = 0.2  # smallest defender–defender distance in the capture stage
    min_attacker_distance: float = 0.1  # smallest defender–attacker distance (H is singular at 0)
    time_step: float = 0.1  # T, the sampling time of Eq. 13 and of the simulator
    time_limit: float = 600.0  # a hunt not captured by then has failed
    hold_time: float = 2.0  # how long Eqs. 4–5 must hold to count as a capture

    def validated(self, where: str) -> "HuntParameters":
        values = {}
        for f in fields(self):
            name = f.name
            non_negative = name in ("safety_distance", "min_separation", "hold_time")
            unit = " s" if name in _SECONDS else "" if name in _GAINS else " m"
            values[name] = checked_number(
                getattr(self, name), f"{where}.{name}", positive=not non_negative, non_negative=non_negative, unit=unit
            )
        if values["omega"] > 1:
            raise ScenarioError(f"{where}.omega: must lie in (0, 1], got {values['omega']}")
        if values["time_step"] > values["time_limit"]:
            raise ScenarioError(f"{where}.time_step: must not exceed time_limit ({values['time_limit']})")
        steps = values["time_limit"] / values["time_step"]
        if steps > MAX_STEPS:
            raise ScenarioError(
                f"{where}.time_step: time_limit / time_step = {steps:.4g} steps is beyond the "
                f"limit of {MAX_STEPS:g} steps ({LIMITS_DOC})"
            )
        return HuntParameters(**values)


@dataclass(frozen=True)
class Scenario:
    """One hunt: who starts where, how fast, among which obstacles, under which parameters, in which arena."""

    name: str
    defenders: tuple[Defender, ...]
    attacker: Attacker
    obstacles: tuple[Obstacle, ...] = ()
    hunt: HuntParameters = field(default_factory=HuntParameters)
    description: str = ""
    arena: Arena | None = None  # (x_min, y_min, x_max, y_max); mpc_hunt/world/arena.py

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise ScenarioError(f"name: must be a non-empty string, got {shown(self.name)}")
        if not isinstance(self.description, str):
            raise ScenarioError(f"description: must be a string, got {shown(self.description)}")
        if not isinstance(self.defenders, (tuple, list)) or len(self.defenders) == 0:
            raise ScenarioError("defenders: at least one defender is needed")
        if len(self.defenders) > MAX_DEFENDERS:
            raise ScenarioError(
                f"defenders: {len(self.defenders)} defenders is beyond the limit of {MAX_DEFENDERS} ({LIMITS_DOC})"
            )
        if not isinstance(self.obstacles, (tuple, list)):
            raise ScenarioError(f"obstacles: expected a list of obstacles, got {type(self.obstacles).__name__}")
        if len(self.obstacles) > MAX_OBSTACLES:
            raise ScenarioError(
                f"obstacles: {len(self.obstacles)} obstacles is beyond the limit of {MAX_OBSTACLES} ({LIMITS_DOC})"
            )
        set_ = object.__setattr__  # frozen dataclass: normalise in place once
        set_(self, "defenders", _validated_all(Defender, self.defenders, "defenders"))
        set_(self, "attacker", _as(Attacker, self.attacker, "attacker").validated("attacker"))
        set_(self, "obstacles", _validated_all(Obstacle, self.obstacles, "obstacles"))
        set_(self, "hunt", _as(HuntParameters, self.hunt, "hunt").validated("hunt"))
        if self.arena is not None:
            set_(self, "arena", checked_arena(self.arena))
        self._check_geometry()

    def _check_geometry(self) -> None:
        for i, d in enumerate(self.defenders):
            if d.max_speed <= self.attacker.max_speed:
                raise ScenarioError(
                    f"defenders[{i}].max_speed: {d.max_speed} m/s is not faster than the attacker's "
                    f"max_speed {self.attacker.max_speed} m/s (the strategy assumes max|v_a| < max|v_d|)"
                )
        check_positions(
            self,
            ("attacker.start", self.attacker.start),
            [(f"defenders[{i}].start", d.start) for i, d in enumerate(self.defenders)],
        )

    # Array views used by the model and the simulator, made once and read-only.
    @property
    def defender_starts(self) -> np.ndarray:
        return np.array([d.start for d in self.defenders], dtype=float)

    @cached_property
    def defender_max_speeds(self) -> np.ndarray:
        return _read_only(np.array([d.max_speed for d in self.defenders], dtype=float))

    def failed(self, time: float) -> np.ndarray:
        """Which defenders have stopped for good by ``time`` (``Defender.fails_at``)."""
        return np.array([d.fails_at is not None and time >= d.fails_at for d in self.defenders])

    @cached_property
    def obstacle_centres(self) -> np.ndarray:
        return _read_only(np.array([o.centre for o in self.obstacles], dtype=float).reshape(-1, 2))

    @cached_property
    def obstacle_radii(self) -> np.ndarray:
        return _read_only(np.array([o.radius for o in self.obstacles], dtype=float))

    @cached_property
    def packed(self) -> np.ndarray:
        """The parameters as the compiled rules read them (:func:`mpc_hunt.world.packed.parameters`)."""
        return _read_only(parameters(self))


def _read_only(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array


def check_positions(scenario: Scenario, attacker: tuple[str, Vector], defenders: list[tuple[str, Vector]]) -> None:
    """Where the robots of ``scenario`` may stand, as (field, [x, y]) pairs: at a start or in a state file.

    The attacker inside the arena (if there is one); no robot inside an
    obstacle (on its boundary counts as inside); no two robots on the same spot.
    """
    where, p_a = attacker
    if scenario.arena is not None and beyond_edge(scenario.arena, p_a):
        raise ScenarioError(f"{where}: {list(p_a)} lies outside the arena {list(scenario.arena)}")
    robots = [attacker, *defenders]
    for where, p in robots:
        for j, o in enumerate(scenario.obstacles):
            if math.dist(p, o.centre) <= o.radius:
                raise ScenarioError(
                    f"{where}: {list(p)} lies inside obstacles[{j}] (centre {list(o.centre)}, radius {o.radius})"
                )
    for i in range(len(robots)):
        for j in range(i + 1, len(robots)):
            if robots[i][1] == robots[j][1]:
                raise ScenarioError(f"{robots[j][0]}: coincides with {robots[i][0]}")


def _as(cls: type, value: object, where: str):
    if isinstance(value, cls):
        return value
    raise ScenarioError(f"{where}: expected a {cls.__name__}, got {type(value).__name__}")


def _validated_all(cls: type, values: tuple | list, field: str) -> tuple:
    """Every one of ``values`` a ``cls``, validated, an error naming it by its place (``field[i]``)."""
    return tuple(_as(cls, value, f"{field}[{i}]").validated(f"{field}[{i}]") for i, value in enumerate(values))

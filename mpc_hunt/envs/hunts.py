"""Which hunt an environment plays at each reset, and the sizes its spaces are built from.

With no ``scenario``, every reset draws a random hunt from the sweep's generator
(:func:`mpc_hunt.sweep.random_scenario.random_scenario`) with ``ranges`` (the sweep's
defaults, but ``defenders`` robots: an environment's agents and spaces are fixed),
from the generator the reset's seed made; ``reset(options={"scenario": s})`` plays
``s`` once instead (it must fit the spaces: as many defenders, at most as many
obstacles, robots no faster, a step no shorter). A given ``scenario`` is played at
every reset; its team is the environment's.

Every argument is checked when the environment is built (:class:`~mpc_hunt.errors.OptionError`
naming it): a ``defenders`` count that contradicts the scenario's or the ranges', ``ranges``
beside a scenario (they would not be used), and a source whose hunts could leave the
observation's ±MAX_MAGNITUDE (a robot's start plus its top speed over the whole hunt, or
the hunt's last time).
"""

from __future__ import annotations

import dataclasses
from typing import cast

import numpy as np

from mpc_hunt.errors import OptionError
from mpc_hunt.sim.world_step import steps
from mpc_hunt.sweep.random_scenario import ScenarioRanges, random_scenario
from mpc_hunt.world.scenario import MAX_DEFENDERS, MAX_MAGNITUDE, Scenario

DEFAULT_DEFENDERS = 3
PROBE_SEED = 0  # the random hunt the settings are checked on before the first reset


@dataclasses.dataclass(frozen=True)
class Hunts:
    """The source of an environment's hunts (the module's docstring) and the bounds of its spaces. ``defenders``
    None: the scenario's team, or a random hunt's 3 (the ranges' count when they fix one)."""

    scenario: Scenario | None = None
    ranges: ScenarioRanges | None = None
    defenders: int | None = None

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        d = self.defenders
        if d is not None and (
            isinstance(d, bool) or not isinstance(d, (int, np.integer)) or not 1 <= d <= MAX_DEFENDERS
        ):
            raise OptionError(f"defenders: a whole number from 1 to {MAX_DEFENDERS}, got {d!r}")
        if self.scenario is not None:
            if not isinstance(self.scenario, Scenario):
                raise OptionError(f"scenario: a mpc_hunt Scenario or None, got {type(self.scenario).__name__}")
            if self.ranges is not None:
                raise OptionError(
                    "ranges: a given scenario is played at every reset, so ranges would not be used; "
                    "give one or the other"
                )
            team = len(self.scenario.defenders)
            if d is not None and d != team:
                raise OptionError(
                    f"defenders: {d}, but the scenario has {team}; leave defenders out (the "
                    f"scenario's team is the environment's) or give a scenario of {d}"
                )
            set_(self, "defenders", team)
            _check_scenario_reach("scenario", self.scenario)
            return
        ranges = ScenarioRanges() if self.ranges is None else self.ranges
        if not isinstance(ranges, ScenarioRanges):
            raise OptionError(f"ranges: a ScenarioRanges or None, got {type(ranges).__name__}")
        low, high = ranges.n_defenders
        if d is None:
            d = low if self.ranges is not None and low == high else DEFAULT_DEFENDERS
        if self.ranges is not None and not low <= d <= high:
            raise OptionError(
                f"defenders: {d}, outside ranges.n_defenders ({low}, {high}); give defenders within "
                f"them (an environment's team is fixed)"
            )
        set_(self, "defenders", int(d))
        set_(self, "ranges", dataclasses.replace(ranges, n_defenders=(int(d), int(d))))
        _check_reach(
            "ranges",
            max(map(abs, self.drawn.arena)),
            max(self.attacker_speed, self.defender_speed),
            self.drawn.time_limit + self.time_step,
        )

    @property
    def team(self) -> int:
        """How many defenders every hunt has: ``defenders`` as set on construction (never None after)."""
        return cast(int, self.defenders)

    @property
    def drawn(self) -> ScenarioRanges:
        """The ranges the hunts are drawn from, when there is no ``scenario`` (set on construction then)."""
        return cast(ScenarioRanges, self.ranges)

    @property
    def max_obstacles(self) -> int:
        return len(self.scenario.obstacles) if self.scenario is not None else self.drawn.n_obstacles[1]

    @property
    def attacker_speed(self) -> float:
        """The fastest attacker this source plays (the bound of its action)."""
        if self.scenario is not None:
            return self.scenario.attacker.max_speed
        return self.drawn.speed_ratio[1] * self.drawn.defender_speed[1]

    @property
    def defender_speed(self) -> float:
        """The fastest defender this source plays (the bound of its actions)."""
        if self.scenario is not None:
            return float(self.scenario.defender_max_speeds.max())
        return self.drawn.defender_speed[1]

    @property
    def time_step(self) -> float:
        """The step of this source's hunts (the shortest its observation's bounds allow for)."""
        return (self.scenario.hunt if self.scenario is not None else self.drawn.hunt()).time_step

    def probe(self) -> Scenario:
        """A hunt of the source, to check settings on before the first reset."""
        return (
            self.scenario
            if self.scenario is not None
            else random_scenario(np.random.default_rng(PROBE_SEED), self.drawn, name="env")
        )

    def draw(self, rng: np.random.Generator, given: Scenario | None) -> Scenario:
        """The hunt of this reset: ``given`` (from :meth:`given`), else the source's."""
        if given is not None:
            return given
        return self.scenario if self.scenario is not None else random_scenario(rng, self.drawn, name="env")

    def given(self, options: dict | None) -> Scenario | None:
        """The scenario a reset's ``options`` give, checked against the spaces, or None. Other keys are left to
        wrappers (PettingZoo's API test hands one over and expects it ignored)."""
        if options is not None and not isinstance(options, dict):
            raise OptionError(
                f"options: None or a dict (key 'scenario': a hunt to play once), got {type(options).__name__}"
            )
        given = (options or {}).get("scenario")
        if given is not None:
            if (
                not isinstance(given, Scenario)
                or len(given.defenders) != self.defenders
                or len(given.obstacles) > self.max_obstacles
                or given.attacker.max_speed > self.attacker_speed
                or float(given.defender_max_speeds.max()) > self.defender_speed
                or given.hunt.time_step < self.time_step
            ):
                raise OptionError(
                    f"options['scenario']: a Scenario that fits the spaces: {self.defenders} defenders "
                    f"no faster than {self.defender_speed:g} m/s, an attacker no faster than "
                    f"{self.attacker_speed:g} m/s, at most {self.max_obstacles} obstacles, a time "
                    f"step of at least {self.time_step:g} s"
                )
            _check_scenario_reach("options['scenario']", given)
        return given


def _check_scenario_reach(where: str, scenario: Scenario) -> None:
    speed = max(scenario.attacker.max_speed, float(scenario.defender_max_speeds.max()))
    starts = np.vstack([scenario.attacker.start, scenario.defender_starts])
    _check_reach(where, float(np.max(np.abs(starts))), speed, steps(scenario)[0] * scenario.hunt.time_step)


def _check_reach(where: str, start: float, speed: float, duration: float) -> None:
    """Refuse hunts whose robots (at most ``start`` from the origin, at ``speed``) or time could leave the
    observation's ±MAX_MAGNITUDE within ``duration``."""
    if duration > MAX_MAGNITUDE:
        raise OptionError(
            f"{where}: its hunts last up to {duration:.6g} s, beyond the observation's "
            f"{MAX_MAGNITUDE:g}; shorten the time limit"
        )
    if start + speed * duration > MAX_MAGNITUDE:
        raise OptionError(
            f"{where}: a robot could reach {start + speed * duration:.6g} m from the origin, beyond the "
            f"observation's ±{MAX_MAGNITUDE:g}; shorten the time limit or start nearer the origin"
        )

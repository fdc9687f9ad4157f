"""Which hunt an environment plays at each reset, and the sizes its spaces are built from.

With no ``scenario``, every reset draws a random hunt from the sweep's generator
(:func:`mpc_hunt.sweep.random_scenario.random_scenario`) with ``ranges`` (the sweep's
defaults, but ``defenders`` robots: an environment's agents and spaces are fixed),
from the generator the reset's seed made; ``reset(options={"scenario": s})`` plays
``s`` once instead (with as many defenders). A given ``scenario`` is played at every
reset.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mpc_hunt.errors import MpcHuntError
from mpc_hunt.sweep.random_scenario import ScenarioRanges, random_scenario
from mpc_hunt.world.scenario import Scenario

DEFAULT_DEFENDERS = 3


@dataclasses.dataclass(frozen=True)
class Hunts:
    """The source of an environment's hunts (the module's docstring) and the bounds of its spaces."""

    scenario: Scenario | None = None
    ranges: ScenarioRanges | None = None
    defenders: int = DEFAULT_DEFENDERS

    def __post_init__(self) -> None:
        if self.scenario is not None:
            object.__setattr__(self, "defenders", len(self.scenario.defenders))
            return
        ranges = self.ranges or ScenarioRanges()
        if isinstance(self.defenders, bool) or not isinstance(self.defenders, int) or self.defenders < 1:
            raise MpcHuntError(f"defenders: a whole number ≥ 1, got {self.defenders!r}")
        object.__setattr__(self, "ranges", dataclasses.replace(ranges, n_defenders=(self.defenders, self.defenders)))

    @property
    def max_obstacles(self) -> int:
        return len(self.scenario.obstacles) if self.scenario is not None else self.ranges.n_obstacles[1]

    @property
    def attacker_speed(self) -> float:
        """The fastest attacker this source plays (the bound of its action)."""
        if self.scenario is not None:
            return self.scenario.attacker.max_speed
        return self.ranges.speed_ratio[1] * self.ranges.defender_speed[1]

    @property
    def defender_speed(self) -> float:
        """The fastest defender this source plays (the bound of its actions)."""
        if self.scenario is not None:
            return float(self.scenario.defender_max_speeds.max())
        return self.ranges.defender_speed[1]

    def draw(self, rng: np.random.Generator, options: dict | None) -> Scenario:
        """The hunt of this reset."""
        given = (options or {}).get("scenario")
        if given is not None:
            if not isinstance(given, Scenario) or len(given.defenders) != self.defenders or \
                    len(given.obstacles) > self.max_obstacles:
                raise MpcHuntError(f"options['scenario']: a Scenario with {self.defenders} defenders and at most "
                                   f"{self.max_obstacles} obstacles")
            return given
        return self.scenario if self.scenario is not None else random_scenario(rng, self.ranges, name="env")

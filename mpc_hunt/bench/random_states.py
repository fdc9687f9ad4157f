"""Problem-set builder: random capture-stage states around random obstacle layouts, one case per family.

Each state is drawn, with the generator handed in, so that one constraint
family (its ``case``) is active at the one-step optimum:

- ``motion_limit``: the defenders far outside the ring (R_hunt / 2), so each
  wants to move further than r_d;
- ``equal_distance``: the defenders' bearings up to 45° off even spacing (20°
  in the other cases), so that, but for Eq. 14, they would stand at different
  distances;
- ``obstacle_safety``: an obstacle's safety circle just ahead of where a
  defender would step without it;
- ``separation``: a defender outside R_agg, held, just d_sep ahead of where
  one of the two in the capture stage would step without it;
- ``attacker_distance``: the attacker just off an obstacle, whose field pushes
  it towards the one defender in the capture stage, just beyond d_min (two
  defenders that close could not keep d_sep apart clear of the obstacle).

The controlled defenders start near the edge of R_agg (0.8 to 0.98 of it, where
the hunts spend their capture stage), about a third of a turn apart, at a
common distance from the attacker (within 1 mm), so Eq. 14 can hold from the
first step, and every inequality (Eqs. 13, 15, separation, attacker distance)
holds at the current positions. A draw is kept only if the one-step optimum
keeps every constraint (Eq. 14's included, within ``ACTIVE_TOLERANCE``), so
that success is possible, and its family is active there
(:mod:`mpc_hunt.bench.activity`); otherwise it is drawn again. Each state has its own
scenario: the template's robots and parameters, its own obstacles, starting
from the state.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mpc_hunt.bench.activity import ACTIVE_TOLERANCE, ActivityProbe
from mpc_hunt.bench.problem_set import ProblemEntry
from mpc_hunt.capture.evaluator import VIOLATION_NAMES
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.world import attacker
from mpc_hunt.world.geometry import direction, norm
from mpc_hunt.world.hunt_state import HuntState
from mpc_hunt.world.scenario import Defender, Obstacle, Scenario

MAX_DRAWS = 200
SPREAD = 1e-3  # m: the controlled defenders' distances to the attacker differ by at most this


def _near(rng: np.random.Generator, radius: float, n: int) -> np.ndarray:
    return radius + rng.uniform(-SPREAD / 2, SPREAD / 2, n)


def _layout(rng: np.random.Generator, template: Scenario, case: str) -> tuple[np.ndarray, np.ndarray, list]:
    """(attacker, defenders, obstacles as (centre, radius)) for one draw of ``case``."""
    hunt, n = template.hunt, len(template.defenders)
    reach = template.attacker.perception_radius
    p_a = rng.uniform(5.0, 15.0, 2)
    obstacles = []
    if case == "attacker_distance":
        radius, away = rng.uniform(0.3, 0.8), rng.uniform(0, 2 * np.pi)
        obstacles.append((p_a - direction(away) * (radius + rng.uniform(0.02, 0.05)), radius))
        # Beyond the attacker's next step (v_a T), so that holding still keeps the true bound at first.
        close = hunt.min_attacker_distance + rng.uniform(1.5, 2.5) * template.attacker.max_speed * hunt.time_step
        angles = np.concatenate([[away + rng.uniform(-0.1, 0.1)], rng.uniform(0, 2 * np.pi, n - 1)])
        distances = np.concatenate([[close], rng.uniform(1.1, 1.5, n - 1) * reach])
        return p_a, p_a + distances[:, None] * direction(angles), obstacles
    distances = _near(rng, rng.uniform(0.8, 0.98) * reach, n)
    jitter = np.radians(45 if case == "equal_distance" else 20)
    angles = rng.uniform(0, 2 * np.pi) + 2 * np.pi * np.arange(n) / n + rng.uniform(-jitter, jitter, n)
    if case == "separation":  # two in the capture stage, near the edge of R_agg; the rest outside it
        distances = _near(rng, rng.uniform(0.93, 0.98) * reach, n)
        angles[1] = angles[0] + np.pi + rng.uniform(-jitter, jitter)
        distances[2:] = rng.uniform(1.1, 1.5, n - 2) * reach
    defenders = p_a + distances[:, None] * direction(angles)
    for _ in range(rng.integers(0, 3)):  # others, somewhere around
        radius = rng.uniform(0.3, 1.0)
        obstacles.append((p_a + direction(rng.uniform(0, 2 * np.pi)) * (radius + rng.uniform(0.3, 1.5)), radius))
    return p_a, defenders, obstacles


def _ahead(rng: np.random.Generator, defenders: np.ndarray, step: np.ndarray, clearance: float) -> np.ndarray:
    """A point ``clearance`` plus 10 to 60 % of defender 0's ``step`` ahead of it, along that step."""
    length = float(norm(step[0]))
    return defenders[0] + (clearance + rng.uniform(0.1, 0.6) * length) * step[0] / max(length, 1e-12)


def _block(
    rng: np.random.Generator, template: Scenario, case: str, defenders: np.ndarray, obstacles: list, step: np.ndarray
) -> None:
    """Put an obstacle (``obstacle_safety``) or the last, held, defender (``separation``) just ahead of
    defender 0, across the ``step`` it takes when nothing is there."""
    if case == "obstacle_safety":
        radius = rng.uniform(0.2, 0.5)
        obstacles.append((_ahead(rng, defenders, step, radius + template.hunt.safety_distance), radius))
    else:
        defenders[-1] = _ahead(rng, defenders, step, template.hunt.min_separation)


def _admissible(template: Scenario, p_a: np.ndarray, defenders: np.ndarray, obstacles: list) -> bool:
    """A defender in the capture stage, and every inequality held at the current positions."""
    hunt = template.hunt
    if not attacker.perceives(template, p_a, defenders).any():
        return False
    if norm(defenders - p_a).min() < hunt.min_attacker_distance:
        return False
    gaps = norm(defenders[:, None] - defenders[None]) + np.eye(len(defenders)) * 1e9
    if gaps.min() < hunt.min_separation:
        return False
    return all(
        norm(p_a - centre) > radius and norm(defenders - centre).min() >= radius + hunt.safety_distance
        for centre, radius in obstacles
    )


def _scenario(
    template: Scenario, name: str, case: str, p_a: np.ndarray, defenders: np.ndarray, obstacles: list
) -> Scenario:
    return replace(
        template,
        name=name,
        description=f"A random capture-stage state (case {case}).",
        attacker=replace(template.attacker, start=tuple(p_a)),
        defenders=tuple(Defender(tuple(p), d.max_speed) for p, d in zip(defenders, template.defenders)),
        obstacles=tuple(Obstacle(tuple(c), float(r)) for c, r in obstacles),
    )


def random_entry(
    template: Scenario, case: str, name: str, rng: np.random.Generator, probe: ActivityProbe
) -> tuple[Scenario, ProblemEntry]:
    """One random state of ``case`` (a family name) as scenario ``name``, tagged ``random``, ``case:<case>``."""
    if case not in VIOLATION_NAMES:
        raise MpcHuntError(f"case: unknown family {case!r} (known: {', '.join(VIOLATION_NAMES)})")
    if len(template.defenders) < 3:  # a separation state needs two defenders inside R_agg and one held
        raise MpcHuntError(
            f"scenario {template.name}: random states need at least 3 defenders, it has {len(template.defenders)}"
        )
    for _ in range(MAX_DRAWS):
        p_a, defenders, obstacles = _layout(rng, template, case)
        if not _admissible(template, p_a, defenders, obstacles):
            continue
        if case in ("obstacle_safety", "separation"):
            free = _scenario(template, name, case, p_a, defenders, obstacles)
            problem = CaptureProblem.at_state(free, p_a, defenders, 1)
            plan = probe.optimum(problem)
            if plan is None:
                continue
            _block(rng, template, case, defenders, obstacles, plan[0] - defenders)
            if not _admissible(template, p_a, defenders, obstacles) or not np.array_equal(
                attacker.perceives(template, p_a, defenders), problem.controlled
            ):
                continue
        scenario = _scenario(template, name, case, p_a, defenders, obstacles)
        violation, tags = probe.examine(CaptureProblem.at_state(scenario, p_a, defenders, 1))
        if violation is not None and violation <= ACTIVE_TOLERANCE and f"active:{case}" in tags:
            return scenario, ProblemEntry(
                f"{name}/{case}", name, HuntState(0.0, p_a, defenders), None, ("random", f"case:{case}") + tags
            )
    raise MpcHuntError(f"case {case!r}: no draw in {MAX_DRAWS} made the family active")


def random_entries(
    template: Scenario, per_case: int, rng: np.random.Generator, probe: ActivityProbe | None = None
) -> tuple[dict[str, Scenario], list[ProblemEntry]]:
    """``per_case`` random states for every family, their scenarios named ``random-<i>``."""
    probe = probe or ActivityProbe()
    scenarios: dict[str, Scenario] = {}
    entries: list[ProblemEntry] = []
    for case in VIOLATION_NAMES:
        for _ in range(per_case):
            name = f"random-{len(entries)}"
            scenario, entry = random_entry(template, case, name, rng, probe)
            scenarios[name] = scenario
            entries.append(entry)
    return scenarios, entries

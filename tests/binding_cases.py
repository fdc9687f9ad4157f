"""Capture problems in which one constraint family binds at the optimum.

Each case is a small state (three or four defenders within R_agg of the
attacker, horizon 1–2) built so that the plan the objective alone would choose
violates the family: the constrained optimum must stop on its boundary. Each
case also says how to *relax* it, i.e. the same problem with that family's
bound moved out of reach and the objective unchanged (for the motion limit, a
faster defender: only the tiny smoothness weight and the QP's trust region
change with it), so a test can show that without the family the plan would
violate it.

The numbers were calibrated by solving the relaxed problem with every
formulation: the relaxed plans violate the family by the margins given in each
case's comment, while the held plan (δ = 0) keeps it, so no row is relaxed by
"never worse than now".
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mpc_hunt import (Attacker, CaptureProblem, CaptureWeights, Defender, HuntParameters, Obstacle, Scenario,
                      evaluate)

ATTACKER = np.array([5.0, 11.0])
DEFENDER_SPEED = 0.08   # r_d = v_d T = 8 mm a step
SAFETY_DISTANCE = HuntParameters().safety_distance


def on_circle(radius: float, degrees) -> np.ndarray:
    """Defenders at ``radius`` from the attacker, at the given bearings."""
    a = np.radians(np.asarray(degrees, dtype=float))
    return ATTACKER + radius * np.stack([np.cos(a), np.sin(a)], axis=1)


@dataclass(frozen=True)
class Case:
    """One state in which ``family`` binds; ``relaxed`` moves that family's bound out of reach."""

    family: str
    defenders: np.ndarray
    horizon: int
    obstacles: tuple = ()                 # ((x, y), radius)
    hunt: dict = field(default_factory=dict)
    relaxed_hunt: dict = field(default_factory=dict)
    relaxed_speed: float = DEFENDER_SPEED
    relaxed_weights: CaptureWeights = field(default_factory=CaptureWeights)

    def scenario(self, hunt: dict | None = None, speed: float = DEFENDER_SPEED) -> Scenario:
        starts = [(0.0, 0.0), (20.0, 0.0), (0.0, 20.0), (20.0, 20.0)][:len(self.defenders)]
        return Scenario(
            name=f"binds-{self.family}",
            defenders=tuple(Defender(start=s, max_speed=speed) for s in starts),
            attacker=Attacker(start=(10.0, 10.0), nominal_velocity=(0.2, -0.2), max_speed=0.03,
                              perception_radius=1.0),
            obstacles=tuple(Obstacle(centre=tuple(c), radius=r) for c, r in self.obstacles),
            hunt=HuntParameters(**(self.hunt if hunt is None else hunt)),
        )

    def problem(self) -> CaptureProblem:
        return CaptureProblem.at_state(self.scenario(), ATTACKER, self.defenders, self.horizon)

    def relaxed(self) -> CaptureProblem:
        """The same state with the family's bound out of reach."""
        scenario = self.scenario({**self.hunt, **self.relaxed_hunt}, self.relaxed_speed)
        return CaptureProblem.at_state(scenario, ATTACKER, self.defenders, self.horizon, self.relaxed_weights)


def obstacle_near(defender: np.ndarray, bearing: float, distance: float, gap: float):
    """An obstacle centred ``distance`` from ``defender`` at ``bearing`` (degrees), its safety
    circle ``gap`` metres from the defender."""
    a = np.radians(bearing)
    centre = defender + distance * np.array([np.cos(a), np.sin(a)])
    return (tuple(centre), distance - SAFETY_DISTANCE - gap)


SYMMETRIC = on_circle(0.7, [-90.0, 30.0, 150.0])

CASES = {
    # Eq. 13. Three defenders 0.7 m out, 120° apart, the ring term drawing them in to R_hunt/2:
    # every defender takes a full step. With 10× the speed (r_d = 8 cm) the longest step is 7.6–8 cm.
    "motion_limit": Case("motion_limit", SYMMETRIC, horizon=2, relaxed_speed=10 * DEFENDER_SPEED),
    # Eq. 14. The conformance fixture of tests/conftest.py: the obstacle at (6, 11.8) and the
    # attacker's nominal velocity break the symmetry. With no penalty on the slack the
    # distances spread by 1.1 cm.
    "equal_distance": Case("equal_distance", SYMMETRIC, horizon=1, obstacles=(((6.0, 11.8), 0.3),),
                           relaxed_weights=CaptureWeights(equal_distance=0.0)),
    # Eq. 15. An obstacle behind defender 0 (10° off its outward ray), its safety circle 3 mm
    # away. The obstacle's field pushes the attacker the same way as defender 0 does, so
    # defender 0 backs off towards the obstacle to weaken its own push. With R_safe = 0 every
    # formulation's plan enters the safety circle by 1.0–1.2 cm.
    "obstacle_safety": Case("obstacle_safety", SYMMETRIC, horizon=2,
                            obstacles=(obstacle_near(SYMMETRIC[0], 260.0, 0.3, 0.003),),
                            relaxed_hunt={"safety_distance": 0.0}),
    # Defender–defender separation (the default 0.2 m). Two pairs of defenders 20° apart at
    # 0.58 m (0.2014 m apart); drawn in, the lower pair closes to 0.191–0.194 m by step 2.
    "separation": Case("separation", on_circle(0.58, [80.0, 100.0, 260.0, 280.0]), horizon=2,
                       relaxed_hunt={"min_separation": 0.0}),
    # Defender–attacker distance. Raised above R_hunt/2 so that the ring term presses the
    # defenders against it. Three defenders 0.65 m out, 120° apart: the held plan keeps
    # ≥ 0.6472 m from the drifting attacker; with the bound at 1 mm they come to 0.6400–0.6405 m
    # by step 2.
    "attacker_distance": Case("attacker_distance", on_circle(0.65, [-80.0, 40.0, 160.0]), horizon=2,
                              hunt={"min_attacker_distance": 0.645},
                              relaxed_hunt={"min_attacker_distance": 1e-3}),
}


def slack(problem: CaptureProblem, plan: np.ndarray, family: str) -> float:
    """The smallest margin to ``family``'s bound over the plan, in metres (< 0: violated).

    Zero means the plan stands on the boundary. Only the inequality families have one;
    Eq. 14 (an equality) returns NaN.
    """
    c = problem.controlled
    hunt = problem.scenario.hunt
    previous = np.concatenate([problem.defender_positions[None], plan[:-1]])
    if family == "motion_limit":
        return float(np.min(problem.step_limits[c] - np.linalg.norm(plan - previous, axis=2)[:, c]))
    if family == "obstacle_safety":
        centres, radii = problem.scenario.obstacle_centres, problem.scenario.obstacle_radii
        gaps = np.linalg.norm(plan[:, c, None] - centres[None, None], axis=3) - radii - hunt.safety_distance
        return float(gaps.min())
    if family == "separation":
        d = np.linalg.norm(plan[:, :, None] - plan[:, None, :], axis=3)
        pairs = [(i, j) for i in np.flatnonzero(c) for j in range(len(c)) if j != i]
        return float(min(d[:, i, j].min() for i, j in pairs) - hunt.min_separation)
    if family == "attacker_distance":
        path = evaluate(problem, plan).attacker_path
        return float(np.linalg.norm(plan[:, c] - path[:, None], axis=2).min() - hunt.min_attacker_distance)
    return float("nan")


def octagon_slack(problem: CaptureProblem, plan: np.ndarray, sides: int) -> float:
    """Like ``slack(..., "motion_limit")`` but to the inscribed regular polygon the QP uses."""
    c = problem.controlled
    previous = np.concatenate([problem.defender_positions[None], plan[:-1]])
    steps = (plan - previous)[:, c]
    angles = 2 * np.pi * np.arange(sides) / sides
    normals = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    reach = (steps @ normals.T).max(axis=2)
    return float(np.min(problem.step_limits[c] * np.cos(np.pi / sides) - reach))

"""Voronoi encirclement: a baseline from the pursuit–evasion literature, with no optimisation.

Each step builds the attacker's bounded Voronoi cell (:mod:`mpc_hunt.world.voronoi_cell`: the
arena cut by the bisectors to the defenders and by the obstacles' tangents). A defender that
shares an edge with it aims at a distance from the attacker equal to that of the edge's
midpoint, the area-minimising pursuit rule (Huang et al. 2011; Zhou et al. 2016, "Cooperative
pursuit with Voronoi partitions"): half its distance when the edge is centred on it, farther when
the edge runs long to one side (the cell is open there); a defender with no shared edge aims at
the bisector's foot, half its distance. Its bearing is its place in an even
spread round the attacker, in the order the defenders stand (turned as little as possible); a
stationary member (a failed robot, or an obstacle the success test recruits) holds the first
place, so two robots and an obstacle share the turn in thirds. This is the evader-centred cell
compressed while keeping encirclement of Wang et al. (arXiv 2312.01326, OA-ECBVC) and Patra et
al. (arXiv 2603.15278): until the attacker is strictly inside the members' convex hull, the
distance is floored at R_agg + R_hunt / 2, outside the attacker's perception, so it keeps its
course while the defenders take their places (round the attacker's predicted intercept with
each, Eqs. 7–8, unless prediction is off); once enclosed, the floor is R_hunt / 2, the ring the
success test (Eqs. 4–5) holds on, and the movers' places are shifted so that the members'
centroid is the attacker. A stationary member farther than R_hunt does not count in that
centroid: the movers stand opposite it and push the attacker towards it.

A defender whose straight way to its place would cross the circle it aims at goes round it
(towards the tangent point, or one step along the circle). Places are kept in the arena by
R_safe and out of every obstacle's R_safe (Eq. 15); a velocity that would enter either loses its
inward part. Every command passes the separation filter (:mod:`mpc_hunt.world.separation`).
"""

from __future__ import annotations

import math

import numpy as np

from mpc_hunt.control.controller import Command, Observation, attacker_velocity_estimate
from mpc_hunt.world import attacker
from mpc_hunt.world.approach import approach_target
from mpc_hunt.world.arena import kept_clear, safe_velocity
from mpc_hunt.world.geometry import direction, encloses, norm, saturate
from mpc_hunt.world.hunting_circle import members
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.separation import keep_separation
from mpc_hunt.world.voronoi_cell import Cell, attacker_cell


def _bearing(v: np.ndarray) -> float:
    return math.atan2(float(v[1]), float(v[0]))


def compressed_radius(cell: Cell, p_a: np.ndarray, p_d: np.ndarray, label: int) -> float:
    """The Voronoi pursuit's distance: to the midpoint of the shared edge, else to the bisector's foot."""
    edge = cell.shared_edge(label)
    if edge is None:
        return 0.5 * float(norm(p_d - p_a))
    return float(norm(0.5 * (edge[0] + edge[1]) - p_a))


def ring_bearings(p_a: np.ndarray, movers: np.ndarray, stationary: np.ndarray) -> np.ndarray:
    """Each mover's bearing in an even spread round ``p_a``, in the order they stand.

    With stationary members, the nearest holds bearing 0 of k + 1 places; without, k places are
    turned to the movers' circular mean offset (the least turning that keeps their order).
    """
    k = len(movers)
    bearing = np.array([_bearing(q - p_a) for q in movers])
    out = np.empty(k)
    if len(stationary):
        first = stationary[np.argmin(norm(stationary - p_a))]
        phi = _bearing(first - p_a)
        order = np.argsort((bearing - phi) % (2 * math.pi), kind="stable")
        out[order] = phi + 2 * math.pi * np.arange(1, k + 1) / (k + 1)
        return out
    order = np.argsort(bearing % (2 * math.pi), kind="stable")
    slots = 2 * math.pi * np.arange(k) / k
    offset = math.atan2(float(np.sum(np.sin(bearing[order] - slots))), float(np.sum(np.cos(bearing[order] - slots))))
    out[order] = offset + slots
    return out


def route(p_d: np.ndarray, centre: np.ndarray, angle: float, radius: float, reach: float) -> np.ndarray:
    """The place at ``angle`` on the circle (``centre``, ``radius``), or, if the straight way crosses the
    circle, the tangent point on the near side (at least one step, ``reach``, along it)."""
    offset = p_d - centre
    distance, bearing = float(norm(offset)), _bearing(offset)
    turn = (angle - bearing + math.pi) % (2 * math.pi) - math.pi
    limit = max(math.acos(min(1.0, radius / distance)) if distance > 0 else 0.0, reach / radius)
    if abs(turn) > limit:
        angle = bearing + math.copysign(limit, turn)
    return centre + radius * direction(angle)


class VoronoiController:
    """Voronoi encirclement, no optimisation (CLI ``--controller voronoi``)."""

    SUMMARY = (
        "the Voronoi encirclement of the pursuit-evasion literature (area-minimising pursuit, Zhou et al. "
        "2016), no optimisation"
    )

    def __init__(self, scenario: Scenario, *, prediction: bool = True):
        self.scenario = scenario
        self.prediction = prediction

    def describe(self) -> dict:
        return {"controller": "voronoi", "prediction": self.prediction}

    def aims(self, obs: Observation) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, bool]:
        """(the movers, each one's circle centre (k, 2), bearing (k,) and radius (k,), whether the attacker is
        enclosed): where the module's rule sends each mover, before routing round the circle."""
        s, hunt = self.scenario, self.scenario.hunt
        p_a, P = obs.attacker, obs.defenders
        movers = np.flatnonzero(obs.active)
        stationary = self._stationary(obs)
        enclosed = encloses(p_a, np.vstack([P, stationary]))
        cell = attacker_cell(p_a, P, s.obstacle_centres, s.obstacle_radii, self._box(p_a, P))
        floor = 0.5 * hunt.hunt_radius if enclosed else s.attacker.perception_radius + 0.5 * hunt.hunt_radius
        radii = np.array([max(floor, compressed_radius(cell, p_a, P[i], int(i))) for i in movers])
        angles = ring_bearings(p_a, P[movers], stationary)
        places = p_a + radii[:, None] * direction(angles)
        shift = self._centring(p_a, places, stationary) if enclosed else np.zeros(2)
        v_a = attacker_velocity_estimate(obs, hunt.time_step)
        speeds = s.defender_max_speeds
        centres = np.array(
            [p_a + shift if enclosed else approach_target(p_a, v_a, P[i], speeds[i], self.prediction) for i in movers]
        ).reshape(-1, 2)
        return movers, centres, angles, radii, enclosed

    def command(self, obs: Observation) -> Command:
        s, hunt = self.scenario, self.scenario.hunt
        p_a, P = obs.attacker, obs.defenders
        movers, centres, angles, radii, _ = self.aims(obs)
        speeds = s.defender_max_speeds
        velocities = np.zeros_like(P)
        intercepts = np.full_like(P, np.nan)
        for i, centre, angle, radius in zip(movers, centres, angles, radii):
            target = self.allowed(route(P[i], centre, angle, radius, speeds[i] * hunt.time_step))
            intercepts[i] = target
            velocities[i] = safe_velocity(s, P[i], saturate((target - P[i]) / hunt.time_step, speeds[i]))
        capture = attacker.perceives(s, p_a, P) & obs.active
        velocities = keep_separation(P, velocities, obs.active, P, hunt.time_step, speeds, hunt.min_separation)
        return Command(velocities, capture, intercepts)

    def _stationary(self, obs: Observation) -> np.ndarray:
        """Members that cannot move: failed robots, then the obstacles the success test counts or recruits."""
        s = self.scenario
        m = members(obs.attacker, obs.defenders, s.obstacle_centres, s.obstacle_radii, s.hunt.hunt_radius)
        failed = obs.defenders[~obs.active]
        return np.vstack([failed, m.anchors[len(obs.defenders) :]])

    def _centring(self, p_a: np.ndarray, places: np.ndarray, stationary: np.ndarray) -> np.ndarray:
        """The movers' common shift that puts the centroid of their places and the stationary members
        within R_hunt at the attacker."""
        near = stationary[norm(stationary - p_a) <= self.scenario.hunt.hunt_radius]
        count = len(places) + len(near)
        centroid = (places.sum(axis=0) + near.sum(axis=0)) / count
        return (p_a - centroid) * count / len(places)

    def _box(self, p_a: np.ndarray, P: np.ndarray) -> tuple[float, float, float, float]:
        """The arena, or without one a square round the attacker reaching R_agg beyond every defender."""
        if self.scenario.arena is not None:
            return self.scenario.arena
        half = float(np.max(norm(P - p_a))) + self.scenario.attacker.perception_radius
        return (p_a[0] - half, p_a[1] - half, p_a[0] + half, p_a[1] + half)

    def allowed(self, target: np.ndarray) -> np.ndarray:
        """``target`` moved into the arena, R_safe from its edges, and out of every obstacle's R_safe."""
        return kept_clear(self.scenario, target)

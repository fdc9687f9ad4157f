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
from collections.abc import Sequence

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.control.controller import Command, Observation, estimated_velocity, previous_of
from mpc_hunt.control.scenario_rule import ScenarioRule
from mpc_hunt.world.arena import clear_of, safe_of
from mpc_hunt.world.geometry import capped, encloses, length
from mpc_hunt.world.hunting_circle import member_arrays
from mpc_hunt.world.packed import HAS_ARENA, HUNT_RADIUS, MIN_SEPARATION, R_AGG, X_MAX, X_MIN, Y_MAX, Y_MIN, T
from mpc_hunt.world.prediction import meeting_point
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.separation import separated
from mpc_hunt.world.voronoi_cell import cell_of, shared_edge


@kernel
def ring_bearings(p_a: np.ndarray, movers: np.ndarray, stationary: np.ndarray) -> np.ndarray:
    """Each mover's bearing in an even spread round ``p_a``, in the order they stand.

    With stationary members, the nearest holds bearing 0 of k + 1 places; without, k places are
    turned to the movers' circular mean offset (the least turning that keeps their order).
    """
    k = movers.shape[0]
    bearing = np.empty(k)
    for i in range(k):
        bearing[i] = math.atan2(movers[i, 1] - p_a[1], movers[i, 0] - p_a[0])
    out = np.empty(k)
    if stationary.shape[0]:
        nearest, first = math.inf, 0
        for j in range(stationary.shape[0]):
            d = length(stationary[j, 0] - p_a[0], stationary[j, 1] - p_a[1])
            if d < nearest:
                nearest, first = d, j
        phi = math.atan2(stationary[first, 1] - p_a[1], stationary[first, 0] - p_a[0])
        order = np.argsort((bearing - phi) % (2 * math.pi), kind="mergesort")
        for place in range(k):
            out[order[place]] = phi + 2 * math.pi * (place + 1) / (k + 1)
        return out
    order = np.argsort(bearing % (2 * math.pi), kind="mergesort")
    sin_sum = cos_sum = 0.0
    for place in range(k):
        slot = 2 * math.pi * place / k
        sin_sum += math.sin(bearing[order[place]] - slot)
        cos_sum += math.cos(bearing[order[place]] - slot)
    offset = math.atan2(sin_sum, cos_sum)
    for place in range(k):
        out[order[place]] = offset + 2 * math.pi * place / k
    return out


@kernel
def routed(p_d: np.ndarray, cx: float, cy: float, angle: float, radius: float, reach: float) -> tuple[float, float]:
    """The place at ``angle`` on the circle ((cx, cy), ``radius``), or, if the straight way crosses the
    circle, the tangent point on the near side (at least one step, ``reach``, along it)."""
    ox, oy = p_d[0] - cx, p_d[1] - cy
    distance, bearing = length(ox, oy), math.atan2(oy, ox)
    turn = (angle - bearing + math.pi) % (2 * math.pi) - math.pi
    limit = max(math.acos(min(1.0, radius / distance)) if distance > 0 else 0.0, reach / radius)
    if abs(turn) > limit:
        angle = bearing + math.copysign(limit, turn)
    return cx + radius * math.cos(angle), cy + radius * math.sin(angle)


@kernel
def voronoi_aims(p_a, previous, P, active, centres, radii, speeds, prm, prediction):
    """(the movers, each one's circle centre (k, 2), bearing (k,) and radius (k,), whether the attacker is
    enclosed): where the module's rule sends each mover, before routing round the circle. ``previous`` is the
    attacker's last observed position (NaN before the first step: no velocity estimate, Eq. 7)."""
    movers = np.flatnonzero(active)
    anchors, _, _ = member_arrays(p_a, P, centres, radii, prm[HUNT_RADIUS])
    n = P.shape[0]
    failed = np.flatnonzero(~active)
    stationary = np.empty((failed.shape[0] + anchors.shape[0] - n, 2))
    for r in range(failed.shape[0]):
        stationary[r] = P[failed[r]]
    stationary[failed.shape[0] :] = anchors[n:]
    everybody = np.empty((n + stationary.shape[0], 2))
    everybody[:n] = P
    everybody[n:] = stationary
    enclosed = encloses(p_a, everybody)
    if prm[HAS_ARENA]:
        box = np.array([prm[X_MIN], prm[Y_MIN], prm[X_MAX], prm[Y_MAX]])
    else:  # a square round the attacker reaching R_agg beyond every defender
        half = 0.0
        for i in range(n):
            half = max(half, length(P[i, 0] - p_a[0], P[i, 1] - p_a[1]))
        half += prm[R_AGG]
        box = np.array([p_a[0] - half, p_a[1] - half, p_a[0] + half, p_a[1] + half])
    vertices, labels = cell_of(p_a, P, centres, radii, box)
    floor = 0.5 * prm[HUNT_RADIUS] if enclosed else prm[R_AGG] + 0.5 * prm[HUNT_RADIUS]
    k = movers.shape[0]
    rings = np.empty(k)
    for r in range(k):
        i = movers[r]
        found, a, b = shared_edge(vertices, labels, i)
        if found:  # the Voronoi pursuit's distance: to the midpoint of the shared edge, else to the bisector's foot
            compressed = length(0.5 * (a[0] + b[0]) - p_a[0], 0.5 * (a[1] + b[1]) - p_a[1])
        else:
            compressed = 0.5 * length(P[i, 0] - p_a[0], P[i, 1] - p_a[1])
        rings[r] = max(floor, compressed)
    angles = ring_bearings(p_a, P[movers], stationary)
    sx = sy = 0.0
    if enclosed and k:  # the movers' common shift putting the centroid of their places and the stationary
        count, gx, gy, nx, ny = k, 0.0, 0.0, 0.0, 0.0  # members within R_hunt at the attacker
        for r in range(k):
            gx += p_a[0] + rings[r] * math.cos(angles[r])
            gy += p_a[1] + rings[r] * math.sin(angles[r])
        for j in range(stationary.shape[0]):
            if length(stationary[j, 0] - p_a[0], stationary[j, 1] - p_a[1]) <= prm[HUNT_RADIUS]:
                nx, ny, count = nx + stationary[j, 0], ny + stationary[j, 1], count + 1
        sx, sy = (p_a[0] - (gx + nx) / count) * count / k, (p_a[1] - (gy + ny) / count) * count / k
    v_a = estimated_velocity(p_a, previous, prm[T])
    circles = np.empty((k, 2))
    for r in range(k):
        circles[r, 0], circles[r, 1] = p_a[0] + sx, p_a[1] + sy
        if not enclosed and prediction:
            found, x, y = meeting_point(p_a, v_a, P[movers[r]], speeds[movers[r]])
            if found:
                circles[r, 0], circles[r, 1] = x, y
    return movers, circles, angles, rings, enclosed


@kernel
def voronoi_command(
    p_a, previous, P, active, centres, radii, speeds, prm, prediction, velocities, capture, intercepts
) -> None:
    """The module's rule for one hunt, into ``velocities`` (n, 2), ``capture`` (n,) and ``intercepts`` (n, 2)."""
    movers, circles, angles, rings, _ = voronoi_aims(p_a, previous, P, active, centres, radii, speeds, prm, prediction)
    T_ = prm[T]
    velocities[:] = 0.0
    intercepts[:] = np.nan
    for r in range(movers.shape[0]):
        i = movers[r]
        x, y = routed(P[i], circles[r, 0], circles[r, 1], angles[r], rings[r], speeds[i] * T_)
        x, y = clear_of(x, y, centres, radii, prm)
        intercepts[i, 0], intercepts[i, 1] = x, y
        vx, vy = capped((x - P[i, 0]) / T_, (y - P[i, 1]) / T_, speeds[i])
        velocities[i, 0], velocities[i, 1] = safe_of(P[i], vx, vy, centres, radii, prm)
    for i in range(P.shape[0]):
        capture[i] = active[i] and length(p_a[0] - P[i, 0], p_a[1] - P[i, 1]) < prm[R_AGG]
    separated(P, velocities, active, P, T_, speeds, prm[MIN_SEPARATION])


@kernel
def voronoi_batch(
    running: np.ndarray,
    p_a: np.ndarray,
    previous: np.ndarray,
    p_d: np.ndarray,
    n: np.ndarray,
    failed: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    m: np.ndarray,
    speeds: np.ndarray,
    prm: np.ndarray,
    prediction: np.ndarray,
    velocities: np.ndarray,
    capture: np.ndarray,
    intercepts: np.ndarray,
) -> None:
    """:func:`voronoi_command` for every running hunt of a batch (arrays padded; ``n``, ``m`` their counts)."""
    for b in range(running.shape[0]):
        if running[b]:
            k, j = n[b], m[b]
            voronoi_command(
                p_a[b],
                previous[b],
                p_d[b, :k],
                ~failed[b, :k],
                centres[b, :j],
                radii[b, :j],
                speeds[b, :k],
                prm[b],
                prediction[b],
                velocities[b, :k],
                capture[b, :k],
                intercepts[b, :k],
            )


class VoronoiController:
    """Voronoi encirclement, no optimisation (CLI ``--controller voronoi``); a batch of hunts in one call
    (:meth:`batched`)."""

    SUMMARY = (
        "the Voronoi encirclement of the pursuit-evasion literature (area-minimising pursuit, Zhou et al. "
        "2016), no optimisation"
    )

    def __init__(self, scenario: Scenario, *, prediction: bool = True):
        self.scenario = scenario
        self.prediction = prediction

    def describe(self) -> dict:
        return {"controller": "voronoi", "prediction": self.prediction}

    def _inputs(self, obs: Observation) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                                 np.ndarray, np.ndarray, np.ndarray, bool]:  # fmt: skip
        """The rule's inputs for one hunt: the observation, then what the controller knows of the scenario."""
        s = self.scenario
        previous = previous_of(obs)
        attacker, defenders = np.asarray(obs.attacker, float), np.asarray(obs.defenders, float)
        return (attacker, previous, defenders, obs.active, s.obstacle_centres, s.obstacle_radii,
                s.defender_max_speeds, s.packed, self.prediction)  # fmt: skip

    def aims(self, obs: Observation) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, bool]:
        """(the movers, each one's circle centre (k, 2), bearing (k,) and radius (k,), whether the attacker is
        enclosed): where the module's rule sends each mover, before routing round the circle."""
        return voronoi_aims(*self._inputs(obs))

    def command(self, obs: Observation) -> Command:
        P = np.asarray(obs.defenders, float)
        velocities, capture, intercepts = np.zeros_like(P), np.zeros(len(P), dtype=bool), np.empty_like(P)
        voronoi_command(*self._inputs(obs), velocities, capture, intercepts)
        return Command(velocities, capture, intercepts)

    @staticmethod
    def batched(controllers: Sequence[VoronoiController | None]) -> ScenarioRule:
        """The rule of ``controllers`` (None: a hunt commanded otherwise) for a batch, hunt b by its own."""
        return ScenarioRule(controllers, voronoi_batch)

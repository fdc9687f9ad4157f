"""Where the defenders should be to trap an attacker whose law they do not know: the ``trap`` controller's reference.

The defenders know the attacker's top speed v_a, not its law. What they can
shrink without a model is the set of places it can reach before any of them,
its dominance region (:mod:`mpc_hunt.world.reachable_set`: Apollonius circles
for a slower evader, cut by the obstacles, which close directions as
stationary members do, Eqs. 4–5, and open where the region reaches the
arena's edge). The reference has two phases:

- **shrink** (the attacker not yet inside the members' convex hull, or some
  direction still open to the edge): every mover runs at its top speed down
  the gradient of

      J = ½ Σ_rays min(s, b, e)² Δθ  +  W_EDGE Σ_open rays max(0, s − (e − EDGE_MARGIN)) Δθ,

  the region's area plus a penalty on every ray along which it comes within
  ``EDGE_MARGIN`` of the arena's edge before any obstacle (s: the defenders'
  limit along the ray, a soft minimum (Σ s_i^−p)^(−1/p) over them, so every mover has a share;
  b: the nearest obstacle; e: the edge), whose gradient reaches the farthest mover too. This is the area-minimising
  pursuit of
  a reachable set (Huang et al. 2011; Pierson et al., RA-L 2017) with the
  edge's openings closed first: the defender that owns an open arc cuts it, the
  others close the rest, and a team too small to enclose alone leans on the
  obstacles that close the other directions (the paper's obstacles as members).
  The places over the horizon are the straight run at top speed: a
  minimum-time closing, not a tracking of places. Near a slower attacker
  every ray's limit is nearly zero, and the area with it, so the gradient no
  longer spreads the team: a mover within ``NEAR`` R_hunt of the attacker
  instead takes its place in an even spread round it on that circle (no wider
  than the attacker's distance to the arena's edge less R_safe, so that near
  the edge a place stands between the attacker and the way out instead of
  being pushed onto the edge), in the order the movers stand, until the ring
  can close;
- **herd** (fewer robots than the three that enclose, Eqs. 4–5, so an obstacle
  must close the circle, and the attacker farther than R_hunt + ``HOLD_BAND`` from
  the nearest obstacle's surface, or twice the band once closing): the movers take
  places behind the attacker as seen from that obstacle, ``HERD_SPREAD`` either
  side, and close in at top speed (going round, no nearer than ``HERD_ORBIT``,
  until they stand on their side), so that an attacker which keeps away from
  defenders is pushed against the obstacle; an attacker that does not react is
  closed on there all the same. The push is turned past the attacker's observed
  drift (by the angle between its velocity and the way to the obstacle, at most
  ``HERD_STEER``), as a shepherd drives a flock from behind its heading rather
  than its position, except within the obstacle's protective distance, where the
  drift is the obstacle's field sliding it along the surface; a mover farther
  than twice ``HERD_ORBIT`` runs for where it meets the attacker (its intercept
  with the observed velocity), not for where the attacker stands;
- **close** (the attacker strictly inside the hull of the movers and the
  stationary members, and its region reaching the edge along no ray: no
  point of the edge is the attacker's before a defender's; the margin
  ``EDGE_MARGIN`` shapes the shrink only, for an attacker within it of the
  edge could never be closed on): places on an even
  spread round the attacker (:func:`~mpc_hunt.control.voronoi.ring_bearings`,
  a stationary member first), their common centre shifted so that the
  members' centroid is the attacker (Eq. 4), one radius for all, shrinking
  from the nearest mover's distance at the slowest mover's top speed to
  R_hunt / 2 (the others run to the ring at theirs), every place moving with
  the attacker's observed velocity. The centring is taken only as far as half
  the success test's centre tolerance: a stationary member (an obstacle, counted
  from R_hunt + ``HOLD_BAND``) pulls the members' centroid its way, and a full
  shift would take the movers back from the attacker, so that they no longer
  press it towards that member. With fewer than three robots, the close phase
  starts once the attacker is within R_hunt + ``HOLD_BAND`` of the obstacle's
  surface, which holds the first place. While a stationary member stands
  farther than ``PRESS_FROM`` R_hunt from the attacker, the ring's floor is
  the capture problem's least attacker distance plus ``PRESS_CLEARANCE``, not
  R_hunt / 2: an attacker that its own field keeps off the obstacle settles
  where the movers' push balances that field, and on the development hunts
  that balance was 0.52–0.53 m from the surface, just beyond R_hunt, for the
  last 40–50 s of the hunt; only a nearer ring moves it inside. The margin
  below R_hunt keeps the press on until the member is well inside, so that it
  does not flicker at the success test's edge.

Places stay in the arena and out of every obstacle's R_safe; the capture
problem (:class:`~mpc_hunt.capture.problem.CaptureProblem`, the ``enclose``
objective with no term on a predicted attacker) plans every active defender
over the horizon under the constraints (steps within r_d, Eq. 13; R_safe,
Eq. 15; separation; the arena).
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.capture.problem import Reference
from mpc_hunt.control.containment import Unmodelled
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.enclosure import TERMINAL_WEIGHT
from mpc_hunt.control.voronoi import ring_bearings, route
from mpc_hunt.world.arena import kept_clear
from mpc_hunt.world.geometry import direction, encloses, norm
from mpc_hunt.world.hunting_circle import MIN_MEMBERS, members
from mpc_hunt.world.prediction import intercept_time
from mpc_hunt.world.reachable_set import defender_reach, edge_distance, obstacle_block, ray_directions
from mpc_hunt.world.scenario import Scenario

W_EDGE = 20.0  # m: an open ray's penalty per metre beyond the edge less the margin (a ray this long's weight)
EDGE_MARGIN = 1.0  # m: how far inside the edge the shrink's penalty keeps the region's boundary
SHARPNESS = 4.0  # p of the soft minimum (Σ s_i^−p)^(−1/p) over the defenders' limits: positive, at most the least
TINY = 1e-9  # m: a limit's floor in that minimum (a defender already within reach)
STEP = 1e-4  # m: the finite difference of the gradient
NEAR = 5.0  # of R_hunt: a mover this near the attacker before the ring can close takes its place in a spread
# (at 3, three movers came within a gap-seeker's sensing from one side and drove it out)
HERD_SPREAD = np.radians(50.0)  # rad: either side of the attacker's far side from the anchor, where a mover herds
HERD_TOLERANCE = np.radians(30.0)  # rad: a mover this close to its herding bearing closes in; farther, goes round
HOLD_BAND = 0.25  # m: the ring closes on an obstacle from this far beyond R_hunt of it, herds again from twice it
CENTRE_SLACK = 0.5  # of the centre tolerance: the ring's members' centroid is moved no nearer the attacker than this
HERD_DRIFT = 0.3  # of v_a: an attacker moving slower than this has no drift the herd corrects
HERD_ORBIT = 1.0  # m: how close a mover going round comes while it does (it closes in at top speed down to this)
HERD_STEER = np.radians(60.0)  # rad: the herd's push turned at most this far past the way to the anchor
PRESS_FROM = 0.8  # of R_hunt: a stationary member farther than this from the attacker makes the ring press
PRESS_CLEARANCE = 0.05  # m: how far beyond the capture problem's least attacker distance the ring presses


def run_towards(q: np.ndarray, target: np.ndarray, reach: float) -> np.ndarray:
    """``q`` moved straight towards ``target`` by at most ``reach``."""
    way = target - q
    length = float(np.hypot(*way))
    return q + way * (min(1.0, reach / length) if length > 0 else 0.0)


def wrap(angle):
    """``angle`` in [−π, π)."""
    return (np.asarray(angle) + np.pi) % (2 * np.pi) - np.pi


class Trap(Unmodelled):
    """Builds each step's :class:`~mpc_hunt.capture.problem.Reference` for the ``trap`` controller."""

    NAME = "trap"
    SUMMARY = (
        "the capture problem tracking a minimum-time shrink of the attacker's reachable set (no model of the attacker)"
    )

    def __init__(self, scenario: Scenario, horizon: int):
        super().__init__(scenario, horizon)
        self.rays = ray_directions()
        self.phase = "shrink"

    def cost(
        self, p_a: np.ndarray, movers: np.ndarray, speeds: np.ndarray, blocked: np.ndarray, edge: np.ndarray
    ) -> float:
        """J of the module's docstring for the movers at ``movers`` (k, 2)."""
        s = self.scenario
        limits = defender_reach(p_a, self.rays, movers, s.attacker.max_speed / speeds, 0.5 * s.hunt.hunt_radius)
        soft = np.sum(np.maximum(limits, TINY) ** -SHARPNESS, axis=1) ** (-1.0 / SHARPNESS)
        area = 0.5 * np.sum(np.minimum(soft, np.minimum(blocked, edge)) ** 2)
        open_ = blocked > edge
        penalty = W_EDGE * np.sum(np.where(open_, np.maximum(0.0, soft - (edge - EDGE_MARGIN)), 0.0))
        return float((area + penalty) * 2 * np.pi / len(self.rays))

    def bounds(self, p_a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(the nearest obstacle's surface, the arena's edge) along each ray from ``p_a``."""
        s = self.scenario
        return obstacle_block(p_a, self.rays, s.obstacle_centres, s.obstacle_radii), edge_distance(
            p_a, self.rays, s.arena
        )

    def headings(self, p_a: np.ndarray, movers: np.ndarray, speeds: np.ndarray) -> np.ndarray:
        """Each mover's unit direction down the gradient of J (towards the attacker where J is flat for it)."""
        blocked, edge = self.bounds(p_a)
        base = self.cost(p_a, movers, speeds, blocked, edge)
        out = np.empty_like(movers)
        for i in range(len(movers)):
            gradient = np.empty(2)
            for axis in range(2):
                moved = movers.copy()
                moved[i, axis] += STEP
                gradient[axis] = (self.cost(p_a, moved, speeds, blocked, edge) - base) / STEP
            size = float(np.hypot(*gradient))
            towards = p_a - movers[i]
            out[i] = -gradient / size if size > 0 else towards / max(float(np.hypot(*towards)), 1e-12)
        return out

    def closed(self, p_a: np.ndarray, movers: np.ndarray, speeds: np.ndarray, stationary: np.ndarray) -> bool:
        """Is the attacker inside the members' hull, its region reaching the arena's edge along no ray?"""
        s = self.scenario
        if not encloses(p_a, np.vstack([movers, stationary])):
            return False
        limits = defender_reach(p_a, self.rays, movers, s.attacker.max_speed / speeds, 0.5 * s.hunt.hunt_radius)
        blocked, edge = self.bounds(p_a)
        return not np.any((limits.min(axis=1) >= edge) & (blocked > edge))

    def reference(self, obs: Observation) -> Reference:
        """Places for every defender (held ones: where they stand) and the attacker, steps 1..N."""
        s, N = self.scenario, self.horizon
        T = s.hunt.time_step
        p_a, P = obs.attacker, obs.defenders
        velocity = self.observed.update(obs)
        drift = velocity * T * np.arange(1, N + 1)[:, None]
        movers = np.flatnonzero(obs.active)
        speeds = s.defender_max_speeds[movers]
        m = members(p_a, P, s.obstacle_centres, s.obstacle_radii, s.hunt.hunt_radius)
        stationary = np.vstack([P[~obs.active], m.anchors[len(P) :]])
        places = np.repeat(P[None], N, axis=0).astype(float)
        steps = (np.arange(1, N + 1) * T)[:, None]
        anchor = m.anchors[len(P)] if len(P) < MIN_MEMBERS and len(m.anchors) > len(P) else None
        hold = (2.0 if self.phase == "close" else 1.0) * HOLD_BAND
        if len(movers) and anchor is not None and norm(anchor - p_a) > s.hunt.hunt_radius + hold:
            self.phase = "herd"
            places[:, movers] = self._herd(p_a, velocity, P[movers], speeds, anchor, steps)
        elif len(movers) and (anchor is not None or self.closed(p_a, P[movers], speeds, stationary)):
            self.phase = "close"
            places[:, movers] = self._ring(p_a, P[movers], speeds, stationary, steps) + drift[:, None]
        elif len(movers):
            self.phase = "shrink"
            ways = self.headings(p_a, P[movers], speeds)
            places[:, movers] = P[movers][None] + (speeds[None, :, None] * steps[:, :, None]) * ways[None]
            near = norm(P[movers] - p_a) < NEAR * s.hunt.hunt_radius
            if near.any():
                places[:, movers[near]] = self._spread(p_a, P[movers], speeds, stationary, steps, drift)[:, near]
        places[:, movers] = kept_clear(s, places[:, movers])
        weight = np.ones(N)
        weight[-1] = TERMINAL_WEIGHT
        return Reference(places, p_a + drift, weight)

    def _spread(
        self,
        p_a: np.ndarray,
        movers: np.ndarray,
        speeds: np.ndarray,
        stationary: np.ndarray,
        steps: np.ndarray,
        drift: np.ndarray,
    ) -> np.ndarray:
        """The places (N, k, 2) of movers that have come within ``NEAR`` R_hunt while the ring cannot close yet: on
        that circle round the attacker, at their places in an even spread in the order they stand (a stationary
        member first), going round the circle where the straight way would cross it, at top speed."""
        s = self.scenario
        radius = NEAR * s.hunt.hunt_radius
        if s.arena is not None:  # the spread inside the arena, R_safe from its edge: no place clamped onto it
            gap = min(p_a[0] - s.arena[0], p_a[1] - s.arena[1], s.arena[2] - p_a[0], s.arena[3] - p_a[1])
            radius = min(radius, max(0.5 * s.hunt.hunt_radius, gap - s.hunt.safety_distance))
        angles = ring_bearings(p_a, movers, stationary)
        reach = speeds[None] * steps  # (N, k)
        places = np.empty((len(steps), len(movers), 2))
        for k, centre in enumerate(p_a + drift):
            for i, (q, angle) in enumerate(zip(movers, angles)):
                places[k, i] = run_towards(q, route(q, centre, angle, radius, reach[k, i]), reach[k, i])
        return places

    def _herd(
        self,
        p_a: np.ndarray,
        velocity: np.ndarray,
        movers: np.ndarray,
        speeds: np.ndarray,
        anchor: np.ndarray,
        steps: np.ndarray,
    ) -> np.ndarray:
        """The herd phase's places (N, k, 2): behind the attacker as seen from ``anchor``, ``HERD_SPREAD`` either
        side, on the circle R_hunt / 2 round where each mover meets it (its intercept with the attacker's observed
        velocity, Eqs. 7–8 with no model, or where it stands once met), at top speed; a mover not yet on its side
        goes round at ``HERD_ORBIT``."""
        s = self.scenario
        inner = 0.5 * s.hunt.hunt_radius
        towards = np.arctan2(*(anchor - p_a)[::-1])
        error = 0.0
        if norm(velocity) > HERD_DRIFT * s.attacker.max_speed and norm(anchor - p_a) > s.hunt.protective_distance:
            error = float(np.clip(wrap(towards - np.arctan2(velocity[1], velocity[0])), -HERD_STEER, HERD_STEER))
        # (within the obstacle's protective distance its field, not the attacker, bends the drift: none corrected)
        away = towards + np.pi + error  # pushed along the way to the anchor turned past the attacker's drift
        bearings = np.arctan2(movers[:, 1] - p_a[1], movers[:, 0] - p_a[0])
        side = np.where(wrap(bearings - away) >= 0, 1.0, -1.0)
        if len(movers) == 2 and side[0] == side[1]:
            side[np.argmin(wrap(bearings - away) * side[0])] *= -1.0  # one each side
        goals = away + side * HERD_SPREAD if len(movers) > 1 else np.array([away])
        going = np.abs(wrap(goals - bearings)) > HERD_TOLERANCE
        places = np.empty((len(steps), len(movers), 2))
        for i, (q, speed) in enumerate(zip(movers, speeds)):
            far = norm(q - p_a) > 2.0 * HERD_ORBIT
            meet = (intercept_time(p_a, velocity, q, speed) or 0.0) if far else 0.0
            radius = HERD_ORBIT if going[i] else inner
            for k, t in enumerate(steps[:, 0]):
                places[k, i] = run_towards(
                    q, route(q, p_a + velocity * max(meet, t), goals[i], radius, speed * t), speed * t
                )
        return places

    def _ring(
        self, p_a: np.ndarray, movers: np.ndarray, speeds: np.ndarray, stationary: np.ndarray, steps: np.ndarray
    ) -> np.ndarray:
        """The close phase's places (N, k, 2) round the attacker where it stands (the module's docstring)."""
        s = self.scenario
        inner = 0.5 * s.hunt.hunt_radius
        if np.any(norm(stationary - p_a) > PRESS_FROM * s.hunt.hunt_radius):
            inner = s.hunt.min_attacker_distance + PRESS_CLEARANCE
        angles = ring_bearings(p_a, movers, stationary)
        start = float(np.min(norm(movers - p_a)))
        radii = np.maximum(inner, start - float(np.min(speeds)) * steps)  # (N, 1)
        places = p_a + radii[:, :, None] * direction(angles)[None]
        near = stationary[norm(stationary - p_a) <= s.hunt.hunt_radius + HOLD_BAND]
        count = len(movers) + len(near)
        off = p_a - (places.sum(axis=1) + near.sum(axis=0)) / count  # (N, 2)
        size = np.maximum(norm(off), 1e-12)[:, None]
        slack = CENTRE_SLACK * s.hunt.centre_tolerance
        return places + (off * np.maximum(0.0, 1.0 - slack / size) * count / len(movers))[:, None, :]

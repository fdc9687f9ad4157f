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

The reference is one compiled rule (:func:`trap_places`, :mod:`mpc_hunt.compiled`), its phase a code the
controller keeps between steps. Places stay in the arena and out of every obstacle's R_safe; the capture
problem (:class:`~mpc_hunt.capture.problem.CaptureProblem`, the ``enclose``
objective with no term on a predicted attacker) plans every active defender
over the horizon under the constraints (steps within r_d, Eq. 13; R_safe,
Eq. 15; separation; the arena).
"""

from __future__ import annotations

import math

import numpy as np

from mpc_hunt.capture.problem import Reference
from mpc_hunt.compiled import kernel
from mpc_hunt.control.containment import Unmodelled
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.enclosure import TERMINAL_WEIGHT, wrap
from mpc_hunt.control.voronoi import ring_bearings, routed
from mpc_hunt.world.arena import clear_of
from mpc_hunt.world.geometry import encloses, length, run_towards
from mpc_hunt.world.hunting_circle import MIN_MEMBERS, member_arrays
from mpc_hunt.world.packed import (
    CENTRE_TOLERANCE,
    HAS_ARENA,
    HUNT_RADIUS,
    LEAST_DISTANCE,
    PROTECTIVE,
    SAFETY,
    V_A,
    X_MAX,
    X_MIN,
    Y_MAX,
    Y_MIN,
    T,
)
from mpc_hunt.world.prediction import meeting
from mpc_hunt.world.reachable_set import defender_reach, edge_along, obstacle_block, ray_directions
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
PHASES = ("shrink", "herd", "close")  # the phases by their codes in the compiled reference
SHRINK, HERD, CLOSE = range(3)


@kernel
def trap_cost(p_a, rays, movers, ratios, reach, blocked, edge):
    """J of the module's docstring for the movers at ``movers`` (k, 2), κ_i = ``ratios``, within ``reach``."""
    limits = defender_reach(p_a, rays, movers, ratios, reach)
    area = penalty = 0.0
    for r in range(rays.shape[0]):
        total = 0.0
        for i in range(movers.shape[0]):
            total += max(limits[r, i], TINY) ** -SHARPNESS
        soft = total ** (-1.0 / SHARPNESS)
        bound = min(soft, min(blocked[r], edge[r]))
        area += bound * bound
        if blocked[r] > edge[r]:
            penalty += max(0.0, soft - (edge[r] - EDGE_MARGIN))
    return (0.5 * area + W_EDGE * penalty) * 2 * math.pi / rays.shape[0]


@kernel
def trap_headings(p_a, rays, movers, ratios, reach, blocked, edge):
    """Each mover's unit direction down the gradient of J (towards the attacker where J is flat for it)."""
    base = trap_cost(p_a, rays, movers, ratios, reach, blocked, edge)
    moved = movers.copy()
    out = np.empty_like(movers)
    for i in range(movers.shape[0]):
        gradient = np.empty(2)
        for axis in range(2):
            moved[i, axis] = movers[i, axis] + STEP
            gradient[axis] = (trap_cost(p_a, rays, moved, ratios, reach, blocked, edge) - base) / STEP
            moved[i, axis] = movers[i, axis]
        size = math.hypot(gradient[0], gradient[1])
        if size > 0:
            out[i, 0], out[i, 1] = -gradient[0] / size, -gradient[1] / size
        else:
            tx, ty = p_a[0] - movers[i, 0], p_a[1] - movers[i, 1]
            way = max(math.hypot(tx, ty), 1e-12)
            out[i, 0], out[i, 1] = tx / way, ty / way
    return out


@kernel
def trap_closed(p_a, rays, movers, stationary, ratios, reach, blocked, edge) -> bool:
    """Is the attacker inside the members' hull, its region reaching the arena's edge along no ray?"""
    if not encloses(p_a, np.vstack((movers, stationary))):
        return False
    limits = defender_reach(p_a, rays, movers, ratios, reach)
    for r in range(rays.shape[0]):
        if blocked[r] > edge[r] and limits[r].min() >= edge[r]:
            return False
    return True


@kernel
def trap_spread(p_a, movers, speeds, stationary, drift, prm):
    """The places (N, k, 2) of movers that have come within ``NEAR`` R_hunt while the ring cannot close yet: on
    that circle round the attacker (moved by ``drift``, (N, 2)), at their places in an even spread in the order
    they stand (a stationary member first), going round the circle where the straight way would cross it, at top
    speed."""
    radius = NEAR * prm[HUNT_RADIUS]
    if prm[HAS_ARENA]:  # the spread inside the arena, R_safe from its edges: no place clamped onto one
        gap = min(p_a[0] - prm[X_MIN], p_a[1] - prm[Y_MIN], prm[X_MAX] - p_a[0], prm[Y_MAX] - p_a[1])
        radius = min(radius, max(0.5 * prm[HUNT_RADIUS], gap - prm[SAFETY]))
    angles = ring_bearings(p_a, movers, stationary)
    places = np.empty((drift.shape[0], movers.shape[0], 2))
    for t in range(drift.shape[0]):
        cx, cy = p_a[0] + drift[t, 0], p_a[1] + drift[t, 1]
        for i in range(movers.shape[0]):
            reach = speeds[i] * ((t + 1) * prm[T])
            gx, gy = routed(movers[i], cx, cy, angles[i], radius, reach)
            places[t, i, 0], places[t, i, 1] = run_towards(movers[i, 0], movers[i, 1], gx, gy, reach)
    return places


@kernel
def trap_herd(p_a, velocity, movers, speeds, anchor, horizon, prm):
    """The herd phase's places (N, k, 2): behind the attacker as seen from ``anchor``, ``HERD_SPREAD`` either
    side, on the circle R_hunt / 2 round where each mover meets it (its intercept with the attacker's observed
    velocity, Eqs. 7–8 with no model, or where it stands once met), at top speed; a mover not yet on its side
    goes round at ``HERD_ORBIT``."""
    k = movers.shape[0]
    inner = 0.5 * prm[HUNT_RADIUS]
    towards = math.atan2(anchor[1] - p_a[1], anchor[0] - p_a[0])
    error = 0.0
    far_anchor = length(anchor[0] - p_a[0], anchor[1] - p_a[1]) > prm[PROTECTIVE]
    if length(velocity[0], velocity[1]) > HERD_DRIFT * prm[V_A] and far_anchor:
        error = min(max(wrap(towards - math.atan2(velocity[1], velocity[0])), -HERD_STEER), HERD_STEER)
    # (within the obstacle's protective distance its field, not the attacker, bends the drift: none corrected)
    away = towards + math.pi + error  # pushed along the way to the anchor turned past the attacker's drift
    bearings, side = np.empty(k), np.empty(k)
    for i in range(k):
        bearings[i] = math.atan2(movers[i, 1] - p_a[1], movers[i, 0] - p_a[0])
        side[i] = 1.0 if wrap(bearings[i] - away) >= 0 else -1.0
    if k == 2 and side[0] == side[1]:  # one each side
        flip = 0 if wrap(bearings[0] - away) * side[0] <= wrap(bearings[1] - away) * side[0] else 1
        side[flip] = -side[flip]
    places = np.empty((horizon, k, 2))
    for i in range(k):
        goal = away + side[i] * HERD_SPREAD if k > 1 else away
        radius = HERD_ORBIT if abs(wrap(goal - bearings[i])) > HERD_TOLERANCE else inner
        meet = 0.0
        if length(movers[i, 0] - p_a[0], movers[i, 1] - p_a[1]) > 2.0 * HERD_ORBIT:
            found, when = meeting(p_a, velocity, movers[i], speeds[i])
            meet = when if found else 0.0
        for t in range(horizon):
            step = (t + 1) * prm[T]
            ahead = max(meet, step)
            reach = speeds[i] * step
            gx, gy = routed(movers[i], p_a[0] + velocity[0] * ahead, p_a[1] + velocity[1] * ahead, goal, radius, reach)
            places[t, i, 0], places[t, i, 1] = run_towards(movers[i, 0], movers[i, 1], gx, gy, reach)
    return places


@kernel
def trap_ring(p_a, movers, speeds, stationary, drift, prm):
    """The close phase's places (N, k, 2) round the attacker where it stands (the module's docstring), moved by
    ``drift`` (N, 2)."""
    k, hunt_radius = movers.shape[0], prm[HUNT_RADIUS]
    inner = 0.5 * hunt_radius
    near_x = near_y = 0.0
    count = k
    for j in range(stationary.shape[0]):
        distance = length(stationary[j, 0] - p_a[0], stationary[j, 1] - p_a[1])
        if distance > PRESS_FROM * hunt_radius:
            inner = prm[LEAST_DISTANCE] + PRESS_CLEARANCE
    for j in range(stationary.shape[0]):
        if length(stationary[j, 0] - p_a[0], stationary[j, 1] - p_a[1]) <= hunt_radius + HOLD_BAND:
            near_x, near_y, count = near_x + stationary[j, 0], near_y + stationary[j, 1], count + 1
    angles = ring_bearings(p_a, movers, stationary)
    start, slowest = math.inf, math.inf
    for i in range(k):
        start = min(start, length(movers[i, 0] - p_a[0], movers[i, 1] - p_a[1]))
        slowest = min(slowest, speeds[i])
    slack = CENTRE_SLACK * prm[CENTRE_TOLERANCE]
    places = np.empty((drift.shape[0], k, 2))
    for t in range(drift.shape[0]):
        radius = max(inner, start - slowest * ((t + 1) * prm[T]))
        sum_x = sum_y = 0.0
        for i in range(k):
            places[t, i, 0] = p_a[0] + radius * math.cos(angles[i])
            places[t, i, 1] = p_a[1] + radius * math.sin(angles[i])
            sum_x, sum_y = sum_x + places[t, i, 0], sum_y + places[t, i, 1]
        off_x, off_y = p_a[0] - (sum_x + near_x) / count, p_a[1] - (sum_y + near_y) / count
        size = max(length(off_x, off_y), 1e-12)
        shift = max(0.0, 1.0 - slack / size)
        for i in range(k):
            places[t, i, 0] = (places[t, i, 0] + off_x * shift * count / k) + drift[t, 0]
            places[t, i, 1] = (places[t, i, 1] + off_y * shift * count / k) + drift[t, 1]
    return places


@kernel
def shrink_terms(p_a, rays, centres, radii, prm, speeds):
    """(κ_i = v_a / v_i of the movers of top speeds ``speeds``, the reach R_hunt / 2, the nearest obstacle's surface
    and the arena's edge along each ray): what J and its gradient read besides the movers' places."""
    blocked = obstacle_block(p_a, rays, centres, radii)
    edge = edge_along(p_a, rays, prm[X_MIN], prm[Y_MIN], prm[X_MAX], prm[Y_MAX])
    return prm[V_A] / speeds, 0.5 * prm[HUNT_RADIUS], blocked, edge


@kernel
def trap_places(p_a, velocity, P, active, phase, horizon, centres, radii, prm, speeds, rays):
    """(the places (N, n, 2) of every defender, held ones where they stand, the phase's code after this step): the
    module's reference for the attacker at ``p_a`` seen moving at ``velocity``, ``phase`` the last step's code
    (:data:`PHASES`), over ``horizon`` steps; ``speeds`` are every defender's top speed, ``rays`` the directions of
    the attacker's dominance region."""
    n, hunt_radius = P.shape[0], prm[HUNT_RADIUS]
    movers = np.flatnonzero(active)
    k = movers.shape[0]
    mover_at, mover_speeds = P[movers], speeds[movers]
    drift = np.empty((horizon, 2))
    for t in range(horizon):
        drift[t, 0], drift[t, 1] = velocity[0] * prm[T] * (t + 1), velocity[1] * prm[T] * (t + 1)
    anchors, _, _ = member_arrays(p_a, P, centres, radii, hunt_radius)
    stationary = np.vstack((P[~active], anchors[n:]))
    places = np.empty((horizon, n, 2))
    for t in range(horizon):
        places[t] = P
    has_anchor = n < MIN_MEMBERS and anchors.shape[0] > n
    anchor = anchors[n] if has_anchor else p_a
    hold = (2.0 if phase == CLOSE else 1.0) * HOLD_BAND
    ratios, reach, blocked, edge = shrink_terms(p_a, rays, centres, radii, prm, mover_speeds)
    if k and has_anchor and length(anchor[0] - p_a[0], anchor[1] - p_a[1]) > hunt_radius + hold:
        phase = HERD
        placed = trap_herd(p_a, velocity, mover_at, mover_speeds, anchor, horizon, prm)
    elif k and (has_anchor or trap_closed(p_a, rays, mover_at, stationary, ratios, reach, blocked, edge)):
        phase = CLOSE
        placed = trap_ring(p_a, mover_at, mover_speeds, stationary, drift, prm)
    elif k:
        phase = SHRINK
        ways = trap_headings(p_a, rays, mover_at, ratios, reach, blocked, edge)
        placed = np.empty((horizon, k, 2))
        for t in range(horizon):
            for i in range(k):
                run = mover_speeds[i] * ((t + 1) * prm[T])
                placed[t, i, 0], placed[t, i, 1] = mover_at[i, 0] + run * ways[i, 0], mover_at[i, 1] + run * ways[i, 1]
        spread = np.empty((0, 0, 2))
        for i in range(k):
            if length(mover_at[i, 0] - p_a[0], mover_at[i, 1] - p_a[1]) < NEAR * hunt_radius:
                if spread.shape[0] == 0:
                    spread = trap_spread(p_a, mover_at, mover_speeds, stationary, drift, prm)
                placed[:, i] = spread[:, i]
    else:
        placed = np.empty((horizon, 0, 2))
    for t in range(horizon):
        for i in range(k):
            places[t, movers[i], 0], places[t, movers[i], 1] = clear_of(
                placed[t, i, 0], placed[t, i, 1], centres, radii, prm
            )
    return places, phase


class Trap(Unmodelled):
    """Builds each step's :class:`~mpc_hunt.capture.problem.Reference` for the ``trap`` controller
    (:func:`trap_places`)."""

    NAME = "trap"
    SUMMARY = (
        "the capture problem tracking a minimum-time shrink of the attacker's reachable set (no model of the attacker)"
    )

    def __init__(self, scenario: Scenario, horizon: int):
        super().__init__(scenario, horizon)
        self.rays = ray_directions()
        self.phase = PHASES[SHRINK]

    def headings(self, p_a: np.ndarray, movers: np.ndarray, speeds: np.ndarray) -> np.ndarray:
        """Each mover's unit direction down the gradient of J (:func:`trap_headings`)."""
        s, p_a = self.scenario, np.asarray(p_a, dtype=float)
        terms = shrink_terms(p_a, self.rays, s.obstacle_centres, s.obstacle_radii, s.packed,
                             np.asarray(speeds, dtype=float))  # fmt: skip
        return trap_headings(p_a, self.rays, np.asarray(movers, dtype=float), *terms)

    def reference(self, obs: Observation) -> Reference:
        """Places for every defender (held ones: where they stand) and the attacker, steps 1..N."""
        s, N = self.scenario, self.horizon
        p_a = np.asarray(obs.attacker, dtype=float)
        velocity = self.observed.update(obs)
        places, code = trap_places(
            p_a, velocity, np.asarray(obs.defenders, dtype=float), np.asarray(obs.active, dtype=bool),
            PHASES.index(self.phase), N, s.obstacle_centres, s.obstacle_radii, s.packed, s.defender_max_speeds,
            self.rays,
        )  # fmt: skip
        self.phase = PHASES[code]
        weight = np.ones(N)
        weight[-1] = TERMINAL_WEIGHT
        return Reference(places, p_a + velocity * s.hunt.time_step * np.arange(1, N + 1)[:, None], weight)

"""Where the defenders should be: the reference that the ``enclose`` capture objective tracks.

The paper's capture objective parks the defenders on the attacker's perception
radius R_agg and escorts it out (docs/formulations.md, "Why the paper's
objective does not capture"). This builds, at every step, a place on a hunting
circle for every active defender over the horizon, and the attacker's intended
position, in three phases (docs/formulations.md, "The enclose objective"):

- **gather**: the circle of radius R_agg + ``CLEARANCE`` around the attacker's
  predicted position, which it does not perceive, so it keeps its course; the
  three nearest defenders take places 120° apart, the first on the attacker's
  escape direction (its undisturbed course), the others the bisectors between
  them; a defender whose straight way to its place would cross the circle goes
  round it (its target at most ``ORBIT_STEP`` radians ahead on the circle). The
  first to stand at the escape-side place steps in to ``BLOCK`` R_agg and holds
  the attacker where it is while the others come;
- **herd** (only with an *anchor*: a failed defender, which must end in the
  circle, or an obstacle standing in for a third robot when fewer than three
  can move): from the moment one mover stands at its place, the movers close in
  behind the attacker, at ``PUSH`` R_agg, to push it towards a point
  ``ANCHOR_GAP`` from the anchor;
- **close**, once at least three defenders near the circle surround the
  attacker (no gap between neighbours wider than ``MAX_GAP``; with an anchor,
  once the attacker is at it): the radius shrinks at ``SHRINK_RATE`` of the
  slowest defender's speed (no faster than the farthest defender of the first
  three follows) to R_hunt / 2, the attacker's reference is the centre, and the
  centre moves at ``DRIFT`` of the attacker's top speed towards the farthest
  defender still on its way (the success test needs every robot within R_hunt).
  Nothing switches at R_agg: the capture problem plans every active defender at
  every step.

If the attacker leaves the closing circle (farther than half its radius from
the centre), the circle gathers again.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from mpc_hunt.capture.problem import EncloseWeights, Reference
from mpc_hunt.compiled import kernel
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.reference import Places
from mpc_hunt.world.attacker import velocity_of
from mpc_hunt.world.geometry import direction, norm, run_towards, unit
from mpc_hunt.world.packed import T
from mpc_hunt.world.scenario import Scenario

CLEARANCE = 0.3  # m beyond R_agg: the gathering circle, which the attacker does not perceive
ARRIVED_ANGLE = 0.3  # rad: a defender this close to its place's bearing (and ARRIVED_RADIUS to its radius) is there
ARRIVED_RADIUS = 0.25  # m
ORBIT_STEP = 0.5  # rad: how far ahead on the circle a defender going round aims
SHRINK_RATE = 0.5  # of the slowest defender's speed: how fast the closing circle contracts
FOLLOW_SLACK = 0.1  # m: the circle waits while a defender of the first three is this much farther out
PUSH = 0.8  # of R_agg: how close the movers herd the attacker from behind
ANCHOR_GAP = 0.3  # m from an anchor's surface (or a failed robot): where an anchor's circle is centred
HERDED = 0.3  # m: the attacker this close to that point, the circle closes
TERMINAL_WEIGHT = 5.0  # the places' weight at step N (the others: 1)
CORE = 3  # the fewest members that enclose
DRIFT = 0.7  # of the attacker's top speed: how fast the closing circle moves towards a latecomer
BLOCK = 0.9  # of R_agg: where the escape-side defender holds the attacker while the others come
MAX_GAP = 2.6  # rad (about 150°): the widest gap between neighbours that still surrounds the attacker
SWAP_MARGIN = 0.5  # m: how much nearer a defender must be to take a first member's place


@kernel
def wrap(angle: float) -> float:
    """``angle`` in [−π, π)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


@kernel
def predicted_path(
    p_a: np.ndarray, p_d: np.ndarray, centres: np.ndarray, radii: np.ndarray, prm: np.ndarray, horizon: int
) -> np.ndarray:
    """The attacker at steps 1..N (Eq. 2, the model's parameters ``prm``, :mod:`mpc_hunt.world.packed`) with the
    defenders ``p_d`` held where they are."""
    out, p = np.empty((horizon, 2)), p_a.copy()
    for k in range(horizon):
        vx, vy = velocity_of(p, p_d, centres, radii, prm)
        p[0], p[1] = p[0] + prm[T] * vx, p[1] + prm[T] * vy
        out[k, 0], out[k, 1] = p[0], p[1]
    return out


@kernel
def route(p: np.ndarray, predicted: np.ndarray, angle: float, radius: float, reach: float) -> np.ndarray:
    """A defender's targets at steps 1..N: towards its place on the circle round the predicted attacker,
    going round the circle where the straight way would cross it; each no farther than it can move."""
    N = predicted.shape[0]
    out = np.empty((N, 2))
    qx, qy = p[0] - predicted[0, 0], p[1] - predicted[0, 1]
    distance, bearing = np.hypot(qx, qy), math.atan2(qy, qx)
    turn = wrap(angle - bearing)
    if abs(turn) > ORBIT_STEP:
        angle = bearing + math.copysign(ORBIT_STEP, turn)
        radius = max(radius, min(distance, radius + 1.0))
    cx, cy = radius * np.cos(angle), radius * np.sin(angle)
    for k in range(N):
        out[k, 0], out[k, 1] = run_towards(p[0], p[1], predicted[k, 0] + cx, predicted[k, 1] + cy, (k + 1) * reach)
    return out


@dataclass
class _Circle:
    """The memory between steps: the phase and, once closing, the frozen centre and the radius."""

    phase: str = "gather"
    centre: np.ndarray | None = None
    radius: float | None = None
    heading: float | None = None  # the frozen escape (or herding) direction while closing

    def frozen(self) -> tuple[np.ndarray, float, float]:
        """The centre, radius and heading of a closing circle (all three are set as it closes)."""
        if self.centre is None or self.radius is None or self.heading is None:
            raise RuntimeError(f"a {self.phase} circle has no centre, radius and heading")
        return self.centre, self.radius, self.heading


class Enclosure(Places):
    """Builds each step's :class:`~mpc_hunt.capture.problem.Reference` for the ``enclose`` objective."""

    NAME = "enclose"
    SUMMARY = (
        "the paper's model and constraints with the enclose objective: every defender planned towards "
        "places on a hunting circle round the believed attacker (docs/formulations.md)"
    )
    weights = EncloseWeights()

    def __init__(self, scenario: Scenario, horizon: int, posed: Callable[[], Scenario] | None = None):
        super().__init__(scenario, horizon, posed)
        self.circle = _Circle()
        self._members: list[int] = []  # the first three, kept between steps

    @property
    def phase(self) -> str:
        return self.circle.phase

    def reference(self, obs: Observation) -> Reference:
        """Places for every defender (held ones: where they stand) and the attacker, steps 1..N."""
        s, N = self.scenario, self.horizon
        T, R = s.hunt.time_step, s.attacker.perception_radius
        p_a, P = obs.attacker, obs.defenders
        movers = np.flatnonzero(obs.active)
        predicted = self._predicted(p_a, P)
        anchor = self._anchor(obs, len(movers))
        c = self.circle
        if c.phase == "close":
            centre, radius, _ = c.frozen()
            if norm(p_a - centre) > max(0.5 * radius, ANCHOR_GAP):
                self.circle = c = _Circle()  # it slipped out: gather again
        core = self._core(p_a if c.centre is None else c.centre, P, movers)
        if c.phase != "close":
            angles, heading = self._angles(p_a, P, movers, core, anchor, predicted)
            ready = (
                self._behind(p_a, P, movers, heading, R + CLEARANCE)
                if anchor is not None
                else self._surrounded(p_a, P, movers, R + CLEARANCE)
            )
            if c.phase == "gather" and ready:
                c.phase = "herd" if anchor is not None and norm(p_a - anchor) > HERDED else "close"
            if c.phase == "herd" and norm(p_a - anchor) <= HERDED:
                c.phase = "close"
            if c.phase == "close":
                c.centre, c.heading = (p_a.copy() if anchor is None else anchor), heading
                nearest_fit = float(max(norm(P[i] - c.centre) for i in core))
                c.radius = max(0.5 * s.hunt.hunt_radius, min(R + CLEARANCE, nearest_fit))
        places = np.repeat(P[None], N, axis=0).astype(float)
        undisturbed = self._predicted(p_a, P[:0])
        target = undisturbed  # gathering, the attacker should not notice anybody
        if c.phase == "close":
            centre, radius, heading = c.frozen()
            angles = self._spread(centre, P, movers, core, anchor, heading, radius)
            farthest = float(max(norm(P[i] - centre) for i in core))
            rate = SHRINK_RATE * float(np.min(s.defender_max_speeds[movers])) * T
            ring = 0.5 * s.hunt.hunt_radius
            c.radius = radius = max(ring, min(radius, max(radius - rate, farthest - FOLLOW_SLACK)))
            radii = np.maximum(ring, radius - rate * np.arange(1, N + 1))
            drift = self._drift(c, P, movers) if anchor is None else np.zeros(2)
            centres = centre + np.arange(1, N + 1)[:, None] * drift
            c.centre = centre + drift
            for i in movers:
                places[:, i] = centres + radii[:, None] * direction(angles[int(i)])
            target = centres
        else:
            radius = PUSH * R if c.phase == "herd" else R + CLEARANCE
            blocker = (
                self._blocker(p_a, P, core, angles, heading, R + CLEARANCE)
                if c.phase == "gather" and anchor is None
                else None
            )
            for i in movers:
                ring = BLOCK * R if i == blocker else radius
                places[:, i] = route(P[i], predicted, angles[i], ring, s.defender_max_speeds[i] * T)
            if blocker is not None:
                target = np.repeat(p_a[None], N, axis=0)  # held while the others come
            if c.phase == "herd":
                target[:] = anchor
        weight = np.ones(N)
        weight[-1] = TERMINAL_WEIGHT
        return Reference(places, target, weight)

    def _predicted(self, p_a: np.ndarray, P: np.ndarray) -> np.ndarray:
        """The attacker at steps 1..N with the defenders ``P`` held where they are (Eq. 2)."""
        s = self.scenario
        P = np.asarray(P, dtype=float).reshape(-1, 2)
        return predicted_path(
            np.asarray(p_a, dtype=float), P, s.obstacle_centres, s.obstacle_radii, s.packed, self.horizon
        )

    def _anchor(self, obs: Observation, movers: int) -> np.ndarray | None:
        """Where the circle must be centred to include a stationary member, or None (enclose in place).

        A failed defender must end inside the circle (the success test counts every robot); with fewer
        than three movers and no failed one, the obstacle whose surface is nearest the attacker stands in.
        """
        s, p_a = self.scenario, obs.attacker
        if obs.failed is not None and obs.failed.any():
            stopped = obs.defenders[obs.failed]
            nearest = stopped[np.argmin(norm(stopped - p_a))]
            return nearest + ANCHOR_GAP * unit(p_a - nearest)
        if movers >= CORE or not len(s.obstacles):
            return None
        gaps = norm(p_a - s.obstacle_centres) - s.obstacle_radii
        j = int(np.argmin(gaps))
        return s.obstacle_centres[j] + (s.obstacle_radii[j] + s.hunt.safety_distance + ANCHOR_GAP) * unit(
            p_a - s.obstacle_centres[j]
        )

    def _core(self, centre: np.ndarray, P: np.ndarray, movers: np.ndarray) -> np.ndarray:
        """The (up to) three movers nearest ``centre``: the first members of the circle (once per step).

        Sticky: a member is replaced only by a mover ``SWAP_MARGIN`` nearer, so two defenders at much the
        same distance do not trade places (and targets) step after step.
        """
        distance = {int(i): float(norm(P[i] - centre)) for i in movers}
        core = [i for i in self._members if i in distance]
        for i in sorted(distance, key=distance.__getitem__):
            if i in core:
                continue
            if len(core) < CORE:
                core.append(i)
                continue
            worst = max(core, key=distance.__getitem__)
            if distance[i] < distance[worst] - SWAP_MARGIN:
                core[core.index(worst)] = i
        self._members = core
        return np.array(sorted(core, key=distance.__getitem__), dtype=int)

    def _angles(self, centre, P, movers, core, anchor, predicted, heading: float | None = None):
        """Each mover's bearing on the circle around ``centre``, and the direction the first place faces."""
        if heading is None:
            if anchor is not None:
                heading = math.atan2(*(centre - anchor)[::-1])  # behind the attacker, seen from the anchor
            else:
                v = self._predicted(centre, P[:0])[0] - centre
                heading = math.atan2(v[1], v[0]) if np.hypot(*v) > 0 else 0.0
        bearing = {int(i): math.atan2(*(P[i] - centre)[::-1]) for i in movers}
        angles: dict[int, float] = {}
        if anchor is not None:  # the anchor holds the place opposite the heading; the movers share the rest
            n = len(movers)
            slots = [heading + math.pi + 2 * math.pi * (j + 1) / (n + 1) for j in range(n)]
            order = sorted(movers, key=lambda i: wrap(bearing[int(i)] - heading - math.pi) % (2 * math.pi))
            return {int(i): slots[j] for j, i in enumerate(order)}, heading
        k = len(core)
        slots = [heading + 2 * math.pi * j / k for j in range(k)]
        order = sorted(core, key=lambda i: bearing[int(i)] % (2 * math.pi))
        best = min(
            range(k),
            key=lambda rot: max(abs(wrap(slots[(j + rot) % k] - bearing[int(i)])) for j, i in enumerate(order)),
        )
        angles.update({int(i): slots[(j + best) % k] for j, i in enumerate(order)})
        spare = [heading + math.pi / k + 2 * math.pi * j / k for j in range(k)]
        for i in sorted((i for i in movers if i not in core), key=lambda i: norm(P[i] - centre)):
            j = min(range(len(spare)), key=lambda j: abs(wrap(spare[j] - bearing[int(i)])))
            angles[int(i)] = spare.pop(j) if len(spare) > 1 else spare[0]
        return angles, heading

    def _spread(self, centre, P, movers, core, anchor, heading: float, radius: float) -> dict[int, float]:
        """Places on the closing circle: the movers within reach of it (and the anchor) evenly spaced, in the
        order they stand, turned as little as possible; each latecomer on the bisector of the widest gap."""
        bearing = {int(i): math.atan2(*(P[i] - centre)[::-1]) for i in movers}
        present = [int(i) for i in movers if norm(P[i] - centre) <= radius + 2 * ARRIVED_RADIUS]
        if anchor is not None:
            return self._angles(centre, P, movers, core, anchor, None, heading)[0]
        if len(present) < CORE:
            present = [int(i) for i in core]
        n = len(present)
        order = sorted(present, key=lambda i: bearing[i] % (2 * math.pi))
        offset = math.atan2(
            sum(math.sin(bearing[i] - 2 * math.pi * j / n) for j, i in enumerate(order)),
            sum(math.cos(bearing[i] - 2 * math.pi * j / n) for j, i in enumerate(order)),
        )
        angles = {i: offset + 2 * math.pi * j / n for j, i in enumerate(order)}
        taken = sorted(a % (2 * math.pi) for a in angles.values())
        for i in (int(i) for i in movers if int(i) not in angles):
            gaps = [(taken[(j + 1) % n] - taken[j]) % (2 * math.pi) or 2 * math.pi for j in range(n)]
            j = int(np.argmax(gaps))
            angles[i] = taken[j] + gaps[j] / 2
        return angles

    def _drift(self, c: _Circle, P: np.ndarray, movers: np.ndarray) -> np.ndarray:
        """One step of the closing circle's centre towards the farthest defender still on its way (the
        circle carries the attacker, at ``DRIFT`` of its top speed), until that defender is near."""
        s = self.scenario
        centre, radius, _ = c.frozen()
        away = {int(i): float(norm(P[i] - centre)) for i in movers}
        i = max(away, key=away.__getitem__)
        gap = away[i] - (radius + s.attacker.perception_radius + CLEARANCE)
        if gap <= 0:
            return np.zeros(2)
        return unit(P[i] - centre) * min(gap, DRIFT * s.attacker.max_speed * s.hunt.time_step)

    def _blocker(self, p_a, P, core, angles, heading, radius) -> int | None:
        """The first member whose place faces the escape direction, once it stands there (else None)."""
        for i in core:
            if abs(wrap(angles[int(i)] - heading)) < 1e-9:
                return int(i) if self._there(p_a, P, i, heading, radius) else None
        return None

    def _behind(self, p_a, P, movers, heading, radius) -> bool:
        """Does a mover stand near the circle on the attacker's far side from the anchor (within 90° of
        ``heading``), where it can push the attacker towards it?"""
        offsets = P[movers] - p_a
        bearings = np.arctan2(offsets[:, 1], offsets[:, 0])
        return bool(
            np.any(
                (norm(offsets) <= radius + ARRIVED_RADIUS)
                & (np.abs((bearings - heading + math.pi) % (2 * math.pi) - math.pi) <= math.pi / 2)
            )
        )

    def _surrounded(self, p_a, P, movers, radius) -> bool:
        """Do at least three movers near the gathering circle surround the attacker, no gap between
        neighbours' bearings wider than ``MAX_GAP``? (Which defender stands where does not matter.)"""
        offsets = P[movers] - p_a
        near = offsets[norm(offsets) <= radius + ARRIVED_RADIUS]
        if len(near) < CORE:
            return False
        bearings = np.sort(np.arctan2(near[:, 1], near[:, 0]))
        gaps = np.diff(np.append(bearings, bearings[0] + 2 * math.pi))
        return float(gaps.max()) <= MAX_GAP

    def _there(self, p_a, P, i, angle, radius) -> bool:
        """Does defender ``i`` stand at its place, bearing ``angle`` from ``p_a``, no farther out than the circle of
        ``radius`` allows? (Nearer counts: a defender stepping in from its place is still there, so the test
        does not flip as it moves.)"""
        offset = P[i] - p_a
        return (
            abs(wrap(math.atan2(offset[1], offset[0]) - angle)) <= ARRIVED_ANGLE
            and norm(offset) <= radius + ARRIVED_RADIUS
        )

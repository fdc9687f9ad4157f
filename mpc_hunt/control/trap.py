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
  limit along the ray, a soft minimum over them, so every mover has a share;
  b: the nearest obstacle; e: the edge). This is the area-minimising pursuit of
  a reachable set (Huang et al. 2011; Pierson et al., RA-L 2017) with the
  edge's openings closed first: the defender that owns an open arc cuts it, the
  others close the rest, and a team too small to enclose alone leans on the
  obstacles that close the other directions (the paper's obstacles as members).
  The places over the horizon are the straight run at top speed: a
  minimum-time closing, not a tracking of places;
- **close** (the attacker strictly inside the hull of the movers and the
  stationary members, and no direction open to the edge): places on an even
  spread round the attacker (:func:`~mpc_hunt.control.voronoi.ring_bearings`,
  a stationary member first), their common centre shifted so that the
  members' centroid is the attacker (Eq. 4), the radius shrinking from where
  each mover stands at its speed less v_a (what the attacker can push back)
  to R_hunt / 2, every place moving with the attacker's observed velocity.

Places stay in the arena and out of every obstacle's R_safe; the capture
problem (:class:`~mpc_hunt.capture.problem.CaptureProblem`, the ``enclose``
objective with no term on a predicted attacker) plans every active defender
over the horizon under the constraints (steps within r_d, Eq. 13; R_safe,
Eq. 15; separation; the arena).
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.capture.problem import Reference
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.enclosure import TERMINAL_WEIGHT
from mpc_hunt.control.observed import ObservedVelocity
from mpc_hunt.control.voronoi import ring_bearings
from mpc_hunt.world.arena import kept_clear
from mpc_hunt.world.geometry import direction, encloses, norm
from mpc_hunt.world.hunting_circle import members
from mpc_hunt.world.reachable_set import defender_reach, edge_distance, obstacle_block, ray_directions
from mpc_hunt.world.scenario import Scenario

W_EDGE = 20.0         # m: an open ray's penalty per metre beyond the edge less the margin (a ray this long's weight)
EDGE_MARGIN = 1.0     # m: how far inside the edge the region's boundary must stay to count as closed
SOFTNESS = 0.5        # m: the soft minimum's width over the defenders' limits
STEP = 1e-4           # m: the finite difference of the gradient


class Trap:
    """Builds each step's :class:`~mpc_hunt.capture.problem.Reference` for the ``trap`` controller."""

    def __init__(self, scenario: Scenario, horizon: int):
        self.scenario = scenario
        self.horizon = horizon
        self.observed = ObservedVelocity(scenario)
        self.rays = ray_directions()
        self.phase = "shrink"

    def cost(self, p_a: np.ndarray, movers: np.ndarray, speeds: np.ndarray, blocked: np.ndarray,
             edge: np.ndarray) -> float:
        """J of the module's docstring for the movers at ``movers`` (k, 2)."""
        s = self.scenario
        limits = defender_reach(p_a, self.rays, movers, s.attacker.max_speed / speeds, 0.5 * s.hunt.hunt_radius)
        low = limits.min(axis=1)
        soft = low - SOFTNESS * np.log(np.sum(np.exp(-(limits - low[:, None]) / SOFTNESS), axis=1))
        area = 0.5 * np.sum(np.minimum(soft, np.minimum(blocked, edge)) ** 2)
        open_ = blocked > edge
        penalty = W_EDGE * np.sum(np.where(open_, np.maximum(0.0, soft - (edge - EDGE_MARGIN)), 0.0))
        return float((area + penalty) * 2 * np.pi / len(self.rays))

    def headings(self, p_a: np.ndarray, movers: np.ndarray, speeds: np.ndarray) -> np.ndarray:
        """Each mover's unit direction down the gradient of J (towards the attacker where J is flat for it)."""
        s = self.scenario
        blocked = obstacle_block(p_a, self.rays, s.obstacle_centres, s.obstacle_radii)
        edge = edge_distance(p_a, self.rays, s.arena)
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
        """Is the attacker inside the members' hull with no direction open to the arena's edge?"""
        s = self.scenario
        if not encloses(p_a, np.vstack([movers, stationary])):
            return False
        limits = defender_reach(p_a, self.rays, movers, s.attacker.max_speed / speeds, 0.5 * s.hunt.hunt_radius)
        blocked = obstacle_block(p_a, self.rays, s.obstacle_centres, s.obstacle_radii)
        edge = edge_distance(p_a, self.rays, s.arena)
        return not np.any((limits.min(axis=1) > edge - EDGE_MARGIN) & (blocked > edge))

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
        stationary = np.vstack([P[~obs.active], m.anchors[len(P):]])
        places = np.repeat(P[None], N, axis=0).astype(float)
        steps = (np.arange(1, N + 1) * T)[:, None]
        if len(movers) and self.closed(p_a, P[movers], speeds, stationary):
            self.phase = "close"
            places[:, movers] = self._ring(p_a, P[movers], speeds, stationary, steps) + drift[:, None]
        elif len(movers):
            self.phase = "shrink"
            ways = self.headings(p_a, P[movers], speeds)
            places[:, movers] = P[movers][None] + (speeds[None, :, None] * steps[:, :, None]) * ways[None]
        for k in range(N):
            for i in movers:
                places[k, i] = kept_clear(s, places[k, i])
        weight = np.ones(N)
        weight[-1] = TERMINAL_WEIGHT
        return Reference(places, p_a + drift, weight)

    def _ring(self, p_a: np.ndarray, movers: np.ndarray, speeds: np.ndarray, stationary: np.ndarray,
              steps: np.ndarray) -> np.ndarray:
        """The close phase's places (N, k, 2) round the attacker where it stands (the module's docstring)."""
        s = self.scenario
        inner = 0.5 * s.hunt.hunt_radius
        angles = ring_bearings(p_a, movers, stationary)
        start = norm(movers - p_a)
        radii = np.maximum(inner, start[None] - (speeds - s.attacker.max_speed)[None] * steps)    # (N, k)
        places = p_a + radii[:, :, None] * direction(angles)[None]
        near = stationary[norm(stationary - p_a) <= s.hunt.hunt_radius]
        count = len(movers) + len(near)
        centroid = (places.sum(axis=1) + near.sum(axis=0)) / count                                # (N, 2)
        return places + ((p_a - centroid) * count / len(movers))[:, None, :]

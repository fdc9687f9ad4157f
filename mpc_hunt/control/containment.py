"""Where the defenders should be when the attacker's law is unknown: the reference of the ``contain`` controller.

The ``enclose`` reference (:mod:`mpc_hunt.control.enclosure`) is built on the
defenders' model of the attacker: it gathers outside R_agg because the model
says the attacker does not perceive them there, puts the first place on the
model's undisturbed course and freezes the closing circle's centre. Against an
attacker that follows another law it loses (docs/model.md, E15). This reference assumes only what the defenders
observe and the
attacker's top speed:

- each mover's place comes from the Voronoi encirclement
  (:meth:`mpc_hunt.control.voronoi.VoronoiController.aims`: the area-minimising
  pursuit of Zhou et al. 2016 on an even spread round the attacker, in the
  order the defenders stand; an intercept point while the attacker is not
  enclosed, the attacker itself once it is);
- over the horizon the places move with the attacker's *observed* velocity
  (:class:`~mpc_hunt.control.observed.ObservedVelocity`, capped at v_a),
  so the ring co-moves with whatever the attacker does instead of being frozen;
- a defender's place at step k is no farther than k steps of its top speed,
  going round the tightest ring any defender aims at where the straight way
  would cross it (the baseline goes round the circle of the defender's own
  radius, half a far defender's distance, the long way round);
- the attacker's reference is its observed-velocity prediction, so the
  capture problem tracks the places and does not try to herd through a model.

The capture problem (:class:`~mpc_hunt.capture.problem.CaptureProblem`, the
``enclose`` objective) then plans every active defender over the horizon under
the constraints the baseline only filters for: steps within r_d (Eq. 13), the
obstacles' safety distance (Eq. 15), separation, the arena.
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.capture.problem import EncloseWeights, Reference
from mpc_hunt.compiled import kernel
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.enclosure import TERMINAL_WEIGHT
from mpc_hunt.control.observed import ObservedVelocity
from mpc_hunt.control.reference import Places
from mpc_hunt.control.voronoi import VoronoiController, routed
from mpc_hunt.world.arena import clear_of
from mpc_hunt.world.geometry import run_towards
from mpc_hunt.world.packed import T
from mpc_hunt.world.scenario import Scenario

# No term on the attacker's predicted position: the prediction is the defenders' model, which this controller
# does not trust to herd with; the arena's edge term stays (it only ever keeps the attacker in).
CONTAIN_WEIGHTS = EncloseWeights(attacker=0.0)


@kernel
def around(p_d, cx: float, cy: float, angle: float, radius: float, guard: float, reach: float) -> tuple[float, float]:
    """The place at ``angle`` on the circle ((cx, cy), ``radius``), straight, unless the straight way passes
    inside the ``guard`` circle round the centre (the tightest ring any defender aims at): then round that
    circle (:func:`~mpc_hunt.control.voronoi.routed` on it). A far defender takes the short way to a far-side place
    instead of going round the wide circle of its own Voronoi radius."""
    px, py = cx + radius * np.cos(angle), cy + radius * np.sin(angle)
    wx, wy = px - p_d[0], py - p_d[1]
    way = np.hypot(wx, wy)
    if way == 0:
        return px, py
    along = min(max(((cx - p_d[0]) * wx + (cy - p_d[1]) * wy) / way**2, 0.0), 1.0)
    if np.hypot(p_d[0] + along * wx - cx, p_d[1] + along * wy - cy) >= guard:
        return px, py
    return routed(p_d, cx, cy, angle, max(guard, 1e-9), reach)


@kernel
def contain_places(P, movers, circles, angles, rings, enclosed, drift, speeds, centres, radii, prm) -> np.ndarray:
    """Every defender's places at steps 1..N (N = ``drift``'s rows; a held one: where it stands): each mover's
    place (its circle ``circles[r]``, bearing ``angles[r]``, radius ``rings[r]``; the circle moved by ``drift``
    once the attacker is ``enclosed``) by :func:`around`, out of R_safe (:func:`clear_of`), no farther than k
    steps of its top speed."""
    N = drift.shape[0]
    places = np.empty((N, P.shape[0], 2))
    for k in range(N):
        places[k] = P
    guard = rings.min() if rings.shape[0] else 0.0
    for r in range(movers.shape[0]):
        i = movers[r]
        reach = speeds[i] * prm[T]
        for k in range(N):
            cx, cy = circles[r, 0], circles[r, 1]
            if enclosed:
                cx, cy = cx + drift[k, 0], cy + drift[k, 1]
            gx, gy = around(P[i], cx, cy, angles[r], rings[r], guard, reach)
            gx, gy = clear_of(gx, gy, centres, radii, prm)
            places[k, i, 0], places[k, i, 1] = run_towards(P[i, 0], P[i, 1], gx, gy, (k + 1) * reach)
    return places


class Unmodelled(Places):
    """The base of a reference that assumes no model of the attacker (``contain``, ``trap``): the objective with
    no term on its predicted position (``CONTAIN_WEIGHTS``), and its velocity as the defenders observe it
    (``self.observed``, fed every observation by :meth:`reference`); a subclass sets ``NAME``, ``SUMMARY`` and
    builds :meth:`reference`."""

    weights = CONTAIN_WEIGHTS

    def __init__(self, scenario: Scenario, horizon: int):
        super().__init__(scenario, horizon)
        self.observed = ObservedVelocity(scenario)


class Containment(Unmodelled):
    """Builds each step's :class:`~mpc_hunt.capture.problem.Reference` for the ``contain`` controller."""

    NAME = "contain"
    SUMMARY = (
        "the capture problem tracking the Voronoi rule's places, moved with the attacker's observed "
        "velocity (no model of the attacker)"
    )

    def __init__(self, scenario: Scenario, horizon: int):
        super().__init__(scenario, horizon)
        self.rule = VoronoiController(scenario)

    def reference(self, obs: Observation) -> Reference:
        """Places for every defender (held ones: where they stand) and the attacker, steps 1..N."""
        s, N = self.scenario, self.horizon
        T = s.hunt.time_step
        P = obs.defenders
        drift = self.observed.update(obs) * T * np.arange(1, N + 1)[:, None]
        movers, circles, angles, rings, enclosed = self.rule.aims(obs)
        places = contain_places(
            np.asarray(P, dtype=float),
            movers,
            circles,
            angles,
            rings,
            enclosed,
            drift,
            s.defender_max_speeds,
            s.obstacle_centres,
            s.obstacle_radii,
            s.packed,
        )
        weight = np.ones(N)
        weight[-1] = TERMINAL_WEIGHT
        return Reference(places, obs.attacker + drift, weight)

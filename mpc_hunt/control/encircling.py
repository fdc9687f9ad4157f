"""The traditional baseline: a hunting circle of robots only, by potential fields, with no optimisation.

The paper compares its strategy against hunting "using only robots". Here every
defender runs the approaching stage (Eq. 6 towards the predicted intercept)
until it is within R_agg; inside, its target is the point of the circle of
radius R_hunt / 2 around the attacker on its own bearing, turned along the
circle away from capture-stage neighbours that are closer in angle than an even
spread (2π / n), and Eq. 6's obstacle and defender repulsion blends in as in the
approaching stage. Obstacles are never members and nothing is herded: the
robots close the circle and follow the attacker. The approaching stage's
commands keep the safety distance R_safe (:mod:`mpc_hunt.world.safety`); every
command passes the separation filter (:mod:`mpc_hunt.world.separation`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.control.controller import Command, Observation, previous_of
from mpc_hunt.control.scenario_rule import ScenarioRule
from mpc_hunt.control.strategy import approach_stage
from mpc_hunt.world.approach import approach_of
from mpc_hunt.world.geometry import length
from mpc_hunt.world.packed import HUNT_RADIUS, MIN_SEPARATION, R_AGG, T
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.separation import separated


@kernel
def circle_targets(p_a: np.ndarray, p_d: np.ndarray, ring_radius: float) -> np.ndarray:
    """Each defender's place on the circle around ``p_a``: its bearing, spread towards 2π / n spacing."""
    n = p_d.shape[0]
    bearing = np.empty(n)
    for i in range(n):
        bearing[i] = math.atan2(p_d[i, 1] - p_a[1], p_d[i, 0] - p_a[0])
    spacing = 2 * np.pi / n
    out = np.empty((n, 2))
    for i in range(n):
        turn = 0.0
        for j in range(n):
            if i != j:
                gap = (bearing[i] - bearing[j] + np.pi) % (2 * np.pi) - np.pi  # in (−π, π]
                if abs(gap) < spacing:
                    turn += 0.5 * (1.0 if gap >= 0 else -1.0) * (spacing - abs(gap))
        angle = bearing[i] + turn
        out[i, 0], out[i, 1] = p_a[0] + ring_radius * math.cos(angle), p_a[1] + ring_radius * math.sin(angle)
    return out


@kernel
def apf_command(p_a, previous, P, active, centres, radii, speeds, prm, prediction, velocities, capture, intercepts):
    """The module's rule for one hunt, into ``velocities`` (n, 2), ``capture`` (n,) and ``intercepts`` (n, 2)."""
    n = P.shape[0]
    for i in range(n):
        capture[i] = active[i] and length(p_a[0] - P[i, 0], p_a[1] - P[i, 1]) < prm[R_AGG]
    velocities[:] = 0.0
    intercepts[:] = np.nan
    approach_stage(p_a, previous, P, ~capture & active, speeds, centres, radii, prm, prediction, velocities,
                   intercepts)  # fmt: skip
    inside = np.flatnonzero(capture)
    if inside.shape[0]:
        targets = circle_targets(p_a, P[inside], 0.5 * prm[HUNT_RADIUS])
        for r in range(inside.shape[0]):
            i = inside[r]
            velocities[i, 0], velocities[i, 1] = approach_of(P, i, targets[r, 0], targets[r, 1], speeds[i], centres,
                                                             radii, prm)  # fmt: skip
    separated(P, velocities, active, P, prm[T], speeds, prm[MIN_SEPARATION])


@kernel
def apf_batch(running, p_a, previous, p_d, n, failed, centres, radii, m, speeds, prm, prediction, velocities, capture,
              intercepts) -> None:  # fmt: skip
    """:func:`apf_command` for every running hunt of a batch (arrays padded; ``n``, ``m`` their counts)."""
    for b in range(running.shape[0]):
        if running[b]:
            k, j = n[b], m[b]
            apf_command(p_a[b], previous[b], p_d[b, :k], ~failed[b, :k], centres[b, :j], radii[b, :j], speeds[b, :k],
                        prm[b], prediction[b], velocities[b, :k], capture[b, :k], intercepts[b, :k])  # fmt: skip


class EncirclingController:
    """Potential-field encirclement: the no-optimisation baseline (CLI ``--controller apf``); a batch of hunts in
    one call (:meth:`batched`)."""

    SUMMARY = "the traditional potential-field encirclement, no optimisation"

    def __init__(self, scenario: Scenario, *, prediction: bool = True):
        self.scenario = scenario
        self.prediction = prediction

    def describe(self) -> dict:
        return {"controller": "apf", "prediction": self.prediction}

    def command(self, obs: Observation) -> Command:
        s, P = self.scenario, np.asarray(obs.defenders, float)
        previous = previous_of(obs)
        velocities, capture, intercepts = np.zeros_like(P), np.zeros(len(P), dtype=bool), np.empty_like(P)
        apf_command(np.asarray(obs.attacker, float), previous, P, obs.active, s.obstacle_centres, s.obstacle_radii,
                    s.defender_max_speeds, s.packed, self.prediction, velocities, capture, intercepts)  # fmt: skip
        return Command(velocities, capture, intercepts)

    @staticmethod
    def batched(controllers: Sequence[EncirclingController | None]) -> ScenarioRule:
        """The rule of ``controllers`` (None: a hunt commanded otherwise) for a batch, hunt b by its own."""
        return ScenarioRule(controllers, apf_batch)

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

import numpy as np

from mpc_hunt.control.controller import Command, Observation
from mpc_hunt.control.strategy import approach_commands
from mpc_hunt.world import attacker
from mpc_hunt.world.approach import approach_velocity
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.separation import keep_separation


def circle_targets(p_a: np.ndarray, p_d: np.ndarray, ring_radius: float) -> np.ndarray:
    """Each defender's place on the circle around ``p_a``: its bearing, spread towards 2π / n spacing."""
    offsets = p_d - p_a
    bearing = np.arctan2(offsets[:, 1], offsets[:, 0])
    n = len(p_d)
    spacing = 2 * np.pi / n
    turn = np.zeros(n)
    for i in range(n):
        for j in range(n):
            if i != j:
                gap = (bearing[i] - bearing[j] + np.pi) % (2 * np.pi) - np.pi  # in (−π, π]
                if abs(gap) < spacing:
                    turn[i] += 0.5 * np.sign(gap or 1.0) * (spacing - abs(gap))
    angle = bearing + turn
    return p_a + ring_radius * np.stack([np.cos(angle), np.sin(angle)], axis=1)


class EncirclingController:
    """Potential-field encirclement: the no-optimisation baseline (CLI ``--controller apf``)."""

    SUMMARY = "the traditional potential-field encirclement, no optimisation"

    def __init__(self, scenario: Scenario, *, prediction: bool = True):
        self.scenario = scenario
        self.prediction = prediction

    def describe(self) -> dict:
        return {"controller": "apf", "prediction": self.prediction}

    def command(self, obs: Observation) -> Command:
        s = self.scenario
        capture = attacker.perceives(s, obs.attacker, obs.defenders) & obs.active
        velocities, intercepts = approach_commands(s, obs, ~capture & obs.active, self.prediction)
        inside = np.flatnonzero(capture)
        if len(inside):
            targets = circle_targets(obs.attacker, obs.defenders[inside], 0.5 * s.hunt.hunt_radius)
            speeds = s.defender_max_speeds
            for target, i in zip(targets, inside):
                others = np.delete(obs.defenders, i, axis=0)
                velocities[i] = approach_velocity(s, obs.defenders[i], target, speeds[i], others)
        velocities = keep_separation(
            obs.defenders,
            velocities,
            obs.active,
            obs.defenders,
            s.hunt.time_step,
            s.defender_max_speeds,
            s.hunt.min_separation,
        )
        return Command(velocities, capture, intercepts)

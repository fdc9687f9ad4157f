"""A team's capture problem as its robots see it (the ``distributed`` formulation,
:mod:`mpc_hunt.formulations.distributed`).

The numbers the team shares at a state (the team's θ, each robot's places), the
round's broadcast (:mod:`mpc_hunt.formulations.team_push`: the attacker's path under the
team's plans and each defender's push on it), and each robot's step inputs: its
own θ, laid out for its structure (:func:`robot_structure`, ``Structure.robot``),
and its reference. A robot's separation rows go to the midpoints between its
reference and its ``NEIGHBOURS`` nearest team-mates' at each step; a row to a
team-mate farther than d_min + 2ρ (ρ = the trust region's diagonal, 2√2 r_d)
can never bind, and team-mates nearer than that beyond the slots are counted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.structure import Structure
from mpc_hunt.formulations.capture_model import (
    pack,
    parameter_size,
    parameter_vector,
    reference_size,
    step_size,
    unpack,
)
from mpc_hunt.formulations.qp import TRUST_REGION
from mpc_hunt.formulations.team_push import team_push

NEIGHBOURS = 8  # slots: 7 team-mates d_min apart fit within d_min + 2ρ of a robot at the paper's numbers


def robot_structure(team: Structure) -> Structure:
    """The structure of one robot's QP in a team of structure ``team``."""
    return Structure(1, min(team.defenders - 1, NEIGHBOURS), team.obstacles, team.horizon, team.objective, robot=True)


@dataclass(frozen=True)
class Broadcast:
    """A round's broadcast under the team's ``plans`` (N, n, 2; the held defenders where they stand): the
    attacker's path ``path`` (N, 2), each defender's push on it (N, n, 2) and that push's Jacobian (N, n, 4),
    and their sums over the team."""

    plans: np.ndarray
    path: np.ndarray
    pushes: np.ndarray
    jacobians: np.ndarray
    push: np.ndarray
    jacobian: np.ndarray


class Team:
    """A team's capture problem as its robots see it: the numbers they share, and each one's inputs."""

    def __init__(self, problem: CaptureProblem, smoothing: float):
        self.structure = problem.structure
        self.robot = robot_structure(self.structure)
        self.push = team_push(self.structure)
        parts = unpack(np.arange(parameter_size(self.robot) + 1), self.robot)  # where each part sits in θ
        self._at = {name: (int(v[0]), int(v[-1]) + 1) for name, v in parts.items() if len(v)}
        self.load(problem, smoothing)

    def load(self, problem: CaptureProblem, smoothing: float) -> None:
        """The team's numbers at ``problem`` (same structure), and the part of every robot's θ they fix."""
        s, robot = self.structure, self.robot
        nc, N = s.planned, s.horizon
        self.theta = np.append(parameter_vector(problem), smoothing)
        p = unpack(self.theta, s)
        self.held = p["held"].reshape(-1, 2)
        self.controlled = p["controlled"].reshape(-1, 2)
        self.step_limits = p["step_limits"]
        self.reach = p["min_separation"][0] + 2 * math.sqrt(2) * TRUST_REGION * self.step_limits
        steps = p["reference"].reshape(N, reference_size(nc))
        self.places = steps[:, : 2 * nc].reshape(N, nc, 2)
        reference = np.zeros((N, step_size(robot)))
        reference[:, 2:5] = steps[:, 2 * nc :]  # the attacker's reference, the weight
        values = {
            **p,
            "controlled": np.zeros(2),
            "held": (),
            "step_limits": np.zeros(1),
            "length": self.step_limits.mean(),
            "pushed": np.zeros(2),
            "reference": reference,
        }
        self.template = np.append(pack(values, robot), smoothing)

    def broadcast(self, plans: np.ndarray) -> Broadcast:
        """The round's :class:`Broadcast` under the planned defenders' ``plans`` (N, n_c, 2)."""
        N, n = self.structure.horizon, self.structure.defenders
        path, pushes, jacobians = self.push(self.theta, plans.reshape(-1))
        pushes = np.asarray(pushes).T.reshape(N, n, 2)
        jacobians = np.asarray(jacobians).T.reshape(N, n, 4)
        team = np.concatenate([plans, np.broadcast_to(self.held, (N, *self.held.shape))], axis=1)
        return Broadcast(team, np.asarray(path).T, pushes, jacobians, pushes.sum(axis=1), jacobians.sum(axis=1))

    def robot_inputs(self, i: int, broadcast: Broadcast) -> tuple[np.ndarray, np.ndarray, int]:
        """Robot ``i``'s θ and reference from the round's ``broadcast``, and how many team-mates within reach at
        some step have no slot."""
        N, K = self.robot.horizon, self.robot.fixed
        theta = self.template.copy()
        at = self._at
        theta[at["controlled"][0] : at["controlled"][1]] = self.controlled[i]
        theta[at["step_limits"][0]] = self.step_limits[i]
        pushed = broadcast.push - broadcast.pushes[:, i]  # the others' push, steps 0..N−1
        theta[at["pushed"][0] : at["pushed"][1]] = pushed[0]
        steps = theta[at["reference"][0] : at["reference"][1]].reshape(N, -1)
        steps[:, :2] = self.places[:, i]
        mine = broadcast.plans[:, i]
        offset = reference_size(1)
        if K:
            gap = broadcast.plans - mine[:, None]
            distance = np.einsum("kjc,kjc->kj", gap, gap)
            distance[:, i] = np.inf
            nearest = np.argsort(distance, axis=1, kind="stable")[:, :K]
            slots = steps[:, offset : offset + 2 * K].reshape(N, K, 2)
            np.add(mine[:, None], np.take_along_axis(broadcast.plans, nearest[:, :, None], axis=1), out=slots)
            slots *= 0.5
            unseen = int(max(0, (distance <= self.reach[i] ** 2).sum(axis=1).max() - K))
        else:
            unseen = 0
        offset += 2 * K  # step k's team terms, k = 1..N−1
        steps[:-1, offset : offset + 2] = pushed[1:]
        steps[:-1, offset + 2 : offset + 6] = broadcast.jacobian[1:] - broadcast.jacobians[1:, i]
        steps[:-1, offset + 6 : offset + 8] = broadcast.path[1:]
        return theta, mine.reshape(-1), unseen

"""``distributed``: every defender plans itself, one small stage QP per robot, as in the paper's Fig. 2.

Robot i's QP is ``rti``'s (:mod:`formulations.rti`) for a structure of one robot
(:attr:`~mpc_hunt.capture.structure.Structure.robot`): the state (p_a, p_di), 4
numbers, and its own step, 2, at each stage, whatever the team's size. What the
others do enters through the round's broadcast (:mod:`formulations.team_push`):

- the attacker's response, linearised along the team's latest plans: its path
  ā_k under them and the others' push on it to first order, so that robot i's
  QP is the team's ``rti`` QP with the others' positions held at their plans;
- the others' plans, fixed: a separation row to the midpoint between its plan
  and each of its ``NEIGHBOURS`` nearest team-mates' at each step,
  |p_di − m_ij| ≥ d_min / 2 (two robots that keep theirs stay d_min apart even
  when both move in the same round; so a row its reference breaks is relaxed to
  the reference's value, never to where the robot stands, :mod:`formulations.rti`).
  A row to a team-mate farther than
  d_min + 2ρ at the reference (ρ = the trust region's diagonal, 2√2 r_d) can
  never bind, as the robot stays within ρ of its reference; those nearer than
  that beyond the slots are counted (``unseen_neighbours``), not modelled.

Its objective is the team's ``enclose`` objective with the others held: its own
places, the attacker's reference and the arena's edge, its own smoothness, at
the team's scale (the mean step r̄_d).

A control step makes ``rounds`` rounds. ``jacobi``: every robot solves from the
same broadcast, so the robots run in parallel and a round costs one robot's QP;
``gauss-seidel``: one after another, each from a broadcast with the plans of
those before it (one broadcast per robot). A robot whose QP fails keeps its
reference for the round, and the step reports that QP's status.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable

import numpy as np

from formulations.base import Formulation
from formulations.capture_model import pack, parameter_size, parameter_vector, reference_size, step_size, unpack
from formulations.qp import TRUST_REGION
from formulations.rti import RTIFormulation, linearised_stages
from formulations.team_push import team_push
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.solution import Solution, Status
from mpc_hunt.capture.structure import Structure

NEIGHBOURS = 8      # slots: 7 team-mates d_min apart fit within d_min + 2ρ of a robot at the paper's numbers
SCHEMES = ("jacobi", "gauss-seidel")
MAX_ROUNDS = 100


def robot_structure(team: Structure) -> Structure:
    """The structure of one robot's QP in a team of structure ``team``."""
    return Structure(1, min(team.defenders - 1, NEIGHBOURS), team.obstacles, team.horizon, team.objective, robot=True)


@dataclass
class RobotProblem:
    """One robot's step inputs: what :class:`~mpc_hunt.solving.loop.CaptureLoop` is built from and loads."""

    structure: Structure
    theta: np.ndarray
    reference: np.ndarray
    controlled: np.ndarray = field(default_factory=lambda: np.ones(1, dtype=bool))

    @property
    def horizon(self) -> int:
        return self.structure.horizon


class RobotStep(RTIFormulation):
    """``rti`` for one robot's structure, its inputs handed over whole (a :class:`RobotProblem`)."""

    def step_inputs(self, problem: RobotProblem, warm_plan=None) -> tuple[np.ndarray, np.ndarray]:
        return problem.theta, problem.reference


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
        parts = unpack(np.arange(parameter_size(self.robot) + 1), self.robot)     # where each part sits in θ
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
        self.places = steps[:, :2 * nc].reshape(N, nc, 2)
        reference = np.zeros((N, step_size(robot)))
        reference[:, 2:5] = steps[:, 2 * nc:]                            # the attacker's reference, the weight
        values = {**p, "controlled": np.zeros(2), "held": (), "step_limits": np.zeros(1),
                  "length": self.step_limits.mean(), "pushed": np.zeros(2), "reference": reference}
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
        theta[at["controlled"][0]:at["controlled"][1]] = self.controlled[i]
        theta[at["step_limits"][0]] = self.step_limits[i]
        pushed = broadcast.push - broadcast.pushes[:, i]                 # the others' push, steps 0..N−1
        theta[at["pushed"][0]:at["pushed"][1]] = pushed[0]
        steps = theta[at["reference"][0]:at["reference"][1]].reshape(N, -1)
        steps[:, :2] = self.places[:, i]
        mine = broadcast.plans[:, i]
        offset = reference_size(1)
        if K:
            gap = broadcast.plans - mine[:, None]
            distance = np.einsum("kjc,kjc->kj", gap, gap)
            distance[:, i] = np.inf
            nearest = np.argsort(distance, axis=1, kind="stable")[:, :K]
            slots = steps[:, offset:offset + 2 * K].reshape(N, K, 2)
            np.add(mine[:, None], np.take_along_axis(broadcast.plans, nearest[:, :, None], axis=1), out=slots)
            slots *= 0.5
            unseen = int(max(0, (distance <= self.reach[i] ** 2).sum(axis=1).max() - K))
        else:
            unseen = 0
        offset += 2 * K                                                  # step k's team terms, k = 1..N−1
        steps[:-1, offset:offset + 2] = pushed[1:]
        steps[:-1, offset + 2:offset + 6] = broadcast.jacobian[1:] - broadcast.jacobians[1:, i]
        steps[:-1, offset + 6:offset + 8] = broadcast.path[1:]
        return theta, mine.reshape(-1), unseen


@dataclass
class Rounds:
    """What a step's rounds gave: the team's plans, the first failed QP's status and message, and counts."""

    plans: np.ndarray
    status: Status = Status.OPTIMAL
    message: str = ""
    iterations: int = 0
    qps: int = 0
    robot_times: list = field(default_factory=list)      # s, each robot QP's inputs and solve, in order
    unseen_neighbours: int = 0

    def extras(self, rounds: int) -> dict:
        times = np.array(self.robot_times)
        return {"qps": self.qps, "rounds": rounds, "robot_time_max": float(times.max()) if times.size else 0.0,
                "unseen_neighbours": self.unseen_neighbours}


# (robot, θ, reference) → (status, plan (N·2) or None, iterations, message)
SolveRobot = Callable[[int, np.ndarray, np.ndarray], tuple]


class DistributedFormulation(Formulation):
    """One ``rti`` QP per robot, ``rounds`` rounds a step by ``scheme`` (module docstring)."""

    name = "distributed"
    kind = "ocp-qp"
    default_backend = "hpipm"
    exact = RTIFormulation.exact
    smoothing = RTIFormulation.smoothing
    per_robot = True
    objectives = ("enclose",)     # the paper's objective plans only defenders within R_agg: nothing to distribute

    def __init__(self, rounds: int = 1, scheme: str = "jacobi"):
        if isinstance(rounds, bool) or not isinstance(rounds, int) or not 1 <= rounds <= MAX_ROUNDS:
            raise ValueError(f"rounds: a whole number from 1 to {MAX_ROUNDS}, got {rounds!r}")
        if scheme not in SCHEMES:
            raise ValueError(f"scheme: one of {', '.join(SCHEMES)}, got {scheme!r}")
        self.rounds, self.scheme = rounds, scheme

    @cached_property
    def robot_step(self) -> RobotStep:
        """One robot's step, as the control loop and the C export run it."""
        return RobotStep()

    @property
    def iteration(self):
        return self.robot_step.iteration

    def prepare(self, structure: Structure) -> None:
        linearised_stages(robot_structure(structure))
        team_push(structure)

    def team(self, problem: CaptureProblem) -> Team:
        return Team(problem, self.smoothing)

    def robot_problem(self, team: Team, theta: np.ndarray, reference: np.ndarray) -> RobotProblem:
        """One robot's step inputs, for its control loop."""
        return RobotProblem(team.robot, theta, reference)

    def run(self, team: Team, plans: np.ndarray, solve_robot: SolveRobot) -> Rounds:
        """The step's rounds from the team's reference ``plans`` (N, n_c, 2), each robot's QP by ``solve_robot``."""
        out = Rounds(np.array(plans, dtype=float))
        for _ in range(self.rounds):
            broadcast = team.broadcast(out.plans)
            new = out.plans.copy()
            for i in range(team.structure.planned):
                t0 = time.perf_counter()
                if self.scheme == "gauss-seidel" and i:
                    broadcast = team.broadcast(new)
                theta, reference, unseen = team.robot_inputs(i, broadcast)
                status, plan, iterations, message = solve_robot(i, theta, reference)
                out.robot_times.append(time.perf_counter() - t0)
                out.qps += 1
                out.iterations += iterations
                out.unseen_neighbours = max(out.unseen_neighbours, unseen)
                if status.usable:
                    new[:, i] = np.reshape(plan, (-1, 2))
                elif out.status.usable:
                    out.status, out.message = status, f"robot {i + 1}: {message or status.value}"
            out.plans = new
        return out

    def solve(self, problem, backend, warm_plan, duals) -> Solution:
        team = self.team(problem)
        start = problem.x_from_plan(problem.held_plan() if warm_plan is None else warm_plan)
        times = {"solver_time": 0.0, "setup_time": 0.0}

        def solve_robot(i, theta, reference):
            result = backend.solve(self.robot_step.stage_data(team.robot, (theta, reference)))
            times["solver_time"] += result.solver_time
            times["setup_time"] += result.setup_time
            return result.status, result.x, result.iterations, result.message

        out = self.run(team, start.reshape(problem.horizon, -1, 2), solve_robot)
        x = out.plans.reshape(-1)
        return Solution(status=out.status, message=out.message, x=x, plan=problem.plan_from_x(x),
                        iterations=out.iterations, extras=out.extras(self.rounds), **times)

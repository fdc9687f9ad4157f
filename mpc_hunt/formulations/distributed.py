"""``distributed``: every defender plans itself, one small stage QP per robot, as in the paper's Fig. 2.

Robot i's QP is ``rti``'s (:mod:`mpc_hunt.formulations.rti`) for a structure of one robot
(:attr:`~mpc_hunt.capture.structure.Structure.robot`): the state (p_a, p_di), 4
numbers, and its own step, 2, at each stage, whatever the team's size. What the
others do enters through the round's broadcast (:mod:`mpc_hunt.formulations.team_push`):

- the attacker's response, linearised along the team's latest plans: its path
  ā_k under them and the others' push on it to first order, so that robot i's
  QP is the team's ``rti`` QP with the others' positions held at their plans;
- the others' plans, fixed: a separation row to the midpoint between its plan
  and each of its ``NEIGHBOURS`` nearest team-mates' at each step,
  |p_di − m_ij| ≥ d_min / 2 (two robots that keep theirs stay d_min apart even
  when both move in the same round; so a row its reference breaks is relaxed to
  the reference's value, never to where the robot stands, :mod:`mpc_hunt.formulations.rti`).
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

import time
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable

import numpy as np

from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.solution import Solution, Status
from mpc_hunt.capture.structure import Structure
from mpc_hunt.formulations.base import Formulation
from mpc_hunt.formulations.rti import RTIFormulation
from mpc_hunt.formulations.team import Team, robot_structure
from mpc_hunt.formulations.team_push import team_push

SCHEMES = ("jacobi", "gauss-seidel")
MAX_ROUNDS = 100


@dataclass
class RobotProblem:
    """One robot's step inputs: what :class:`~mpc_hunt.solving.step.CaptureStep` is built from and loads."""

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

    def write_inputs(self, problem: RobotProblem, warm_plan, theta: np.ndarray, reference: np.ndarray) -> None:
        theta[:] = problem.theta
        reference[:] = problem.reference


@dataclass
class Rounds:
    """What a step's rounds gave: the team's plans, the first failed QP's status and message, and counts."""

    plans: np.ndarray
    status: Status = Status.OPTIMAL
    message: str = ""
    iterations: int = 0
    qps: int = 0
    failed: int = 0  # robot QPs that failed (their robots kept their reference)
    robot_times: list = field(default_factory=list)  # s, each robot QP's inputs and solve, in order
    unseen_neighbours: int = 0

    def extras(self, rounds: int) -> dict:
        times = np.array(self.robot_times)
        return {
            "qps": self.qps,
            "rounds": rounds,
            "failed_robot_qps": self.failed,
            "robot_time_max": float(times.max()) if times.size else 0.0,
            "unseen_neighbours": self.unseen_neighbours,
        }


# (robot, θ, reference) → (status, plan (N·2) or None, iterations, message)
SolveRobot = Callable[[int, np.ndarray, np.ndarray], tuple]


class DistributedFormulation(Formulation):
    """One ``rti`` QP per robot, ``rounds`` rounds a step by ``scheme`` (module docstring)."""

    name = "distributed"
    kind = "ocp-qp"
    # A robot's QP condensed to its 2N controls and solved by DAQP from its last active set: 3x faster than HPIPM
    # on the stage form at the same plans (studies/team_size).
    default_backend = "daqp-condensed"
    smoothing = RTIFormulation.smoothing
    per_robot = True
    objectives = ("enclose",)  # the paper's objective plans only defenders within R_agg: nothing to distribute

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
        self.robot_step.prepare(robot_structure(structure))
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
                    continue
                out.failed += 1
                if out.status.usable:
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
        return Solution(
            status=out.status,
            message=out.message,
            x=x,
            plan=problem.plan_from_x(x),
            iterations=out.iterations,
            extras=out.extras(self.rounds),
            solver_time=times["solver_time"],
            setup_time=times["setup_time"],
        )

"""The distributed capture step a control loop calls: one :class:`~mpc_hunt.solving.step.CaptureStep` per robot.

A formulation that plans robot by robot (``distributed``) makes one small stage
QP per robot, all of one structure (one robot, its neighbour slots), which the
backend closes into one Function, set up once. ``TeamStep`` holds a step per
robot, each with its own arrays, and runs the formulation's rounds on them:
each round broadcasts the team's plans (what the UAV, or every robot, computes),
then each robot writes its inputs into its step's arrays and steps. On the
robots, each runs :meth:`robot_step` for itself on its own board; here they run
one after another, and each robot's time is kept (``robot_times``), and the
rest of the step's (``broadcast_time``): the team's step, the robots in
parallel, is the broadcast plus the slowest robot. The plans each step starts
from are :class:`~mpc_hunt.solving.mpc.CaptureMPC`'s, whose ``loop_step``
drives it as it drives a centralised step.

    mpc = CaptureMPC("distributed", "hpipm-codegen")
    for each control step:
        status = mpc.loop_step(problem)   # the state and the plans to start from loaded, the rounds run
"""

from __future__ import annotations

import time

import numpy as np

from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.solution import Status
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.solving.step import CaptureStep


class TeamStep:
    """The rounds of a robot-by-robot formulation on one :class:`CaptureStep` per robot, for one team structure."""

    def __init__(self, problem: CaptureProblem, formulation, backend):
        self.formulation = formulation
        self.structure = problem.structure
        self.team = formulation.team(problem)
        self.plan = problem.x_from_plan(problem.held_plan()).reshape(problem.horizon, -1, 2)
        broadcast = self.team.broadcast(self.plan)
        self.robots = []
        for i in range(self.structure.planned):
            theta, reference, _ = self.team.robot_inputs(i, broadcast)
            self.robots.append(
                CaptureStep(formulation.robot_problem(self.team, theta, reference), formulation.robot_step, backend)
            )
        self.step_function = self.robots[0].step_function
        self.objective = np.full(1, np.nan)  # no one objective: each robot minimises its own
        self.iterations = self.qps = 0
        self.message = ""
        self.robot_times: list[float] = []
        self.broadcast_time = 0.0  # the last step's time outside the robots' QPs (s)
        self.evaluation_time = 0.0  # s of the last step inside the robots' Function evaluations
        self.unseen_neighbours = 0
        self.extras: dict = {}

    @property
    def certificate(self) -> np.ndarray:
        """The worst of the robots' last QPs' certificates (primal residual, dual residual, duality gap)."""
        return np.max([robot.certificate for robot in self.robots], axis=0)

    @property
    def setup_time(self) -> float:
        """Seconds of the last step its robots' steps spent rebuilding their Function for a new cap (a set-up)."""
        return sum(robot.setup_time for robot in self.robots)

    def load(self, problem: CaptureProblem, warm_plan: np.ndarray | None = None) -> None:
        """The team's numbers at ``problem``, and the plans to start from (``warm_plan``, else every one held)."""
        if problem.structure != self.structure:
            raise MpcHuntError(
                f"problem: structure {problem.structure}, this step was built for {self.structure}; "
                "build one step per structure"
            )
        self.team.load(problem, self.formulation.smoothing)
        start = problem.held_plan() if warm_plan is None else warm_plan
        self.plan = problem.x_from_plan(start).reshape(problem.horizon, -1, 2)

    def robot(self, i: int) -> CaptureStep:
        """Robot ``i``'s step with its inputs written from the broadcast of ``plan`` (what a robot steps, or
        the C export writes)."""
        theta, reference, _ = self.team.robot_inputs(i, self.team.broadcast(self.plan))
        robot = self.robots[i]
        robot.theta[:] = theta
        robot.reference.reshape(-1)[:] = reference
        return robot

    def robot_step(self, i: int, theta: np.ndarray, reference: np.ndarray) -> tuple:
        """Robot ``i``'s QP from its inputs, on its step: (status, plan, iterations, message)."""
        robot = self.robots[i]
        robot.theta[:] = theta
        robot.reference.reshape(-1)[:] = reference
        status = robot.step()
        self.evaluation_time += robot.evaluation_time
        return status, robot.plan.reshape(-1), robot.iterations, robot.message

    def step(self) -> Status:
        """The formulation's rounds from ``plan``; the team's new plans go into ``plan``."""
        start, self.evaluation_time = time.perf_counter(), 0.0
        out = self.formulation.run(self.team, self.plan, self.robot_step)
        self.broadcast_time = time.perf_counter() - start - sum(out.robot_times)
        self.plan = out.plans
        self.iterations, self.qps, self.message = out.iterations, out.qps, out.message
        self.robot_times, self.unseen_neighbours = out.robot_times, out.unseen_neighbours
        self.extras = out.extras(self.formulation.rounds)
        return out.status

"""The capture step a control loop calls: built once for a structure, then called once per control step.

A benchmark wants a :class:`~mpc_hunt.capture.solution.Solution` (posed problem,
scored plan, times); a control loop wants the plan. ``CaptureStep``
holds the step's inputs and outputs in arrays allocated once (``theta``, with
named views ``parts``; ``reference``; ``plan``) and evaluates the backend's one
step Function through CasADi's buffers, which read and write those arrays in
place: the caller writes the state into ``parts``, calls :meth:`step`, reads
``plan``. No evaluator runs; nothing but the status is returned.

It runs the stage-form formulations (kind ``ocp-qp``: ``rti``, one QP a step;
``stage-sqp``, that QP repeated at its own plan until no position moves by more
than the formulation's tolerance) on the backends that close them into one
Function (``hpipm``, ``hpipm-codegen``). :class:`~mpc_hunt.solving.solver.CaptureSolver`
builds one per structure for such a pair and solves on it; its plans are the
formulation's own (``CaptureSolver(..., loop=False)``) to the last bit from the
same inputs (a test holds it): no duals are handed over, which HPIPM does not read.
The step keeps no memory between calls beyond its arrays: the reference each step
starts from (the plan applied last step, shifted one step) and the fallback are
:class:`~mpc_hunt.solving.mpc.CaptureMPC`'s, whose ``loop_step`` drives it.

    mpc = CaptureMPC("rti", "hpipm-codegen")
    for each control step:
        status = mpc.loop_step(problem)   # the problem and its start written in, one step; mpc.plan applied
"""

from __future__ import annotations

import math
import time

import numpy as np

from mpc_hunt.capture.iteration import another_fits
from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.solution import Status
from mpc_hunt.errors import MpcHuntError


class CaptureStep:
    """One stage-form formulation × backend step for one structure, on arrays allocated once.

    ``problem`` fixes the structure (controlled and held defenders, obstacles,
    horizon, objective) and the first inputs; ``formulation`` and ``backend`` are
    the instances a :class:`~mpc_hunt.solving.solver.CaptureSolver` holds (its
    :meth:`~mpc_hunt.solving.solver.CaptureSolver.step_for` builds one).
    """

    def __init__(self, problem: CaptureProblem, formulation, backend):
        self.formulation, self.backend = formulation, backend
        self.structure = problem.structure
        self.step_function = self.backend.prepared(self.formulation.stage_data(self.structure))[0]  # its step
        theta, reference = self.formulation.step_inputs(problem)
        nc, horizon = int(problem.controlled.sum()), problem.horizon
        self.theta = np.array(theta, dtype=float)
        self.parts = self.formulation.parameter_parts(self.theta, self.structure)  # views: writes go into θ
        self.reference = np.array(reference, dtype=float).reshape(horizon, nc, 2)
        self._reference = self.reference.reshape(-1)  # the same numbers, flat (a view)
        self.plan = self.reference.copy()  # until a step: the reference (every defender held)
        self.objective = np.zeros(1)  # the model's objective at the plan
        self.iterations = 0  # the solver's iterations in the last step (every QP's)
        self.qps = 0  # QPs in the last step
        self.message = ""  # why the last step failed ("" when it did not)
        self._previous = np.empty_like(self.plan)  # the last usable plan of the step under way
        self._move = np.empty_like(self.plan)  # |plan − reference|, so a step allocates nothing
        self._stepped = False  # whether a step has run (the first, slower, is not paced)
        self.certificate = np.full(3, np.nan)  # the last QP's primal and dual residuals and duality gap
        self.setup_time = 0.0  # s of the last step spent rebuilding its Function for a new cap (a set-up)
        self.evaluation_time = 0.0  # s of the last step inside the Function's evaluations (its compiled work)
        self._bind()

    def _bind(self) -> None:
        """Evaluate the backend's loop Function of the step through buffers on the arrays (again once rebuilt)."""
        self._function = self.backend.loop_function(self.step_function)
        self._buffer, self._evaluate = self._function.buffer()
        self._buffer.set_arg(0, self.theta.data)
        self._buffer.set_arg(1, self._reference.data)
        self._buffer.set_res(0, self.plan.reshape(-1).data)
        self._buffer.set_res(1, self.objective.data)
        if self.backend.LOOP_CERTIFICATE:
            self._buffer.set_res(5, self.certificate.data)

    @property
    def extras(self) -> dict:
        """What a solution reports of the last step beyond the plan."""
        return {"qps": self.qps}

    def load(self, problem: CaptureProblem, warm_plan: np.ndarray | None = None) -> None:
        """Write ``problem``'s inputs into the arrays (the reference from ``warm_plan``, else every defender held)."""
        if problem.structure != self.structure:
            raise MpcHuntError(
                f"problem: structure {problem.structure}, this step was built for {self.structure}; "
                "build one step per structure"
            )
        self.formulation.write_inputs(problem, warm_plan, self.theta, self._reference)

    def step(self) -> Status:
        """Solve from the arrays; the plan goes into ``plan``. A failed QP leaves in ``plan`` the last usable plan
        of this step (the reference it started from, if none) and returns its status. A step that ran past the
        backend's time limit returns ``time_limit`` (its plan kept); no further QP is started once what is left of
        the limit would not fit one (:func:`~mpc_hunt.capture.iteration.another_fits`), nor once it would not fit
        the longest the next QP may take, where its cap is fixed (:meth:`longest_qp` of the backend)."""
        t0, cpu = time.perf_counter(), time.thread_time()
        self.setup_time = self.evaluation_time = 0.0
        with self.backend.step_within(t0):
            status = self._step()
        elapsed = time.perf_counter() - t0 - self.setup_time
        if self._stepped and not self.setup_time:
            self.backend.record_pace(time.thread_time() - cpu, self.iterations)
        self._stepped = True
        limit = self.backend.time_limit
        if limit is not None and elapsed > limit and status.usable:
            self.message = f"after {elapsed:.3g} s: past the {limit:g} s limit"
            return Status.TIME_LIMIT
        return status

    def _step(self) -> Status:
        iteration = self.formulation.iteration
        self.iterations = 0
        np.copyto(self._previous, self.reference)
        self.message = ""
        start = time.perf_counter()
        for count in range(iteration.max_qps):
            left = self.backend.time_left()
            longest = self.backend.longest_qp(self.step_function) if count else None
            if not another_fits(left, time.perf_counter() - start, count) or (
                longest is not None and left is not None and longest > left
            ):
                np.copyto(self.plan, self._previous)
                return Status.TIME_LIMIT
            self.qps = count + 1
            rebuilt = self.backend.loop_prepare(self.step_function)
            if rebuilt:  # a set-up: not the step's time
                self.setup_time += rebuilt
                self.backend.set_up_within_step(rebuilt)
                start += rebuilt
            if self.backend.loop_function(self.step_function) is not self._function:  # rebuilt, here or by a
                self._bind()  # step sharing it (a team's robots)
            evaluation = time.perf_counter()
            try:
                self._evaluate()
            except RuntimeError as exc:  # CasADi refuses the QP (a NaN in it, say)
                self.message = str(exc).splitlines()[0]
                np.copyto(self.plan, self._previous)
                return Status.ERROR
            finally:
                self.evaluation_time += time.perf_counter() - evaluation
            status, iterations = self.backend.loop_status(self.step_function, self._buffer)
            self.iterations += iterations
            np.abs(np.subtract(self.plan, self.reference, out=self._move), out=self._move)
            move = self._move.max()  # NaN when the plan has one
            if not status.usable or not math.isfinite(move):
                status = status if not status.usable else Status.ERROR
                detail = self.backend.loop_message(self.step_function, self._buffer)
                self.message = f"QP {count + 1}: {status.value}" + (f" ({detail})" if detail else "")
                np.copyto(self.plan, self._previous)
                return status
            if iteration.settled(move):
                return status
            np.copyto(self._previous, self.plan)
            np.copyto(self.reference, self.plan)
        self.message = f"no convergence in {iteration.max_qps} QPs"
        return Status.ITERATION_LIMIT

"""``stage-sqp``: the ``rti`` step iterated to convergence (sequential QP in stage form).

Each iterate relinearises the multiple-shooting model at the previous QP's
plan, as ``sqp`` does with ``qp``'s condensed one, and stops by ``sqp``'s rule
(:class:`~mpc_hunt.capture.iteration.QPIteration`). Every QP is one call of the
backend's step, so a compiled step (``hpipm-codegen``) compiles the whole
iteration's work. The trust region of
each QP (|δp_d| ≤ 2 r_d round its reference) bounds every step.
"""

from __future__ import annotations

from mpc_hunt.capture.solution import Solution
from mpc_hunt.formulations.rti import RTIFormulation
from mpc_hunt.formulations.sqp import SQPFormulation, iterate


class StageSQPFormulation(RTIFormulation):
    name = "stage-sqp"
    iteration = SQPFormulation.iteration

    def solve(self, problem, backend, warm_plan, duals) -> Solution:
        def step(reference, duals):
            return RTIFormulation.solve(self, problem, backend, reference, duals)

        return iterate(
            step,
            problem.held_plan() if warm_plan is None else warm_plan,
            duals,
            self.iteration,
            backend.time_left,
        )

"""The control loop's step (``CaptureSolver.step_for``): the formulation's own plans to the bit, on arrays allocated once."""

from __future__ import annotations

import time

import numpy as np
import pytest

from conftest import ATTACKER, DEFENDERS, small_scenario
from mpc_hunt import CaptureProblem, CaptureSolver, Status, shift_plan
from mpc_hunt.errors import MpcHuntError

HORIZON = 3
PAIRS = [("rti", "hpipm"), ("rti", "hpipm-codegen"), ("stage-sqp", "hpipm"), ("stage-sqp", "hpipm-codegen")]


@pytest.fixture(scope="module", autouse=True)
def cache(tmp_path_factory):
    """One compiled step for the module's structure, built in a cache of its own."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("MPC_HUNT_CACHE", str(tmp_path_factory.mktemp("cache")))
        yield


def _closed_loop(formulation: str, backend: str, steps: int = 8):
    """(problem, warm plan, the formulation's own solution) along a short hunt: the defenders go to each plan's
    first step, the attacker drifts east."""
    scenario, solver = small_scenario(), CaptureSolver(formulation, backend, loop=False)
    attacker, defenders, warm = ATTACKER.copy(), DEFENDERS.copy(), None
    for _ in range(steps):
        problem = CaptureProblem.at_state(scenario, attacker, defenders, HORIZON)
        solution = solver.solve(problem, warm)
        yield problem, warm, solution
        assert solution.success, solution.message
        defenders, attacker, warm = solution.plan[0], attacker + np.array([0.02, 0.0]), shift_plan(solution.plan)


@pytest.mark.parametrize(("formulation", "backend"), PAIRS)
def test_the_loops_plans_are_the_solvers_to_the_bit(formulation, backend):
    loop = None
    for problem, warm, solution in _closed_loop(formulation, backend):
        loop = loop or CaptureSolver(formulation, backend).step_for(problem)
        loop.load(problem, warm)
        assert loop.step() is solution.status
        np.testing.assert_array_equal(loop.plan, solution.plan[:, problem.controlled])
        assert loop.iterations == solution.iterations
        assert loop.objective[0] == solution.formulation_objective


def test_before_any_step_the_plan_is_the_held_reference():
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON)
    loop = CaptureSolver("rti", "hpipm").step_for(problem)
    np.testing.assert_array_equal(loop.plan, np.broadcast_to(DEFENDERS, loop.plan.shape))
    assert loop.step() is Status.OPTIMAL


@pytest.mark.parametrize("backend", ["hpipm", "hpipm-codegen"])
def test_a_failed_step_reports_its_status_and_leaves_the_reference_as_the_plan(backend):
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON)
    loop = CaptureSolver("stage-sqp", backend).step_for(problem)
    loop.parts["attacker"][:] = np.nan
    status = loop.step()
    assert not status.usable and loop.message
    np.testing.assert_array_equal(loop.plan, np.broadcast_to(DEFENDERS, loop.plan.shape))
    loop.load(problem)                                   # the loop recovers with the next good state
    assert loop.step() is Status.OPTIMAL


def test_a_plan_with_a_nan_is_an_error_even_when_the_solver_reports_success(monkeypatch):
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON)
    loop = CaptureSolver("rti", "hpipm-codegen").step_for(problem)
    monkeypatch.setattr(loop.backend, "loop_status", lambda step, buffer: (Status.OPTIMAL, 1))
    loop.reference[0, 0] = np.nan                     # the plan is read back round the reference
    assert loop.step() is Status.ERROR and loop.message
    np.testing.assert_array_equal(loop.plan, loop.reference)          # the plan it started from


def test_only_stage_form_steps_and_one_structure_per_loop():
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON)
    with pytest.raises(MpcHuntError, match="formulation: .*rti, stage-sqp"):
        CaptureSolver("sqp", "daqp").step_for(problem)
    with pytest.raises(MpcHuntError, match="formulation: .*rti, stage-sqp"):
        CaptureSolver("sqp", "daqp", loop=True)
    loop = CaptureSolver("rti", "hpipm").step_for(problem)
    other = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON + 1)
    with pytest.raises(MpcHuntError, match="problem: structure .* one step per structure"):
        loop.load(other)


def _slowed(step, seconds: float):
    """``step``'s evaluations each made ``seconds`` longer (outside the compiled code, as a clock sees it)."""
    evaluate = step._evaluate

    def slow():
        time.sleep(seconds)
        evaluate()

    step._evaluate = slow
    return step


def test_a_step_times_its_evaluations_alone_every_qp_of_it_and_afresh_each_step():
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON)
    loop = _slowed(CaptureSolver("stage-sqp", "hpipm").step_for(problem), 0.1)     # beyond a QP's own time
    loop.load(problem)
    start = time.perf_counter()
    assert loop.step().usable
    wall = time.perf_counter() - start
    assert loop.qps >= 2 and loop.qps * 0.1 <= loop.evaluation_time <= wall        # every QP's, not the last one's
    loop.load(problem)
    loop.parts["attacker"][:] = np.nan                                              # fails at once
    assert not loop.step().usable
    assert loop.qps * 0.1 <= loop.evaluation_time < (loop.qps + 1) * 0.1           # this step's only


"""``CaptureSolver`` on control loops for the stage-form pairs: the formulation's own solutions, what it scores."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from conftest import ATTACKER, DEFENDERS, small_scenario
from mpc_hunt import CaptureProblem, CaptureSolver, HuntingStrategy, Status, shift_plan, simulate
from mpc_hunt.formulations.stage_sqp import StageSQPFormulation
from mpc_hunt.capture.iteration import QPIteration
from mpc_hunt.control.enclosure import Enclosure
from mpc_hunt.errors import MpcHuntError, SolverError

HORIZON = 3


def _problems(solver, steps: int = 6):
    """(problem, warm plan, solution) along a short hunt driven by ``solver``'s plans; the attacker drifts east."""
    scenario = small_scenario()
    attacker, defenders, warm = ATTACKER.copy(), DEFENDERS.copy(), None
    for _ in range(steps):
        problem = CaptureProblem.at_state(scenario, attacker, defenders, HORIZON)
        solution = solver.solve(problem, warm)
        yield problem, warm, solution
        defenders, attacker, warm = solution.plan[0], attacker + np.array([0.02, 0.0]), shift_plan(solution.plan)


@pytest.mark.parametrize("formulation", ["rti", "stage-sqp"])
def test_scored_it_returns_the_capture_solvers_solution(formulation):
    loop = CaptureSolver(formulation, "hpipm")
    for problem, warm, expected in _problems(CaptureSolver(formulation, "hpipm", loop=False)):
        got = loop.solve(problem, warm)
        assert got.status is expected.status and got.success
        np.testing.assert_array_equal(got.plan, expected.plan)
        assert (got.objective, got.violation) == (expected.objective, expected.violation)
        assert (got.iterations, got.formulation_objective) == (expected.iterations, expected.formulation_objective)
        assert got.warm_started == (warm is not None)
    assert len(loop._steps) == 1                       # one loop for the one structure, built once


def test_unscored_it_runs_no_evaluator():
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON)
    solution = CaptureSolver("rti", "hpipm", score=False).solve(problem)
    assert solution.success and solution.plan.shape == (HORIZON, 3, 2)
    assert solution.objective is None and solution.violation is None
    assert solution.setup_time > 0 and solution.solver_time > 0


def test_unscored_it_still_scores_a_failed_steps_plan_as_the_capture_solver_does(monkeypatch):
    monkeypatch.setattr(StageSQPFormulation, "iteration", QPIteration(2, StageSQPFormulation.iteration.tolerance))
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON)
    got = CaptureSolver("stage-sqp", "hpipm", score=False).solve(problem)
    expected = CaptureSolver("stage-sqp", "hpipm", loop=False).solve(problem)
    assert got.status is expected.status is Status.ITERATION_LIMIT
    np.testing.assert_array_equal(got.plan, expected.plan)
    assert got.violation == expected.violation and got.objective == expected.objective


def test_a_new_structure_gets_its_own_loop_and_a_nan_start_a_status():
    solver = CaptureSolver("rti", "hpipm", score=False)
    longer = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON + 1)
    assert solver.solve(longer).success
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON)
    broken = solver.solve(problem, np.full((HORIZON, 3, 2), np.nan))
    assert not broken.success and broken.message and broken.formulation_objective is None
    assert len(solver._steps) == 2
    assert solver.solve(problem).success


def test_unscored_the_capture_solver_scores_only_a_failed_solve_and_scoring_is_timed_apart(monkeypatch):
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON)
    quiet = CaptureSolver("sqp", "daqp", score=False).solve(problem)
    assert quiet.success and quiet.violation is None and quiet.score_time == 0.0
    scored = CaptureSolver("sqp", "daqp").solve(problem)
    assert scored.violation is not None and scored.score_time > 0
    np.testing.assert_array_equal(quiet.plan, scored.plan)
    monkeypatch.setattr(StageSQPFormulation, "iteration", QPIteration(2, StageSQPFormulation.iteration.tolerance))
    failed = CaptureSolver("stage-sqp", "hpipm", score=False, loop=False).solve(problem)
    assert failed.status is Status.ITERATION_LIMIT and failed.violation is not None and failed.score_time > 0


def test_the_solver_runs_a_loop_where_the_pair_closes_one():
    assert CaptureSolver("rti", "hpipm").on_steps and CaptureSolver("stage-sqp", "hpipm-codegen").on_steps
    assert not CaptureSolver("sqp", "daqp").on_steps and not CaptureSolver("nlp").on_steps
    assert not CaptureSolver("rti", "hpipm", loop=False).on_steps
    with pytest.raises(SolverError, match="time_limit: backend daqp-condensed takes none"):   # its step is one call
        CaptureSolver("distributed", "daqp-condensed", time_limit=0.05)
    with pytest.raises(MpcHuntError, match="formulation: .*rti, stage-sqp"):
        CaptureSolver("sqp", "daqp", loop=True)
    with pytest.raises(MpcHuntError, match="backend 'osqp' does not solve formulation 'rti'"):
        CaptureSolver("rti", "osqp")


def test_a_hunt_on_the_loop_is_the_hunt_on_the_capture_solver():
    scenario = small_scenario(obstacles=((11.0, 6.0, 0.4),))
    scenario = dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, time_limit=40.0))
    options = dict(reference=Enclosure, formulation="rti", backend="hpipm", horizon=5)
    looped, solved = HuntingStrategy(scenario, **options), HuntingStrategy(scenario, **options)
    solved.mpc.solver = CaptureSolver("rti", "hpipm", score=False, loop=False)
    assert looped.mpc.solver.on_steps
    a, b = simulate(scenario, looped), simulate(scenario, solved)
    assert len(a.solve_times) > 100
    np.testing.assert_array_equal(a.defenders, b.defenders)
    np.testing.assert_array_equal(a.solve_iterations, b.solve_iterations)


def test_the_step_a_solver_set_up_is_the_one_it_exports_and_its_loop_runs(tmp_path):
    """One set-up per structure, whichever path asks for it: solving on the loop, the formulation's own path, the
    control loop handed out and the C export share the backend's step; the export writes the held reference and
    the plan the step makes from it."""
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, HORIZON)
    solver = CaptureSolver("stage-sqp", "hpipm", score=False)
    solved = solver.solve(problem)
    files = solver.export(tmp_path / "board", problem)
    assert solver.step_for(problem) is solver.step_for(problem) and solver.backend.setups == 1
    own = CaptureSolver("stage-sqp", "hpipm", loop=False)
    own.backend = solver.backend
    assert own.solve(problem).success and solver.backend.setups == 1
    assert {f.name for f in files} >= {"capture_step.c", "mpc_hunt_step.h", "input.txt", "expected.txt"}
    numbers = np.loadtxt(tmp_path / "board" / "input.txt")
    np.testing.assert_array_equal(numbers[-solved.x.size:], problem.x_from_plan(problem.held_plan()))
    np.testing.assert_array_equal(np.loadtxt(tmp_path / "board" / "expected.txt"), solved.x)
    assert "#define MPC_HUNT_PLAN 18" in (tmp_path / "board" / "mpc_hunt_step.h").read_text()

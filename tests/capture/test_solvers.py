"""One conformance test for every formulation × backend, plus what each part promises."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import ATTACKER, DEFENDERS, problem_at, small_scenario
from mpc_hunt.formulations.capture_model import decision_point, parameter_vector
from mpc_hunt.formulations.qp import QPFormulation
from mpc_hunt import (CaptureMPC, CaptureProblem, CaptureSolver, SolverError, Status, UnknownNameError, evaluate, pairs,
                      shift_plan, solve)
from mpc_hunt.solving import registry

PAIRS = pairs(objective="paper")


@pytest.mark.parametrize("formulation,backend", PAIRS)
@pytest.mark.parametrize("horizon", [1, 3])
def test_conformance(scenario, formulation, backend, horizon):
    problem = problem_at(scenario, horizon)
    first = solve(problem, formulation, backend)
    assert first.status in (Status.OPTIMAL, Status.OPTIMAL_INACCURATE), first.message
    assert (first.formulation, first.backend) == (formulation, backend)
    assert first.plan.shape == (horizon, 3, 2)
    again = evaluate(problem, first.plan)
    assert first.objective == pytest.approx(again.objective, rel=1e-12)
    assert first.violation == again.violation
    for name in registry.formulation_class(formulation).exact:
        assert first.violation[name] <= 1e-6, (name, first.violation)
    assert first.formulation_objective is not None and np.isfinite(first.formulation_objective)
    assert first.solver_time > 0 and first.overhead_time >= 0 and first.iterations > 0
    second = solve(problem, formulation, backend)
    np.testing.assert_allclose(second.plan, first.plan, atol=1e-9)  # deterministic


def test_every_formulation_reaches_the_same_optimum_to_its_approximation(scenario):
    problem = problem_at(scenario, 2)
    nlp = solve(problem, "nlp").objective
    qp = [solve(problem, "qp", b).objective for b in registry.compatible_backends("qp")]
    assert max(qp) - min(qp) <= 1e-9 * abs(np.mean(qp))        # one QP, every backend: measured ≤ 1e-10
    sqp = solve(problem, "sqp", "clarabel").objective
    assert nlp - 1e-6 * abs(nlp) <= sqp <= min(qp) + 1e-9       # iterating helps; nothing beats the NLP


def test_held_defender_is_not_moved():
    scenario = small_scenario()
    defenders = DEFENDERS.copy()
    defenders[2] = [2.0, 11.0]  # outside R_agg: approaching, so held in the capture problem
    problem = CaptureProblem.at_state(scenario, ATTACKER, defenders, 2)
    assert problem.controlled.tolist() == [True, True, False]
    for formulation, backend in (("nlp", "ipopt"), ("qp", "osqp"), ("qp", "clarabel")):
        plan = solve(problem, formulation, backend).plan
        np.testing.assert_array_equal(plan[:, 2], np.repeat(defenders[2][None], 2, axis=0))


def test_unknown_names_list_the_available_ones(scenario):
    with pytest.raises(UnknownNameError, match="available: .*nlp"):
        CaptureSolver("lp")
    with pytest.raises(UnknownNameError, match="available: .*osqp"):
        CaptureSolver("qp", "gurobi")
    with pytest.raises(UnknownNameError, match="use one of: osqp, clarabel, cvxpy, daqp"):
        CaptureSolver("qp", "ipopt")


def test_a_failed_solve_is_a_status_and_an_exception_only_on_request(scenario):
    problem = problem_at(scenario, 2)
    capped = CaptureSolver("nlp", max_iter=1).solve(problem)
    assert capped.status is Status.ITERATION_LIMIT and not capped.success
    assert capped.objective is not None  # the last iterate is still scored
    with pytest.raises(SolverError, match="iteration_limit"):
        CaptureSolver("nlp", max_iter=1, raise_on_failure=True).solve(problem)


def _least_squares(problem, plan):
    """The evaluator's objective without Eq. 14's penalty: the terms the QP's Gauss–Newton model linearises."""
    terms = evaluate(problem, plan).terms
    return terms["force"] + terms["ring"] + terms["move"]


def test_qp_linearisation_matches_finite_differences_of_the_numpy_model(scenario):
    """The QP's objective gradient at its reference equals the evaluator's, by central differences."""
    problem = problem_at(scenario, 2)
    reference = problem.held_plan() + 0.01 * np.array([[1.0, 0.5], [-0.5, 1.0], [0.3, -0.8]])
    X = problem.x_from_plan(reference)
    data = QPFormulation().built(problem.structure).data(("t",), parameter_vector(problem), X)
    P = data.P.toarray()
    P = P + P.T - np.diag(np.diag(P))
    x = decision_point(problem, X)
    x[:len(X)] = 0.0  # the QP's variable is the step from the reference
    gradient = (P @ x + data.q)[:len(X)]
    # The QP's residual at the reference is the true least-squares part there (Eq. 14's penalty enters by rows).
    residual = data.J @ x + data.c
    assert float(residual @ residual) == pytest.approx(_least_squares(problem, reference), rel=1e-9)
    h = 1e-6
    fd = np.empty_like(X)
    for j in range(len(X)):
        step = np.zeros_like(X); step[j] = h
        up = reference.copy(); up[:, problem.controlled] = (X + step).reshape(2, 3, 2)
        down = reference.copy(); down[:, problem.controlled] = (X - step).reshape(2, 3, 2)
        fd[j] = (_least_squares(problem, up) - _least_squares(problem, down)) / (2 * h)
    np.testing.assert_allclose(gradient, fd, rtol=1e-4, atol=1e-6 * np.abs(fd).max())


def _closed_loop_iterations(formulation, backend, warm, steps=8):
    """Iterations along a short closed loop: a ``CaptureMPC``'s steps (warm: its plan shifted, its duals), or its
    solver's one-shot solves (cold)."""
    scenario = small_scenario()
    mpc = CaptureMPC(formulation, backend)
    attacker, defenders = ATTACKER.copy(), DEFENDERS.copy()
    total = 0
    for k in range(steps):
        problem = CaptureProblem.at_state(scenario, attacker, defenders, 4)
        solution = mpc.step(problem).solution if warm else mpc.solver.solve(problem)
        assert solution.success, solution.message
        assert solution.warm_started == (warm and k > 0)
        total += solution.iterations
        attacker = problem.attacker_step(attacker, defenders)
        defenders = solution.plan[0]
    assert mpc.solver.backend.setups == 1  # set up once; every later step only updated numbers
    return total


@pytest.mark.parametrize("formulation,backend", [("nlp", "ipopt"), ("sqp", "clarabel")])
def test_warm_start_cuts_iterations(formulation, backend):
    assert _closed_loop_iterations(formulation, backend, True) < _closed_loop_iterations(formulation, backend, False)


@pytest.mark.parametrize("backend", registry.compatible_backends("qp"))
def test_a_persistent_qp_backend_is_set_up_once_in_the_loop(backend):
    _closed_loop_iterations("qp", backend, True)


def test_set_up_time_is_counted_once_per_structure(scenario):
    solver = CaptureSolver("qp", "daqp")
    first = solver.solve(problem_at(scenario, 2))
    again = solver.solve(problem_at(scenario, 2), shift_plan(first.plan))
    assert first.setup_time > 0 and again.setup_time == 0


def test_the_qp_marks_its_implied_rows_and_daqp_leaves_them_out(scenario):
    """qp's s ≥ 0 rows are implied by Eq. 14's elastic rows: marked, kept by OSQP, left out by DAQP (an active-set
    method cycles on such dependent rows), whose multipliers there are then 0, with the same plan."""
    problem = problem_at(scenario, 3)
    lin = QPFormulation().built(problem.structure)
    data = lin.data(("qp", problem.structure), parameter_vector(problem), problem.x_from_plan(problem.held_plan()))
    rows = data.A.toarray()[data.implied]
    n_s = int(data.implied.sum())
    assert n_s == 3 * 3 and np.array_equal(rows[:, -n_s:], np.eye(n_s)) and not rows[:, :-n_s].any()
    assert np.all(data.l[data.implied] == 0) and np.all(np.isinf(data.u[data.implied]))
    daqp = registry.backend_class("daqp")().solve(data)
    clarabel = registry.backend_class("clarabel")().solve(data)
    assert daqp.status is Status.OPTIMAL and np.all(daqp.duals.y[data.implied] == 0)
    np.testing.assert_allclose(daqp.x[:-n_s - 3], clarabel.x[:-n_s - 3], atol=1e-7)
    assert daqp.certificate.within(1e-6)

"""The stage-structured formulations: same problem as the condensed ones, smooth model, one call per step."""

from __future__ import annotations


import casadi as ca
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from conftest import ATTACKER, DEFENDERS, problem_at
from mpc_hunt.formulations import field, ms_nlp, stage_model
from mpc_hunt import CaptureProblem, CaptureSolver, solve
from mpc_hunt.world.field import repulsion
from mpc_hunt.capture.plan import shift_plan
from strategies import FAST, angles, floats

R, ETA = 1.0, 1.0
widths = floats(min_value=1e-4, max_value=0.05)


def _smooth(r, w):
    v = ca.DM(np.asarray(r, dtype=float))
    return np.array(field.repulsion(v, R, ETA, w)).ravel()


@pytest.mark.parametrize("horizon", [1, 3])
def test_multiple_shooting_reaches_the_condensed_optimum(scenario, horizon):
    """Same problem, other layout: the evaluator's objective agrees to IPOPT's tolerance (measured: 1.2e-8,
    plans 7e-10 m). At "high" accuracy: by default IPOPT relaxes nlp's squared rows by 1e-8 m², which lets
    its plan step 6e-7 m beyond r_d, and Eq. 14's weight turns that into 1e-4 of the objective."""
    problem = problem_at(scenario, horizon)
    condensed = CaptureSolver("nlp", accuracy="high").solve(problem)
    staged = CaptureSolver("ms-nlp", accuracy="high").solve(problem)
    assert staged.success, staged.message
    assert staged.objective == pytest.approx(condensed.objective, rel=1e-7)
    np.testing.assert_allclose(staged.plan, condensed.plan, atol=1e-8)


@FAST
@given(length=floats(min_value=0.01, max_value=3.0), angle=angles, w=widths)
def test_smoothed_field_is_the_papers_away_from_the_kink(length, angle, w):
    if abs(length - R) < w:
        return
    r = length * np.array([np.cos(angle), np.sin(angle)])
    np.testing.assert_allclose(_smooth(r, w), repulsion(r, R, ETA), rtol=1e-12, atol=1e-15)


@FAST
@given(w=widths, side=st.sampled_from([-1.0, 1.0]), angle=angles)
def test_smoothed_field_is_c1_across_its_band_edges(w, side, angle):
    """Value and Jacobian of H meet from both sides of |r| = R ± w (and the ramp is C² there)."""
    direction = np.array([np.cos(angle), np.sin(angle)])
    r = ca.SX.sym("r", 2)
    value = field.repulsion(r, R, ETA, w)
    H = ca.Function("H", [r], [value, ca.jacobian(value, r)])
    edge, h = R + side * w, 1e-7 * w
    (v_in, J_in), (v_out, J_out) = [map(np.array, H((edge + s * h) * direction)) for s in (-1, 1)]
    np.testing.assert_allclose(v_in, v_out, atol=1e-5 * w)
    np.testing.assert_allclose(J_in, J_out, atol=1e-4)
    z = ca.SX.sym("z")
    ramp = ca.Function("ramp", [z], [ca.hessian(field.ramp(z, w), z)[0]])
    assert abs(float(ramp(side * w - h)) - float(ramp(side * w + h))) <= 1e-3 / w


def test_smoothing_takes_the_kink_out_of_the_field():
    """Without smoothing the Jacobian jumps at |r| = R (by 3η); with it, it is continuous."""
    r = ca.SX.sym("r", 2)
    jump = []
    for w in (0.0, stage_model.SMOOTHING):
        J = ca.Function("J", [r], [ca.jacobian(field.repulsion(r, R, ETA, w), r)])
        jump.append(np.abs(np.array(J([R - 1e-9, 0.0])) - np.array(J([R + 1e-9, 0.0]))).max())
    assert jump[0] == pytest.approx(3 * ETA, rel=1e-6) and jump[1] < 1e-5


@pytest.mark.parametrize("horizon", [1, 3])
def test_rti_step_is_the_qp_where_both_linearise_the_same_problem(scenario, horizon):
    """The conftest state keeps every distance off the smoothing band: rti's QP is qp's, in stage form."""
    problem = problem_at(scenario, horizon)
    condensed, staged = solve(problem, "qp", "clarabel"), solve(problem, "rti", "hpipm")
    assert staged.success, staged.message
    np.testing.assert_allclose(staged.plan, condensed.plan, atol=1e-7)
    assert staged.objective == pytest.approx(condensed.objective, rel=1e-8)


def _paper_problem(horizon: int) -> CaptureProblem:
    from mpc_hunt.bench.problem_set import builtin_problem_set
    problems = builtin_problem_set()
    return problems.problem(next(p for p in problems.tagged("default") if p.scenario == "paper-obstacles"), horizon)


def test_a_control_step_is_one_call_into_casadi(monkeypatch):
    """After set-up, the rti step (linearisation, QP, plan) is one CasADi Function call, whatever N."""
    problem = _paper_problem(10)
    solver = CaptureSolver("rti", "hpipm")
    first = solver.solve(problem)
    calls = []
    original = ca.Function.__call__
    monkeypatch.setattr(ca.Function, "__call__",
                        lambda self, *a, **k: calls.append(self.name()) or original(self, *a, **k))
    solver.formulation.solve(problem, solver.backend, shift_plan(first.plan), first.duals)
    assert calls == ["step"]


def test_rti_drives_a_capture_stage_without_failing(scenario):
    """Twenty consecutive closed-loop steps at N = 10, set up once, all solved, obstacle safety kept."""
    attacker, defenders = ATTACKER, DEFENDERS
    solver, plan = CaptureSolver("rti", "hpipm"), None
    for _ in range(20):
        problem = CaptureProblem.at_state(scenario, attacker, defenders, 10)
        solution = solver.solve(problem, None if plan is None else shift_plan(plan))
        assert solution.success, solution.message
        assert solution.violation["obstacle_safety"] <= 1e-6
        plan = solution.plan
        attacker, defenders = problem.attacker_step(attacker, defenders), plan[0]
    assert solver.backend.setups == 1


def test_ms_nlp_with_no_smoothing_is_the_papers_problem(scenario):
    """smoothing = 0 poses nlp's problem exactly: the field's kink included, also inside the default band."""
    for length in (R - 0.5 * stage_model.SMOOTHING, R + 0.5 * stage_model.SMOOTHING):
        r = np.array([length, 0.0])
        np.testing.assert_allclose(_smooth(r, 0.0), repulsion(r, R, ETA), rtol=1e-12, atol=1e-15)
        assert np.abs(_smooth(r, stage_model.SMOOTHING) - repulsion(r, R, ETA)).max() > 1e-6
    problem = problem_at(scenario, 2)
    solver = CaptureSolver("ms-nlp", accuracy="high")       # "high": see the test above
    solver.formulation.smoothing = 0.0
    paper = CaptureSolver("nlp", accuracy="high").solve(problem)
    assert solver.solve(problem).objective == pytest.approx(paper.objective, rel=1e-7)   # measured 1.3e-8
    assert isinstance(solver.formulation, ms_nlp.MSNLPFormulation)

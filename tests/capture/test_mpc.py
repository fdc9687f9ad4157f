"""``CaptureMPC``: the receding-horizon memory (warm plan, duals), the fallback order, the real-time step."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from conftest import ATTACKER, DEFENDERS, small_scenario
from mpc_hunt import CaptureMPC, CaptureProblem, Status, shift_plan
from mpc_hunt.capture.iteration import QPIteration
from mpc_hunt.control.posing import posed_problem
from mpc_hunt.formulations.sqp import SQPFormulation
from mpc_hunt.world.hunt_state import HuntState

HORIZON = 3
DRIFT = np.array([0.02, 0.0])


def _problem(attacker=ATTACKER, defenders=DEFENDERS, horizon: int = HORIZON, active=None) -> CaptureProblem:
    return CaptureProblem.at_state(small_scenario(), attacker, defenders, horizon, active=active)


def _spied(mpc: CaptureMPC) -> list:
    """Every (warm plan, duals) the MPC hands its solver, in order."""
    calls, solve = [], mpc.solver.solve
    mpc.solver.solve = lambda problem, warm_plan=None, duals=None: calls.append((warm_plan, duals)) or solve(
        problem, warm_plan, duals)
    return calls


def _broken(problem: CaptureProblem) -> CaptureProblem:
    """``problem`` with a NaN where the attacker is (a problem refuses one when made: set behind its back)."""
    object.__setattr__(problem, "attacker_position", np.array([np.nan, ATTACKER[1]]))
    return problem


def _iterations(monkeypatch, qps: int) -> None:
    """``sqp`` stops after ``qps`` QPs: at 2 its plan is 7.5e-6 m infeasible here, at 4 feasible to 1e-12."""
    monkeypatch.setattr(SQPFormulation, "iteration", QPIteration(qps, SQPFormulation.iteration.tolerance))


def test_the_warm_start_is_the_applied_plan_shifted_only_for_the_same_defenders():
    mpc = CaptureMPC("qp", "daqp")
    first = mpc.step(_problem())
    assert first.start is None and not first.solution.warm_started and first.fallback is None
    np.testing.assert_array_equal(mpc.plan, first.solution.plan)
    second = mpc.step(_problem(ATTACKER + DRIFT, first.plan[0]))
    np.testing.assert_array_equal(second.start, shift_plan(first.plan))
    assert second.solution.warm_started
    assert mpc.step(_problem(horizon=HORIZON + 1)).start is None                      # another structure
    mpc.step(_problem())
    assert mpc.step(_problem(active=np.array([True, True, False]))).start is None   # other defenders


def test_duals_are_handed_over_only_after_a_usable_solve_with_the_same_signature(monkeypatch):
    mpc = CaptureMPC("sqp", "daqp")
    calls = _spied(mpc)
    first = mpc.step(_problem())
    second = mpc.step(_problem(ATTACKER + DRIFT, first.plan[0]))
    assert calls[0] == (None, None)
    assert calls[1][1] is first.solution.duals and calls[1][1].y is not None
    _iterations(monkeypatch, 2)
    failed = mpc.step(_problem(ATTACKER + 2 * DRIFT, second.plan[0]))
    assert failed.fallback == "shifted plan" and calls[2][1] is second.solution.duals
    _iterations(monkeypatch, 30)
    after = mpc.step(_problem(ATTACKER + 3 * DRIFT, failed.plan[0]))
    assert after.solution.success and after.start is not None
    assert calls[3][0] is after.start and calls[3][1] is None                     # warm, but no duals
    mpc.step(_problem(horizon=HORIZON + 1))                                      # after a usable solve, but cold
    assert calls[4] == (None, None)


@pytest.mark.parametrize(("qps", "kind"), [(4, "last iterate"), (2, "held")])
def test_a_failed_first_step_applies_its_iterate_only_when_scored_feasible_else_holds(monkeypatch, qps, kind):
    _iterations(monkeypatch, qps)
    problem = _problem()
    step = CaptureMPC("sqp", "daqp", score=False).step(problem)
    assert step.solution.status is Status.ITERATION_LIMIT and step.fallback == kind
    expected = step.solution.plan if kind == "last iterate" else problem.held_plan()
    np.testing.assert_array_equal(step.plan, expected)


def test_each_fallback_gives_the_documented_plan_and_is_counted(monkeypatch):
    mpc = CaptureMPC("sqp", "daqp", score=False)
    first = mpc.step(_problem())
    _iterations(monkeypatch, 2)
    shifted = mpc.step(_problem(ATTACKER + DRIFT, first.plan[0]))      # infeasible iterate: the shifted plan
    assert shifted.fallback == "shifted plan" and shifted.solution.max_violation > 1e-6
    np.testing.assert_array_equal(shifted.plan, shift_plan(first.plan))
    _iterations(monkeypatch, 4)
    mpc.reset()                                                          # cold: 4 QPs do not converge
    iterate = mpc.step(_problem())
    assert iterate.fallback == "last iterate" and iterate.solution.status is Status.ITERATION_LIMIT
    np.testing.assert_array_equal(iterate.plan, iterate.solution.plan)
    held = mpc.step(_broken(_problem(horizon=HORIZON + 1)))               # a NaN, and no plan to shift
    assert held.fallback == "held" and not held.solution.status.usable
    np.testing.assert_array_equal(held.plan, np.repeat(DEFENDERS[None], HORIZON + 1, axis=0))
    assert mpc.fallbacks == Counter({"shifted plan": 1, "last iterate": 1, "held": 1})


def test_reset_forgets_the_plan_and_the_duals():
    mpc = CaptureMPC("qp", "daqp")
    calls = _spied(mpc)
    first = mpc.step(_problem())
    mpc.reset()
    assert mpc.plan is None
    assert mpc.step(_problem(ATTACKER + DRIFT, first.plan[0])).start is None and calls[1] == (None, None)


def test_a_follower_starts_from_the_leaders_plan_without_duals():
    leader, follower = CaptureMPC("qp", "daqp"), CaptureMPC("qp", "osqp")
    calls = _spied(follower)
    follower.step(_problem())
    first = leader.step(_problem())
    follower.follow(leader)
    step = follower.step(_problem(ATTACKER + DRIFT, first.plan[0]))
    np.testing.assert_array_equal(step.start, shift_plan(first.plan))
    assert calls[1][1] is None


@pytest.mark.parametrize(("formulation", "objective"), [("rti", "paper"), ("stage-sqp", "paper"),
                                                        ("distributed", "enclose")])
def test_the_real_time_step_applies_the_scored_steps_plans_to_the_bit(formulation, objective):
    """``loop_step`` (arrays, no evaluator) along ``step``'s closed loop on the formulation's own path: the same
    starts, the same plans; the centralised and the robot-by-robot step are the one object."""
    scored, looped = CaptureMPC(formulation, "hpipm", loop=False), CaptureMPC(formulation, "hpipm")
    attacker, defenders = ATTACKER.copy(), DEFENDERS.copy()
    for k in range(5):
        problem = posed_problem(small_scenario(), HuntState(k * 0.1, attacker, defenders), HORIZON, objective)
        expected = scored.step(problem)
        assert looped.loop_step(problem) is expected.solution.status and expected.fallback is None
        np.testing.assert_array_equal(looped.plan, expected.plan)
        attacker, defenders = attacker + DRIFT, expected.plan[0]
    assert not looped.fallbacks


def test_a_failed_real_time_step_holds_then_shifts_and_never_applies_its_iterate():
    mpc = CaptureMPC("rti", "hpipm")
    assert not mpc.loop_step(_broken(_problem())).usable
    np.testing.assert_array_equal(mpc.plan, _problem().held_plan())
    assert mpc.loop_step(_problem()).usable
    good = mpc.plan
    assert not mpc.loop_step(_broken(_problem())).usable
    np.testing.assert_array_equal(mpc.plan, shift_plan(good))
    assert mpc.fallbacks == Counter({"held": 1, "shifted plan": 1})


def test_a_usable_plan_beyond_the_tolerance_is_violating_and_the_fallback_is_applied():
    """One meaning of success: a usable, scored plan that breaks a hard constraint beyond the loop's tolerance is
    not applied (Eq. 14, elastic, never vetoes)."""
    from conftest import problem_at, small_scenario

    problem = problem_at(small_scenario(), 3)
    strict = CaptureMPC("qp", "clarabel", score=True, tolerance=-1.0)     # nothing is within a negative tolerance
    step = strict.step(problem)
    assert step.solution.success and step.fallback == "held" and strict.violating == 1
    assert np.array_equal(step.plan, problem.held_plan())
    usual = CaptureMPC("qp", "clarabel", score=True)
    applied = usual.step(problem)
    assert applied.fallback is None and usual.violating == 0 and np.array_equal(applied.plan, applied.solution.plan)
    unscored = CaptureMPC("qp", "clarabel", score=False, tolerance=-1.0)  # no violations known: the status decides
    assert unscored.step(problem).fallback is None and unscored.violating == 0

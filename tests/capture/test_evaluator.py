"""The evaluator on hand-made plans whose objective and violations are known."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import small_scenario
from mpc_hunt import CaptureProblem, CaptureWeights, evaluate
from mpc_hunt.capture.evaluator import TERM_NAMES, equal_distance_penalty
from mpc_hunt.world.field import nominal_intent


def _problem(defenders, controlled=(True, True, True), horizon=1, desired=(0.0, 0.0)):
    scenario = small_scenario(obstacles=((8.0, 8.0, 1.0),))
    return CaptureProblem(scenario, np.array([5.0, 5.0]), np.array(defenders, dtype=float),
                          np.array(controlled), np.array(desired), horizon)


def test_objective_of_a_plan_outside_the_field_is_the_nominal_error():
    # Defenders 2 m away: no force on the attacker, so u_a is its (capped) nominal velocity.
    defenders = [[5.0, 3.0], [7.0, 5.0], [3.0, 5.0]]
    p = _problem(defenders, horizon=2, desired=(0.01, 0.0))
    plan = p.held_plan()
    nominal = nominal_intent(np.array([0.2, -0.2]), 0.03)
    force = np.sum((np.array([0.01, 0.0]) - nominal) ** 2) / 0.03**2
    w = CaptureWeights()
    expected = 0.0
    for k in (1, 2):  # the attacker drifts at its nominal velocity: p_a,k = p_a,0 + k T v_nom
        d = np.linalg.norm(np.array([5.0, 5.0]) + k * 0.1 * nominal - np.array(defenders), axis=1)
        squared = d**2     # Eq. 14's L1 penalty at its minimiser q_k, the median squared distance
        expected += (w.force * force + w.ring * np.sum(((d - 0.25) / 0.5) ** 2)
                     + w.equal_distance * np.sum(np.abs(squared - np.median(squared))) / 0.5**2)
    result = evaluate(p, plan)
    np.testing.assert_allclose(result.attacker_path, [[5.0, 5.0] + 0.1 * nominal, [5.0, 5.0] + 0.2 * nominal])
    assert result.objective == pytest.approx(expected, rel=1e-12)
    for name in ("motion_limit", "obstacle_safety", "separation", "attacker_distance"):
        assert result.violation[name] == 0.0


def test_equal_distance_penalty_is_the_l1_gap_to_the_median():
    # Distances 0.3, 0.4, 0.5 m from the attacker: squares 0.09, 0.16, 0.25, median 0.16, gaps 0.07 + 0 + 0.09.
    assert equal_distance_penalty(np.array([0.09, 0.16, 0.25])) == pytest.approx(0.16, rel=1e-12)
    assert equal_distance_penalty(np.array([0.2, 0.2])) == 0.0
    # Any q between the two middle values minimises the sum; the median is one of them.
    assert equal_distance_penalty(np.array([0.1, 0.2, 0.3, 0.7])) == pytest.approx(0.7, rel=1e-12)


def test_terms_add_up_to_the_objective_and_the_penalty_counts_only_controlled_defenders():
    defenders = np.array([[5.0, 4.5], [5.6, 5.0], [3.0, 5.0]])
    p = _problem(defenders, controlled=(True, True, False), horizon=2)
    result = evaluate(p, p.held_plan())
    assert set(result.terms) == set(TERM_NAMES)
    assert result.objective == pytest.approx(sum(result.terms.values()), rel=1e-15)
    expected = 0.0
    for a in result.attacker_path:
        squared = np.sum((defenders[:2] - a) ** 2, axis=1)
        expected += 1e3 * abs(squared[0] - squared[1]) / 0.5**2
    assert result.terms["equal_distance"] == pytest.approx(expected, rel=1e-12)


def test_known_violations():
    defenders = np.array([[5.0, 4.5], [5.6, 5.0], [4.4, 5.0]])
    p = _problem(defenders)
    plan = defenders[None].copy()
    plan[0, 0] += [0.0, -0.1]          # moved 0.1 m, r_d = 0.08 * 0.1 = 0.008 m
    plan[0, 1] = [5.6, 4.95]           # 0.6 m → distance of defender 1 ≈ 0.602
    plan[0, 2] = [6.95, 8.0]           # 1.05 m from the centre of obstacle (8, 8), r = 1: 0.05 m short of R_safe
    v = evaluate(p, plan).violation
    assert v["motion_limit"] == pytest.approx(np.hypot(6.95 - 4.4, 8.0 - 5.0) - 0.008, rel=1e-9)
    dist_obstacle = np.linalg.norm(plan[0, 2] - [8.0, 8.0])
    assert v["obstacle_safety"] == pytest.approx(1.1 - dist_obstacle, rel=1e-9) == pytest.approx(0.05)
    a1 = evaluate(p, plan).attacker_path[0]
    d = np.linalg.norm(plan[0] - a1, axis=1)
    assert v["equal_distance"] == pytest.approx(d.max() - d.min(), rel=1e-12)


def test_separation_and_attacker_distance_violations():
    defenders = np.array([[5.0, 4.5], [5.1, 4.5], [5.0, 5.6]])
    p = _problem(defenders)
    path = evaluate(p, defenders[None]).attacker_path[0]
    plan = defenders[None].copy()
    plan[0, 2] = path + [0.0, 0.05]    # 0.05 m from the attacker; minimum 0.1 m
    v = evaluate(p, plan).violation
    assert v["separation"] == pytest.approx(0.2 - 0.1, rel=1e-9)
    assert v["attacker_distance"] == pytest.approx(0.1 - 0.05, rel=1e-6)


def test_held_defenders_count_in_separation_but_not_in_equal_distance():
    defenders = np.array([[5.0, 4.5], [5.5, 5.0], [5.0, 6.5]])
    p = _problem(defenders, controlled=(True, True, False))
    v = evaluate(p, p.held_plan()).violation
    a1 = evaluate(p, p.held_plan()).attacker_path[0]
    d = np.linalg.norm(defenders[:2] - a1, axis=1)
    assert v["equal_distance"] == pytest.approx(abs(d[0] - d[1]), rel=1e-9)


def test_plan_of_the_wrong_shape_is_refused():
    p = _problem([[5.0, 4.5], [5.5, 5.0], [4.5, 5.0]])
    with pytest.raises(ValueError, match="plan: expected shape"):
        evaluate(p, np.zeros((2, 3, 2)))

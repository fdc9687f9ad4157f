"""The benchmark's metrics on hand-made inputs: shifted geometric mean, success rule, gap, performance profile."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mpc_hunt.bench.compare import CompareRun, SolveRecord
from mpc_hunt.bench.compare_rows import best_known, score
from mpc_hunt.errors import BenchmarkError
from mpc_hunt.bench.metrics import is_success, performance_profile, relative_gap, shifted_geometric_mean
from mpc_hunt.bench.problem_set import ProblemSet

CLEAN = dict.fromkeys(("motion_limit", "equal_distance", "obstacle_safety", "separation", "attacker_distance"), 0.0)


def test_shifted_geometric_mean():
    # exp(mean(log(t + 0.01))) − 0.01 for 10 ms and 30 ms: sqrt(0.02 · 0.04) − 0.01.
    assert shifted_geometric_mean([0.01, 0.03]) == pytest.approx(np.sqrt(0.02 * 0.04) - 0.01, rel=1e-12)
    assert shifted_geometric_mean([0.0, 0.0]) == pytest.approx(0.0, abs=1e-15)
    assert shifted_geometric_mean([2.0, 2.0, 2.0], shift=1.0) == pytest.approx(2.0, rel=1e-12)
    # The shift damps a tiny outlier that would drag a plain geometric mean to zero.
    assert shifted_geometric_mean([1e-9, 0.1]) > 0.02
    for bad, name in (([], "empty"), ([0.1, -0.1], "non-negative"), ([np.inf], "finite")):
        with pytest.raises(BenchmarkError, match=name):
            shifted_geometric_mean(bad)


@pytest.mark.parametrize("family", ["motion_limit", "obstacle_safety", "separation", "attacker_distance"])
def test_success_needs_a_success_status_and_every_hard_violation_within_tolerance(family):
    assert is_success(True, CLEAN, 1e-6)
    assert not is_success(False, CLEAN, 1e-6)
    assert not is_success(True, None, 1e-6)
    assert not is_success(True, {**CLEAN, family: 2e-6}, 1e-6)
    assert is_success(True, {**CLEAN, family: 1e-6}, 1e-6)
    assert is_success(True, {**CLEAN, "equal_distance": 1.0}, 1e-6)    # Eq. 14 is elastic: reported, not a veto


def test_relative_gap():
    assert relative_gap(3.0, 2.0) == pytest.approx(0.5)
    assert relative_gap(2.0, 2.0) == 0.0
    assert relative_gap(1.5, 2.0) == pytest.approx(-0.25)        # a plan that breaks a constraint may beat the best
    assert relative_gap(0.0, 0.0) == 0.0 and math.isinf(relative_gap(1.0, 0.0))


def test_performance_profile():
    taus, rho = performance_profile({"a": [1.0, 2.0, np.inf], "b": [2.0, 1.0, 3.0]})
    # Ratios to the fastest: a = (1, 2, failed), b = (2, 1, 1).
    np.testing.assert_array_equal(taus, [1.0, 2.0])
    np.testing.assert_allclose(rho["a"], [1 / 3, 2 / 3])
    np.testing.assert_allclose(rho["b"], [2 / 3, 1.0])
    _, rho = performance_profile({"a": [np.inf], "b": [np.inf]})      # nobody solved it
    assert rho["a"].tolist() == [0.0] and rho["b"].tolist() == [0.0]
    with pytest.raises(BenchmarkError, match="not NaN"):
        performance_profile({"a": [np.nan]})


def _record(problem, objective, success=True, status="optimal", time=0.01, violation=None, pair=("qp", "osqp")):
    return SolveRecord(*pair, "cold", 1, problem, status, success, objective, violation or CLEAN, time, time / 2,
                       time / 2, 0.0, 0.0, 7, False)


def test_a_row_from_hand_made_records():
    records = [_record("p1", 2.0), _record("p2", 1.1, time=0.03),
               _record("p3", 0.5, success=False, violation={**CLEAN, "equal_distance": 3e-4}),
               _record("p4", None, success=False, status="error", time=0.05)]
    others = [_record("p1", 1.0, pair=("nlp", "ipopt")), _record("p2", 1.0, pair=("nlp", "ipopt")),
              _record("p3", 0.1, success=False, pair=("nlp", "ipopt"))]
    run = CompareRun(ProblemSet({}, ()), [("qp", "osqp"), ("nlp", "ipopt")], [1], ["cold"], "default", 0.1, 1,
                     records + others, {("p1", 1): 1.2, ("p3", 1): 0.25, ("p4", 1): None})
    # The best known: the lowest objective that passes the success rule, references included.
    best = best_known(run)
    assert best == {("p1", 1): 1.0, ("p2", 1): 1.0, ("p3", 1): 0.25}
    row = score(records, best, "default", time_limit=0.1)
    assert row["success_rate"] == 0.5
    assert row["solve_time_median_s"] == pytest.approx(0.02)
    # Failed solves count at the time limit in the shifted geometric mean, as qpbenchmark does.
    assert row["solve_time_shifted_geomean_s"] == pytest.approx(shifted_geometric_mean([0.01, 0.03, 0.1, 0.1]))
    # Gaps over the solves with a success status: 1.0, 0.1 and 1.0 (p3 against the reference 0.25).
    assert row["gap_solves"] == 3 and row["optimality_gap_median"] == pytest.approx(1.0)
    assert row["max_violation"] == row["max_violation_equal_distance"] == 3e-4
    assert row["statuses"] == "error 1, optimal 3" and row["iterations_median"] == 7

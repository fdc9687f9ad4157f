"""Certificates computed from the problem's data and the returned vectors: exact at a known solution, small for
every converged backend, large when a solver is stopped early."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import problem_at
from mpc_hunt import CaptureSolver, Status
from mpc_hunt.capture.certificate import Certificate, qp_certificate
from mpc_hunt.capture.data import QPData
from mpc_hunt.solving import registry

# min ½|x|² − 2 x₀  s.t.  x₀ ≤ 1 (active: y₀ = 1), −1 ≤ x₁ ≤ 1, x₀ + x₁ ≥ −5 (inactive): x* = (1, 0).
P = sp.csc_matrix(np.eye(2))
Q = np.array([-2.0, 0.0])
A = sp.csc_matrix(np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]))
L, U = np.array([-np.inf, -1.0, -5.0]), np.array([1.0, 1.0, np.inf])
X_STAR, Y_STAR = np.array([1.0, 0.0]), np.array([1.0, 0.0, 0.0])
KNOWN = QPData(("known",), P, Q, A, L, U, J=np.eye(2) / np.sqrt(2), c=np.zeros(2), lin=Q)
QP_BACKENDS = [b for b in registry.compatible_backends("qp") if registry.installed(b)]
ACHIEVED = 1e-6     # what every QP backend reaches on KNOWN at its default accuracy (measured: ≤ 4e-7), with margin


def test_the_certificate_of_the_known_solution_is_zero_and_moves_with_each_error():
    assert qp_certificate(P, Q, A, L, U, X_STAR, Y_STAR) == Certificate(0.0, 0.0, 0.0)
    off = qp_certificate(P, Q, A, L, U, X_STAR + np.array([0.01, 0.0]), Y_STAR)    # 0.01 past the bound x₀ ≤ 1
    assert off.primal_residual == pytest.approx(0.01) and off.dual_residual == pytest.approx(0.01)
    wrong = qp_certificate(P, Q, A, L, U, X_STAR, np.array([0.5, 0.0, 0.0]))       # half the multiplier
    assert wrong.primal_residual == 0 and wrong.dual_residual == pytest.approx(0.5)
    assert wrong.duality_gap == pytest.approx(0.5)     # x'Px + q'x + u₀y₀ = 1 − 2 + 0.5


@pytest.mark.parametrize("backend", QP_BACKENDS)
def test_every_qp_backend_certifies_the_known_solution(backend):
    solution = registry.backend_class(backend)().solve(KNOWN)
    assert solution.status is Status.OPTIMAL
    np.testing.assert_allclose(solution.x, X_STAR, atol=ACHIEVED)
    assert solution.certificate is not None and solution.certificate.within(ACHIEVED), solution.certificate


@pytest.mark.parametrize("formulation,backend,loose", [("qp", "osqp", 1e-3), ("qp", "daqp", 1e-3),
                                                       ("qp", "clarabel", 1e-3), ("rti", "hpipm", 1e-3),
                                                       ("nlp", "ipopt", 1e-3)])
def test_a_solver_stopped_early_says_so_in_its_certificate(scenario, formulation, backend, loose):
    problem = problem_at(scenario, 5)
    converged = CaptureSolver(formulation, backend).solve(problem)
    stopped = CaptureSolver(formulation, backend, max_iter=1).solve(problem)
    assert converged.status is Status.OPTIMAL and converged.certificate is not None
    assert stopped.status is Status.ITERATION_LIMIT and stopped.certificate is not None
    worst = max(stopped.certificate.primal_residual, stopped.certificate.dual_residual,
                stopped.certificate.duality_gap)
    assert worst > loose > 1e3 * max(converged.certificate.primal_residual, converged.certificate.dual_residual)


@pytest.mark.parametrize("formulation,backend", [("qp", "osqp"), ("rti", "hpipm"), ("nlp", "ipopt"),
                                                 ("socp", "clarabel"), ("qp", "cvxpy")])
def test_solve_reports_the_certificate_beside_the_true_violations(scenario, formulation, backend):
    report = CaptureSolver(formulation, backend).solve(problem_at(scenario, 3)).to_dict()
    assert set(report["certificate"]) == {"primal_residual", "dual_residual", "duality_gap", "kind"}
    assert report["certificate"]["kind"] == ("nlp" if backend == "ipopt" else "qp")
    assert set(report["violation"]) >= {"motion_limit", "obstacle_safety"}


matrices = st.integers(2, 6).flatmap(lambda n: st.tuples(
    st.just(n), st.integers(1, 6), st.integers(0, 2**32 - 1)))


@settings(max_examples=60, deadline=None)
@given(matrices)
def test_the_certificate_is_the_kkt_residuals_computed_densely(sizes):
    n, m, seed = sizes
    rng = np.random.default_rng(seed)
    M = rng.normal(size=(n, n))
    full = M @ M.T
    a = rng.normal(size=(m, n))
    q, x, y = rng.normal(size=n), rng.normal(size=n), rng.normal(size=m)
    lower = np.where(rng.random(m) < 0.3, -np.inf, rng.normal(size=m) - 1)
    upper = np.where(rng.random(m) < 0.3, np.inf, lower + rng.random(m) + 0.1)
    upper = np.where(np.isfinite(lower), upper, rng.normal(size=m))
    y = np.where((y > 0) & ~np.isfinite(upper), 0.0, np.where((y < 0) & ~np.isfinite(lower), 0.0, y))
    got = qp_certificate(sp.triu(sp.csc_matrix(full)), q, sp.csc_matrix(a), lower, upper, x, y)
    ax = a @ x
    assert got.primal_residual == pytest.approx(max(0.0, *np.maximum(ax - upper, lower - ax)), abs=1e-12)
    assert got.dual_residual == pytest.approx(np.max(np.abs(full @ x + q + a.T @ y)), rel=1e-9, abs=1e-12)
    with np.errstate(invalid="ignore"):
        bound = np.where(y > 0, upper * y, np.where(y < 0, lower * y, 0.0))
    assert got.duality_gap == pytest.approx(abs(x @ full @ x + q @ x + bound.sum()), rel=1e-9, abs=1e-9)

"""Every constraint family, tested where it binds, for every formulation × backend.

For each family (tests/binding_cases.py) a small capture problem whose unconstrained
optimum violates it: the tests check that each pair keeps the family (the evaluator's
violation, within what the formulation promises) while standing on its boundary, and
that without the family the same pair's plan would violate it. Removing any family
from any formulation therefore fails a test here. The QP's safety rows are read
directly and checked to be inner approximations; the QP backends must agree on the
QP's optimum.
"""

from __future__ import annotations

import math
from collections import defaultdict
from functools import lru_cache

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from binding_cases import CASES, SYMMETRIC, Case, octagon_slack, on_circle, slack
from mpc_hunt.formulations.capture_model import parameter_vector
from mpc_hunt.formulations.qp import POLYGON_SIDES, QPFormulation
from mpc_hunt import CaptureProblem, HuntParameters, Solution, Status, evaluate, solve
from mpc_hunt.solving import registry
from mpc_hunt.capture.evaluator import VIOLATION_NAMES


def pairs() -> list[tuple[str, str]]:
    """Every (formulation, backend) pair: the one place that reads the registry."""
    return sorted(registry.pairs(objective="paper"))


FAMILIES = list(CASES)

# The largest violation of the binding family that each formulation may leave, in metres (the
# evaluator's): about 10× the largest measured over the formulation's backends (in the comments),
# never below 1e-9 m. nlp writes every inequality on squared distances, so IPOPT's tolerance
# (1e-8 in m²) shows up as 1e-8 m over a distance of order 1 and 6e-7 m over r_d = 8 mm.
# The QP family keeps Eq. 13 (polygon or cone), Eq. 15 and the separations exactly (inner
# approximations); it linearises Eq. 14 and, beyond the first step, the attacker distance
# (through the attacker's linearised path): those carry a stated bound, the same for qp and socp.
# sqp re-linearises until its plan stops moving, so it keeps every family to solver accuracy.
LINEARISED = 5e-5   # qp: Eq. 14 4.3e-6, attacker distance 0 (4.7e-6 m inside); socp: 6e-14, 3.3e-6
VIOLATION_TOL = {
    "nlp": {"motion_limit": 7e-6,         # 6.2e-7
            "equal_distance": 2e-10,      # 1.9e-11 (the exact L1 penalty)
            "obstacle_safety": 2e-7,      # 1.7e-8
            "separation": 1e-7,           # 8.7e-9
            "attacker_distance": 1e-7},   # 0 (IPOPT stops 4.6e-7 m inside), a squared row like the two above
    "qp": {"motion_limit": 1e-9,          # 5.2e-17 (the octagon lies inside the circle)
           "equal_distance": LINEARISED,  # 4.3e-6
           "obstacle_safety": 1e-9,       # 0 (tangent half-plane)
           "separation": 1e-9,            # 0
           "attacker_distance": LINEARISED},  # 0
    "socp": {"motion_limit": 1e-9,        # 2.9e-12 (the exact cone, interior point)
             "equal_distance": LINEARISED,  # 6.1e-14: at N = 1 every step has length r_d, so the
                                            # linearisation error |δ|² is common to all and cancels
             "obstacle_safety": 1e-9,     # 0
             "separation": 1e-9,          # 0
             "attacker_distance": LINEARISED},  # 3.3e-6
    "sqp": dict.fromkeys(FAMILIES, 5e-8),  # ≤ 4.4e-9 (obstacle safety on OSQP; 2.8e-9 separation)
    # ms-nlp: the stage-structured NLP, rows per step (Eq. 13 per r_d²): 3.0e-11, 1.1e-13, 7.9e-11, 0, 0.
    "ms-nlp": {"motion_limit": 1e-9, "equal_distance": 2e-10, "obstacle_safety": 1e-9, "separation": 1e-9,
               "attacker_distance": 1e-9},
    # rti: one Gauss–Newton QP of the stage-structured problem, the qp's rows: 0, 4.3e-6, 0, 0, 0.
    "rti": {"motion_limit": 1e-9, "equal_distance": LINEARISED, "obstacle_safety": 1e-9, "separation": 1e-9,
            "attacker_distance": LINEARISED},
    # stage-sqp: rti re-linearised to its fixed point (3 to 5 QPs here), every family to HPIPM's accuracy: ≤ 6.7e-16.
    "stage-sqp": dict.fromkeys(FAMILIES, 1e-9),
}

# How far from the family's bound the plan may stop, in metres (|margin|, both sides): the plan
# stands on the boundary. The QP's half-planes are tangent at the reference (the held plan), so a
# one-shot QP (qp, socp) that slides along one stops just inside the true circle: t²/2ρ for a
# slide t along a tangent to a circle of radius ρ, 8e-5 m here for the obstacle. sqp
# re-linearises at its own plan and reaches the circle. Eq. 13: the exact circle or the octagon.
BOUNDARY_TOL = {
    "nlp": {"motion_limit": 7e-6, "obstacle_safety": 2e-7, "separation": 1e-7,
            "attacker_distance": 5e-6},   # measured 6.2e-7, 1.7e-8, 8.7e-9, 4.6e-7
    "qp": {"motion_limit": 1e-9, "obstacle_safety": 1e-3, "separation": 6e-5,
           "attacker_distance": 5e-5},    # 3.1e-12, 8.1e-5, 5.7e-6, 4.7e-6
    "socp": {"motion_limit": 1e-9, "obstacle_safety": 1e-3, "separation": 7e-5,
             "attacker_distance": 4e-5},  # 2.9e-12, 9.3e-5, 6.2e-6, 3.3e-6
    "sqp": dict.fromkeys(FAMILIES, 5e-8),  # ≤ 4.4e-9
    "ms-nlp": {"motion_limit": 1e-9, "obstacle_safety": 1e-9, "separation": 1e-9,
               "attacker_distance": 2e-8},  # measured 3.0e-11, 7.9e-11, 3.0e-11, 1.8e-9
    "rti": {"motion_limit": 1e-9, "obstacle_safety": 1e-3, "separation": 6e-5,
            "attacker_distance": 5e-5},     # 3.6e-11, 8.1e-5, 5.7e-6, 4.7e-6
    "stage-sqp": dict.fromkeys(FAMILIES, 1e-9),  # ≤ 7.2e-11: on the bound, as sqp
}

# Without the family, every pair's plan violates it by at least this (measured ≥ 4.5 mm) and by
# at least 10× the tolerance above, so that dropping the family fails the test below it.
RELAXED_VIOLATION = 1e-3

# The backends of one formulation solve the same QP(s): relative spread of the QP's own objective
# and spread of the plans (m). Measured over the five cases: qp 7.8e-7 and 1.1e-7 (OSQP, ADMM to
# eps 1e-7, on the obstacle case; clarabel and cvxpy agree to 2e-8), socp 9.2e-8 and 9.8e-8,
# sqp 4.1e-7 and 1.6e-7.
AGREEMENT = {"qp": (1e-5, 1e-6), "socp": (1e-6, 1e-6), "sqp": (5e-6, 2e-6),
             "rti": (1e-12, 1e-12), "stage-sqp": (1e-12, 1e-12)}   # the same steps, interpreted and compiled
                                                                   # (measured: equal to the bit)


@lru_cache(maxsize=None)
def solved(family: str, formulation: str, backend: str, relaxed: bool = False) -> Solution:
    case = CASES[family]
    return solve(case.relaxed() if relaxed else case.problem(), formulation, backend)


def boundary_distance(problem: CaptureProblem, plan: np.ndarray, family: str) -> float:
    """How far the plan stops from the family's boundary (Eq. 13: the circle or the QP's octagon)."""
    margin = abs(slack(problem, plan, family))
    if family == "motion_limit":
        margin = min(margin, abs(octagon_slack(problem, plan, POLYGON_SIDES)))
    return margin


def test_every_family_has_a_binding_case():
    assert sorted(CASES) == sorted(VIOLATION_NAMES)
    assert all(case.family == name for name, case in CASES.items())


@pytest.mark.parametrize("family", FAMILIES)
def test_the_case_starts_feasible(family):
    """The held plan keeps the family, so "never worse than now" relaxes none of its rows.

    Eq. 14 is the exception: it is an equality, never relaxed, and the attacker's first step
    already spreads the held defenders' distances.
    """
    problem = CASES[family].problem()
    assert problem.controlled.all()
    held = evaluate(problem, problem.held_plan())
    if family != "equal_distance":
        assert held.violation[family] == 0.0 and slack(problem, problem.held_plan(), family) > 1e-3


@pytest.mark.parametrize("formulation,backend", pairs())
@pytest.mark.parametrize("family", FAMILIES)
def test_without_the_family_the_plan_would_violate_it(family, formulation, backend):
    """Activeness: the same problem with the family's bound out of reach gives a plan that breaks it."""
    relaxed = solved(family, formulation, backend, relaxed=True)
    assert relaxed.plan is not None, relaxed.message
    violation = evaluate(CASES[family].problem(), relaxed.plan).violation[family]
    assert violation >= RELAXED_VIOLATION, violation
    assert violation >= 10 * VIOLATION_TOL[formulation][family]


@pytest.mark.parametrize("formulation,backend", pairs())
@pytest.mark.parametrize("family", FAMILIES)
def test_binding_family_is_kept_on_its_boundary(family, formulation, backend):
    """The pair succeeds, keeps the family to what its formulation promises, and stops on its bound."""
    problem = CASES[family].problem()
    solution = solved(family, formulation, backend)
    assert solution.status in (Status.OPTIMAL, Status.OPTIMAL_INACCURATE), solution.message
    assert solution.violation[family] <= VIOLATION_TOL[formulation][family], solution.violation
    if family != "equal_distance":  # an equality: its activeness is the test above
        assert boundary_distance(problem, solution.plan, family) <= BOUNDARY_TOL[formulation][family]


# --- The QP's safety rows, read from the QP itself -------------------------------------------

def _qp_rows(problem: CaptureProblem, reference: np.ndarray, family: str):
    """The QP at ``reference`` and, for each row of ``family``: (its coefficients on the positions,
    its lower bound, the (step, defender) blocks it involves)."""
    lin = QPFormulation().built(problem.structure)
    Xref = problem.x_from_plan(reference)
    data = lin.data(("rows",), parameter_vector(problem), Xref)
    A = data.A.toarray()
    assert len(lin.family) == A.shape[0]
    rows = []
    for r in np.flatnonzero(lin.family == family):
        assert np.all(A[r, len(Xref):] == 0) and data.u[r] == np.inf   # positions only; a ≥-row
        a = A[r, :len(Xref)]
        blocks = sorted({int(j) // 2 for j in np.flatnonzero(a)})
        rows.append((a, data.l[r], blocks))
    return rows, Xref


def _reference(problem: CaptureProblem, seed: int) -> np.ndarray:
    """A linearisation point: the held plan moved by up to r_d per step (the shifted-plan warm start)."""
    rng = np.random.default_rng(seed)
    plan = problem.held_plan().copy()
    steps = np.arange(1, problem.horizon + 1)[:, None, None]
    plan += rng.uniform(-1, 1, plan.shape) * problem.step_limits[None, :, None] * steps
    return plan


def _disc(rng, centre, radius, n):
    angle = rng.uniform(0, 2 * np.pi, n)
    length = radius * np.sqrt(rng.uniform(0, 1, n))
    return centre + length[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=1)


angles = st.floats(min_value=-math.pi, max_value=math.pi, allow_nan=False)


@settings(deadline=None, max_examples=100)
@given(defender=st.integers(0, 2), bearing=angles, gap=st.floats(1e-3, 0.05),
       radius=st.floats(0.02, 0.5), horizon=st.integers(1, 2), seed=st.integers(0, 2**32 - 1))
def test_qp_obstacle_rows_are_inner_approximations(defender, bearing, gap, radius, horizon, seed):
    """Every point an obstacle row admits keeps the true safety distance; the row touches the
    safety circle at the tangent point nearest its reference and cuts off the points beyond."""
    reference = _reference(Case("obstacle_safety", SYMMETRIC, horizon).problem(), seed)
    rho = radius + HuntParameters().safety_distance
    centre = reference[0, defender] + (rho + gap) * np.array([math.cos(bearing), math.sin(bearing)])
    problem = Case("obstacle_safety", SYMMETRIC, horizon, obstacles=((tuple(centre), radius),)).problem()
    # Every reference point and every defender now outside the safety circle: no row is relaxed
    # ("never worse than now").
    assume(np.linalg.norm(reference - centre, axis=2).min() > rho + 1e-6)
    assume(np.linalg.norm(problem.defender_positions - centre, axis=1).min() > rho + 1e-6)
    rows, Xref = _qp_rows(problem, reference, "obstacle_safety")
    assert len(rows) == horizon * 3            # one per step and controlled defender
    rng = np.random.default_rng(seed)
    for a, lower, blocks in rows:
        assert len(blocks) == 1
        b = blocks[0]
        p_ref = Xref[2 * b:2 * b + 2]
        normal = a[2 * b:2 * b + 2]
        assert np.linalg.norm(normal) == pytest.approx(1.0, abs=1e-12)

        def value(p):
            return (p - p_ref) @ normal - lower    # ≥ 0: admitted

        tangent = centre + rho * (p_ref - centre) / np.linalg.norm(p_ref - centre)
        assert value(tangent) == pytest.approx(0.0, abs=1e-12)      # touches the circle there
        assert value(p_ref) > 0                                      # the reference is admitted
        points = np.vstack([_disc(rng, tangent, 3 * gap + 0.02, 300), _disc(rng, p_ref, 0.05, 100)])
        admitted = np.array([value(p) >= 0 for p in points])
        distance = np.linalg.norm(points - centre, axis=1)
        assert np.all(distance[admitted] >= rho - 1e-12), distance[admitted].min() - rho
        assert np.any(~admitted)                                     # not vacuous


@settings(deadline=None, max_examples=100)
@given(fraction=st.floats(0.3, 0.995), horizon=st.integers(1, 2), seed=st.integers(0, 2**32 - 1),
       spread=st.sampled_from([20.0, 30.0, 60.0]))
def test_qp_separation_rows_are_inner_approximations(fraction, horizon, seed, spread):
    """Every pair of points a separation row admits keeps the true separation, and it is tight."""
    defenders = on_circle(0.58, [260.0, 260.0 + spread, 80.0])
    base = Case("separation", defenders, horizon).problem()
    reference = _reference(base, seed)
    closest = min(np.linalg.norm(plan[k, i] - plan[k, j]) for plan in (reference, base.held_plan())
                  for k in range(horizon) for i in range(3) for j in range(i + 1, 3))
    d_sep = fraction * closest
    problem = Case("separation", defenders, horizon, hunt={"min_separation": d_sep}).problem()
    rows, Xref = _qp_rows(problem, reference, "separation")
    assert len(rows) == horizon * 3            # one per step and pair
    rng = np.random.default_rng(seed)
    for a, lower, blocks in rows:
        assert len(blocks) == 2
        i, j = blocks
        pi_ref, pj_ref = Xref[2 * i:2 * i + 2], Xref[2 * j:2 * j + 2]

        def value(pi, pj):
            return (pi - pi_ref) @ a[2 * i:2 * i + 2] + (pj - pj_ref) @ a[2 * j:2 * j + 2] - lower

        unit = (pi_ref - pj_ref) / np.linalg.norm(pi_ref - pj_ref)
        assert value(pi_ref, pi_ref - d_sep * unit) == pytest.approx(0.0, abs=1e-12)   # tight
        assert value(pi_ref, pj_ref) > 0
        reach = np.linalg.norm(pi_ref - pj_ref) - d_sep + 0.02
        pis, pjs = _disc(rng, pi_ref, reach, 400), _disc(rng, pj_ref, reach, 400)
        admitted = np.array([value(p, q) >= 0 for p, q in zip(pis, pjs)])
        distance = np.linalg.norm(pis - pjs, axis=1)
        assert np.all(distance[admitted] >= d_sep - 1e-12)
        assert np.any(~admitted)                            # not vacuous


@settings(deadline=None, max_examples=50)
@given(excess=st.floats(1.01, 1.5), horizon=st.integers(1, 3), seed=st.integers(0, 2**32 - 1))
def test_qp_separation_rows_a_held_pair_breaks_are_relaxed_to_its_distance_now(excess, horizon, seed):
    """Never worse than now: with d_sep beyond a pair's distance now, each of its rows asks for
    n·(p_i − p_j) ≥ that distance, wherever the reference lies; the other pairs keep d_sep."""
    defenders = on_circle(0.58, [260.0, 280.0, 80.0])        # pair (0, 1) 0.20 m apart, the others farther
    now = np.linalg.norm(defenders[0] - defenders[1])
    d_sep = excess * now
    problem = Case("separation", defenders, horizon, hunt={"min_separation": d_sep}).problem()
    assert np.linalg.norm(defenders[[0, 1]] - defenders[2], axis=1).min() > 1.5 * d_sep
    rows, Xref = _qp_rows(problem, _reference(problem, seed), "separation")
    for a, lower, (i, j) in rows:
        pair = (i % 3, j % 3)
        n = a[2 * i:2 * i + 2]
        threshold = lower + n @ (Xref[2 * i:2 * i + 2] - Xref[2 * j:2 * j + 2])   # on n·(p_i − p_j)
        assert threshold == pytest.approx(now if pair == (0, 1) else d_sep, abs=1e-12), pair


# --- The QP backends agree --------------------------------------------------------------------

def _multi_backend() -> list[str]:
    backends = defaultdict(list)
    for f, b in pairs():
        backends[f].append(b)
    return sorted(f for f, bs in backends.items() if len(bs) > 1)


@pytest.mark.parametrize("formulation", _multi_backend())
@pytest.mark.parametrize("family", FAMILIES)
def test_backends_agree_on_the_optimum(family, formulation):
    """Every backend of a formulation whose certificate's duality gap is within the agreement reaches the same
    optimum, to the accuracy measured above; one whose gap is not (OSQP: eps 1e-7 on the cost scaled by 1 / max|P|
    leaves its objective up to 0.6 % above on these problems) is above the others' optimum by no more than its gap,
    which bounds it."""
    solutions = [solved(family, f, b) for f, b in pairs() if f == formulation]
    objective_tol, plan_tol = AGREEMENT[formulation]
    scale = max(abs(s.formulation_objective) for s in solutions)
    gap_tol = max(objective_tol, 1e-6) * scale     # the converged ones: ≤ 3e-7 relative (measured)
    converged = [s for s in solutions if s.certificate is None or s.certificate.duality_gap <= gap_tol]
    assert len(converged) >= len(solutions) - 1 >= 1, [s.certificate for s in solutions]
    objectives = np.array([s.formulation_objective for s in converged])
    plans = np.array([s.plan for s in converged])
    assert np.ptp(objectives) <= objective_tol * scale, objectives
    assert np.ptp(plans, axis=0).max() <= plan_tol
    for s in solutions:
        if s not in converged:
            assert s.formulation_objective - objectives.min() <= 1.01 * s.certificate.duality_gap + 1e-9 * scale

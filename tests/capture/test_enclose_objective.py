"""The enclose objective: each term decides a plan on a hand-made state, the arena bounds every plan, and the
CasADi model scores a plan as the evaluator does."""

from __future__ import annotations

import dataclasses

import casadi as ca
import numpy as np
import pytest

from conftest import small_scenario
from mpc_hunt.formulations.capture_model import capture_model, parameter_vector
from mpc_hunt.formulations.stage_linearisation import stage_linearisation
from mpc_hunt import CaptureProblem, CaptureSolver, Structure, evaluate
from mpc_hunt.capture.evaluator import ENCLOSE_TERM_NAMES
from mpc_hunt.capture.problem import EncloseWeights, ProblemError, Reference

STAGE_PAIRS = [("nlp", "ipopt"), ("ms-nlp", "ipopt"), ("rti", "hpipm"), ("qp", "osqp"), ("sqp", "osqp")]
ATTACKER = np.array([10.0, 10.0])


def _scenario(arena=None, nominal=(0.2, -0.2)):
    s = small_scenario(obstacles=())
    return dataclasses.replace(s, arena=arena, attacker=dataclasses.replace(s.attacker, nominal_velocity=nominal))


def _problem(scenario, defenders, places, attacker_place=None, horizon=5, weights=EncloseWeights(),
             attacker=ATTACKER):
    defenders = np.asarray(defenders, dtype=float)
    places = np.broadcast_to(np.asarray(places, dtype=float), (horizon,) + defenders.shape)
    target = np.broadcast_to(attacker if attacker_place is None else attacker_place, (horizon, 2))
    reference = Reference(places, target, np.ones(horizon))
    problem = CaptureProblem.at_state(scenario, attacker, defenders, horizon, reference=reference)
    return dataclasses.replace(problem, enclose_weights=weights)


FAR = ATTACKER + np.array([[3.0, 0.0], [0.0, 3.0], [-3.0, 0.0]])     # outside R_agg: the attacker drifts


def test_the_model_scores_a_plan_as_the_evaluator_does():
    problem = _problem(_scenario(arena=(0.0, 0.0, 20.0, 20.0)), FAR, FAR + [0.05, -0.02], horizon=3)
    plan = problem.held_plan() + np.random.default_rng(0).normal(0, 0.004, problem.held_plan().shape)
    model = capture_model(problem.structure)
    f = ca.Function("f", [model.X, model.theta], [ca.sumsqr(model.residual)])
    evaluation = evaluate(problem, plan)
    assert set(evaluation.terms) == set(ENCLOSE_TERM_NAMES)
    assert float(f(problem.x_from_plan(plan), parameter_vector(problem))) == pytest.approx(evaluation.objective,
                                                                                              rel=1e-12)


@pytest.mark.parametrize("formulation, backend", STAGE_PAIRS)
def test_the_slot_term_moves_each_defender_to_its_place(formulation, backend):
    shift = np.array([0.012, 0.0])                   # 1.5 steps east (within the QPs' trust region)
    problem = _problem(_scenario(), FAR, FAR + shift)
    solution = CaptureSolver(formulation, backend).solve(problem)
    assert solution.success
    exact = backend != "osqp"       # OSQP's default accuracy: 8e-4 m here; the interior-point solvers: 1e-11 m
    np.testing.assert_allclose(solution.plan[-1], FAR + shift, atol=1e-6 if exact else 2e-3)
    still = dataclasses.replace(problem, reference=dataclasses.replace(problem.reference, slot_weight=np.zeros(5)),
                                enclose_weights=EncloseWeights(attacker=0.0))
    if exact:      # OSQP's default accuracy leaves about a centimetre on this flat QP
        assert np.max(np.abs(CaptureSolver(formulation, backend).solve(still).plan[-1] - FAR)) < 1e-6


@pytest.mark.parametrize("formulation, backend", STAGE_PAIRS)
def test_the_attacker_term_pushes_the_attacker_to_its_place(formulation, backend):
    # Three defenders 0.9 m round a still attacker (inside R_agg); the attacker's place is 2 cm west.
    ring = ATTACKER + 0.9 * np.array([[np.cos(a), np.sin(a)] for a in np.radians([0.0, 120.0, 240.0])])
    scenario = _scenario(nominal=(0.0, 0.0))
    goal = ATTACKER - [0.02, 0.0]
    pushed = evaluate(p := _problem(scenario, ring, ring, goal, horizon=10),
                      CaptureSolver(formulation, backend).solve(p).plan).attacker_path[-1]
    idle = _problem(scenario, ring, ring, goal, horizon=10, weights=EncloseWeights(attacker=0.0))
    left = evaluate(idle, CaptureSolver(formulation, backend).solve(idle).plan).attacker_path[-1]
    assert np.linalg.norm(pushed - goal) < np.linalg.norm(left - goal) - 2e-3


@pytest.mark.parametrize("formulation, backend", STAGE_PAIRS)
def test_the_edge_term_turns_the_attacker_from_the_arena_edge(formulation, backend):
    # The attacker 0.5 m from the east edge (within the 1 m margin), heading east; one defender behind
    # it inside R_agg, two far; every place where each stands: only the edge term asks for a move.
    scenario = _scenario(arena=(0.0, 0.0, 10.5, 20.0), nominal=(0.03, 0.0))
    defenders = np.array([[9.2, 10.3], [5.0, 5.0], [5.0, 15.0]])
    edge = _problem(scenario, defenders, defenders, ATTACKER + [0.03, 0.0], horizon=10,
                    weights=EncloseWeights(attacker=0.0))
    free = dataclasses.replace(edge, enclose_weights=EncloseWeights(attacker=0.0, edge=0.0))
    x_edge = evaluate(edge, CaptureSolver(formulation, backend).solve(edge).plan).attacker_path[-1][0]
    x_free = evaluate(free, CaptureSolver(formulation, backend).solve(free).plan).attacker_path[-1][0]
    assert x_edge < x_free - 1e-4


@pytest.mark.parametrize("formulation, backend", STAGE_PAIRS)
def test_the_arena_bounds_every_plan(formulation, backend):
    # A defender 1 cm from the west edge, its place 5 cm beyond it: it stops on the edge.
    scenario = _scenario(arena=(9.0, 0.0, 20.0, 20.0))
    defenders = np.array([[9.01, 12.0], [13.0, 10.0], [12.0, 13.0]])
    places = defenders - [[0.06, 0.0], [0.0, 0.0], [0.0, 0.0]]
    solution = CaptureSolver(formulation, backend).solve(_problem(scenario, defenders, places))
    assert solution.success
    assert np.min(solution.plan[:, 0, 0]) >= 9.0 - 1e-6
    assert np.min(solution.plan[:, 0, 0]) == pytest.approx(9.0, abs=1e-6)       # binding (IPOPT: 9e-8 inside)


def test_a_reference_of_the_wrong_shape_is_a_one_line_error():
    scenario = _scenario()
    with pytest.raises(ProblemError, match="reference.defenders"):
        CaptureProblem.at_state(scenario, ATTACKER, FAR, 4, reference=Reference(np.zeros((3, 3, 2)),
                                                                               np.zeros((4, 2)), np.ones(4)))
    with pytest.raises(ProblemError, match="needs a Reference"):
        CaptureProblem(scenario, ATTACKER, FAR, np.ones(3, bool), np.zeros(2), 1, objective="enclose")



def test_the_stage_qp_leaves_eq14_out_and_keeps_eq13():
    """Under ``enclose`` rti's stage QP has neither Eq. 14's slacks nor its rows (4 of 10 controls and 6 rows fewer
    a stage at N_d = 3), and keeps Eq. 13's octagon: defenders sent 1.5 steps along a diagonal stop on its
    diagonal side (at r_d cos(π/8) along the diagonal), which only its rows hold."""
    assert (stage_linearisation(Structure(3, 0, 0, 1, "paper")).nu,
            stage_linearisation(Structure(3, 0, 0, 1, "enclose")).nu) == (10, 6)
    diagonal = np.array([1.0, 1.0]) / np.sqrt(2.0)
    problem = _problem(_scenario(), FAR, FAR + 0.012 * diagonal, horizon=3)
    solution = CaptureSolver("rti", "hpipm").solve(problem)
    assert solution.success, solution.message
    along = (solution.plan[0] - FAR) @ diagonal
    np.testing.assert_allclose(along, np.cos(np.pi / 8) * problem.step_limits, rtol=1e-9)   # achieved: 1e-13
    assert solution.violation["motion_limit"] <= 1e-9

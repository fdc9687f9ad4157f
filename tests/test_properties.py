"""Properties over random states: speed limits, obstacle safety of QP plans, the evaluator's symmetry."""

from __future__ import annotations

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from conftest import small_scenario
from mpc_hunt import CaptureProblem, EncirclingController, HuntingStrategy, Observation, evaluate, solve
from mpc_hunt.world.attacker import perceives
from strategies import floats

EXAMPLES = settings(deadline=None, max_examples=40)
offsets = st.tuples(floats(min_value=0.25, max_value=1.6), floats(min_value=-np.pi, max_value=np.pi))


def _state(attacker, polar_offsets):
    return np.array([attacker + r * np.array([np.cos(a), np.sin(a)]) for r, a in polar_offsets])


def _clear(scenario, defenders, margin=0.0):
    gaps = np.linalg.norm(defenders[:, None] - scenario.obstacle_centres[None], axis=2) - scenario.obstacle_radii
    spread = np.linalg.norm(defenders[:, None] - defenders[None], axis=2) + np.eye(len(defenders))
    return gaps.min() > scenario.hunt.safety_distance + margin and spread.min() > scenario.hunt.min_separation


obstacle = st.tuples(floats(min_value=4.0, max_value=6.0), floats(min_value=10.0, max_value=12.0),
                     floats(min_value=0.2, max_value=0.6))


@EXAMPLES
@given(st.lists(offsets, min_size=3, max_size=3), obstacle, st.sampled_from(["paper", "apf"]))
def test_every_command_respects_the_speed_limits(polar_offsets, obs, controller):
    scenario = small_scenario(obstacles=(obs,))
    attacker = np.array([5.0, 11.0])
    defenders = _state(attacker, polar_offsets)
    assume(_clear(scenario, defenders))
    control = (HuntingStrategy(scenario, formulation="qp", backend="daqp", horizon=2) if controller == "paper"
               else EncirclingController(scenario))
    command = control.command(Observation(0.0, attacker, attacker - [0.003, 0.0], defenders))
    assert np.all(np.linalg.norm(command.velocities, axis=1) <= scenario.defender_max_speeds + 1e-12)


@EXAMPLES
@given(st.lists(offsets, min_size=3, max_size=3), obstacle)
def test_a_qp_plan_keeps_the_obstacle_safety_distance(polar_offsets, obs):
    scenario = small_scenario(obstacles=(obs,))
    attacker = np.array([5.0, 11.0])
    defenders = _state(attacker, polar_offsets)
    assume(_clear(scenario, defenders))
    assume(perceives(scenario, attacker, defenders).any())
    problem = CaptureProblem.at_state(scenario, attacker, defenders, 2)
    solution = solve(problem, "qp", "daqp")
    assert solution.success, solution.message
    assert solution.violation["obstacle_safety"] <= 1e-9     # tangent half-planes: an inner approximation
    assert solution.violation["separation"] <= 1e-9


@EXAMPLES
@given(st.lists(offsets, min_size=3, max_size=3), st.permutations([0, 1, 2]),
       st.lists(st.tuples(floats(min_value=-0.008, max_value=0.008), floats(min_value=-0.008, max_value=0.008)),
                min_size=6, max_size=6))
def test_the_evaluator_does_not_depend_on_the_order_of_the_defenders(polar_offsets, order, steps):
    scenario = small_scenario()
    attacker = np.array([5.0, 11.0])
    defenders = _state(attacker, polar_offsets)
    assume(perceives(scenario, attacker, defenders).any())
    problem = CaptureProblem.at_state(scenario, attacker, defenders, 2)
    plan = problem.held_plan() + np.cumsum(np.array(steps).reshape(2, 3, 2), axis=0)
    reordered = CaptureProblem.at_state(scenario, attacker, defenders[list(order)], 2)
    a, b = evaluate(problem, plan), evaluate(reordered, plan[:, list(order)])
    assert abs(b.objective - a.objective) <= 1e-12 * abs(a.objective)
    for name, value in a.violation.items():
        assert abs(b.violation[name] - value) <= 1e-12, name

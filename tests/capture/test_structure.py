"""A problem's structure: what fixes a formulation's sizes, named, with its derived sizes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from conftest import ATTACKER, DEFENDERS, small_scenario
from mpc_hunt.formulations.capture_model import parameter_size, parameter_vector
from mpc_hunt import CaptureProblem, Structure


def test_a_problem_names_its_structure_and_the_sizes_follow():
    problem = CaptureProblem.at_state(small_scenario(obstacles=((11.0, 6.0, 0.4),)), ATTACKER, DEFENDERS, 4)
    structure = problem.structure
    assert structure == Structure(planned=3, fixed=0, obstacles=1, horizon=4, objective="paper")
    assert (structure.defenders, structure.plan_size, structure.reference_steps) == (3, 24, 0)
    assert structure.stage == dataclasses.replace(structure, horizon=1)
    assert parameter_size(structure) == parameter_vector(problem).size
    assert problem.signature == (structure, (0, 1, 2))
    assert "3 planned and 0 held defenders, 1 obstacles, horizon 4" in str(structure)


def test_the_enclose_objective_carries_one_reference_step_per_step():
    enclose = Structure(3, 1, 0, 5, "enclose")
    assert enclose.reference_steps == 5 and enclose.stage.reference_steps == 1
    assert parameter_size(enclose) - parameter_size(enclose, 0) == 5 * (2 * 3 + 3)


@pytest.mark.parametrize("horizon", [1, 3])
def test_a_decision_vector_and_a_plan_are_each_others_inverse(horizon):
    problem = CaptureProblem.at_state(small_scenario(), ATTACKER, DEFENDERS, horizon)
    plan = problem.held_plan() + np.arange(problem.held_plan().size).reshape(problem.held_plan().shape) * 1e-3
    x = problem.x_from_plan(plan)
    assert x.size == problem.structure.plan_size
    np.testing.assert_array_equal(problem.plan_from_x(np.concatenate([x, [7.0, 8.0]])), plan)


def test_theta_follows_each_problems_scenario_within_one_structure():
    """θ's writer works out what a scenario fixes once per scenario: problems of one structure from two
    scenarios, taken in turn, each get their own scenario's numbers; a held defender's go to its parts."""
    from mpc_hunt.formulations.capture_model import unpack
    from mpc_hunt.formulations.rti import RTIFormulation

    near, far = small_scenario(), small_scenario(obstacles=((9.0, 3.0, 0.5),))
    far = dataclasses.replace(far, defenders=tuple(dataclasses.replace(d, max_speed=0.09) for d in far.defenders))
    held = DEFENDERS.copy()
    held[2] = ATTACKER + [3.0, 0.0]                    # outside R_agg: held where it stands
    for scenario in (near, far, near):
        problem = CaptureProblem.at_state(scenario, ATTACKER, held, 3)
        assert problem.structure == Structure(2, 1, 1, 3, "paper")
        p = unpack(parameter_vector(problem), problem.structure)
        np.testing.assert_array_equal(p["centres"], scenario.obstacle_centres.ravel())
        np.testing.assert_array_equal(p["radii"], scenario.obstacle_radii)
        np.testing.assert_array_equal(p["step_limits"], problem.step_limits[:2])
        np.testing.assert_array_equal(p["nominal"], problem.nominal_velocity)
        np.testing.assert_array_equal(p["controlled"], held[:2].ravel())
        np.testing.assert_array_equal(p["held"], held[2])
        formulation = RTIFormulation()
        theta, reference = formulation.step_inputs(problem, problem.held_plan() + 0.01)
        assert theta[-1] == formulation.smoothing and theta[:-1].tobytes() == parameter_vector(problem).tobytes()
        np.testing.assert_array_equal(reference, problem.x_from_plan(problem.held_plan() + 0.01))

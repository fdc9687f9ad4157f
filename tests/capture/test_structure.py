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

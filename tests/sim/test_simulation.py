"""Closed-loop hunts: the paper's two simulations, the QP in the loop, determinism, fallbacks."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from conftest import small_scenario
from mpc_hunt import builtin_scenario, make_controller, simulate
from mpc_hunt.bench.capture_state import circle_formed, first_formed_circle


def _check_capture(result, scenario):
    assert result.captured, result.termination
    assert result.final_hunting_radius <= scenario.hunt.hunt_radius
    if scenario.obstacles:
        assert result.min_obstacle_clearance > 0          # never inside an obstacle
    assert result.min_defender_separation > 0 and result.min_attacker_distance > 0


@pytest.mark.slow
@pytest.mark.parametrize("name", ["paper-open", "paper-obstacles"])
@pytest.mark.parametrize("prediction", [True, False])
def test_paper_simulations_capture_without_collision(name, prediction):
    scenario = builtin_scenario(name)
    result = simulate(scenario, prediction=prediction)
    _check_capture(result, scenario)
    assert result.steps == len(result.times) - 1 == len(result.capture_stage)
    assert result.capture_time <= result.times[-1]


@pytest.mark.parametrize("name", ["paper-open", "paper-obstacles"])
@pytest.mark.parametrize("backend", ["osqp", "clarabel"])
def test_the_qp_drives_the_capture_stage(name, backend):
    scenario = builtin_scenario(name)
    result = simulate(scenario, make_controller("paper", scenario, formulation="qp", backend=backend))
    _check_capture(result, scenario)
    assert (result.formulation, result.backend) == ("qp", backend)
    stats = result.to_dict()["solve_time"]
    assert stats["count"] == len(result.solve_times) > 0
    assert stats["median_s"] <= stats["p95_s"] <= stats["max_s"]


def test_same_scenario_same_result():
    scenario = small_scenario(obstacles=())
    scenario = dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, time_limit=30.0))
    a, b = simulate(scenario), simulate(scenario)
    np.testing.assert_array_equal(a.attacker, b.attacker)
    np.testing.assert_array_equal(a.defenders, b.defenders)
    assert a.to_dict() | {"solve_time": None} == b.to_dict() | {"solve_time": None}


def test_until_stops_at_the_first_formed_circle():
    scenario = builtin_scenario("paper-open")
    state = first_formed_circle(scenario)
    distances = np.linalg.norm(state.attacker - state.defenders, axis=1)
    assert np.all(distances < scenario.attacker.perception_radius)
    assert distances.max() - distances.min() <= 2 * 0.08 * scenario.hunt.time_step
    result = simulate(scenario, until=lambda obs: circle_formed(scenario, obs))
    assert result.termination == "stopped" and not result.captured
    np.testing.assert_array_equal(result.attacker[-1], state.attacker)


@pytest.mark.slow
def test_a_starved_solver_falls_back_and_the_hunt_goes_on():
    scenario = builtin_scenario("paper-open")
    starved = make_controller("paper", scenario, formulation="nlp", time_limit=1e-9)
    result = simulate(scenario, starved)
    assert result.failed_solves > 0 and result.fallbacks == result.failed_solves
    assert np.all(np.isfinite(result.defenders))

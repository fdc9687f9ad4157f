"""The Voronoi encirclement baseline (mpc_hunt/control/voronoi.py, voronoi_cell.py)."""

from __future__ import annotations

import numpy as np
import pytest

from mpc_hunt import Attacker, Defender, HuntParameters, Obstacle, Scenario, simulate
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.voronoi import VoronoiController
from mpc_hunt.world.voronoi_cell import attacker_cell
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.control.spec import ControllerSpec, make_controller
from mpc_hunt.world.geometry import norm

ARENA = (0.0, 0.0, 20.0, 20.0)
NONE = np.empty((0, 2)), np.empty(0)


def hunt(attacker_start, nominal, defenders, obstacles=(), time_limit=60.0) -> Scenario:
    return Scenario(name="voronoi", arena=ARENA, hunt=HuntParameters(time_limit=time_limit),
                    attacker=Attacker(attacker_start, nominal, max(float(np.hypot(*nominal)), 0.01), 1.0),
                    defenders=tuple(Defender(p, 0.08) for p in defenders),
                    obstacles=tuple(Obstacle(c, r) for c, r in obstacles))


def test_the_cell_of_four_defenders_on_the_axes_is_the_square_of_their_bisectors():
    defenders = np.array([[2.0, 0.0], [0.0, 2.0], [-2.0, 0.0], [0.0, -2.0]])
    cell = attacker_cell(np.zeros(2), defenders, *NONE, (-10.0, -10.0, 10.0, 10.0))
    assert sorted(map(tuple, cell.vertices.round(12))) == [(-1, -1), (-1, 1), (1, -1), (1, 1)]
    for i, q in enumerate(defenders):
        a, b = cell.shared_edge(i)
        np.testing.assert_allclose(0.5 * (a + b), q / 2, atol=1e-12)


def test_an_open_side_runs_the_shared_edges_to_the_box_and_an_obstacle_cuts_at_its_tangent():
    defenders = np.array([[2.0, 0.0], [0.0, 2.0], [-2.0, 0.0]])       # nobody below: the box closes the cell
    cell = attacker_cell(np.zeros(2), defenders, *NONE, (-10.0, -10.0, 10.0, 10.0))
    a, b = cell.shared_edge(0)
    np.testing.assert_allclose(0.5 * (a + b), [1.0, -4.5], atol=1e-12)   # x = 1 from y = −10 to y = 1
    assert cell.shared_edge(1) is not None and cell.shared_edge(3) is None
    cell = attacker_cell(np.zeros(2), defenders, np.array([[0.0, -3.0]]), np.array([1.0]), (-10, -10, 10, 10))
    a, b = cell.shared_edge(-1)                                        # the tangent y = −2, from x = −1 to 1
    np.testing.assert_allclose(sorted([a[0], b[0]]), [-1.0, 1.0], atol=1e-12)
    np.testing.assert_allclose([a[1], b[1]], [-2.0, -2.0], atol=1e-12)
    np.testing.assert_allclose(0.5 * (sum(cell.shared_edge(0))), [1.0, -0.5], atol=1e-12)


def run(scenario, steps):
    """The controller's commands along a hunt, with the observations they answered."""
    controller = VoronoiController(scenario)
    seen = []

    def record(obs: Observation) -> bool:
        seen.append((obs, controller.command(obs)))
        return len(seen) >= steps
    simulate(scenario, controller, until=record)
    return seen


def test_every_command_is_within_the_speed_and_keeps_places_and_defenders_in_the_arena():
    # The attacker runs at the arena's west edge: the places on its far side lie beyond the edge.
    s = hunt((1.0, 10.0), (-0.02, 0.0), [(6.0, 10.0), (4.0, 14.0), (4.0, 6.0)])
    safe = s.hunt.safety_distance
    for obs, cmd in run(s, 600):
        assert np.all(norm(cmd.velocities) <= 0.08 + 1e-12)
        after = obs.defenders + s.hunt.time_step * cmd.velocities
        assert np.all((after >= 0.0) & (after <= 20.0))
        places = cmd.intercepts[~np.isnan(cmd.intercepts[:, 0])]
        assert np.all((places >= safe - 1e-12) & (places <= 20.0 - safe + 1e-12))


def test_a_defender_beside_an_obstacle_is_never_commanded_into_its_safety_distance():
    # Defender 0's straight way to its place runs through the obstacle; it starts 0.02 m beyond R_safe.
    centre, radius = np.array([5.0, 5.0]), 0.5
    s = hunt((5.0, 3.2), (0.0, 0.0), [(5.0, 5.62), (3.0, 1.5), (7.0, 1.5)], obstacles=[((5.0, 5.0), radius)])
    limit = radius + s.hunt.safety_distance
    for obs, cmd in run(s, 300):
        after = obs.defenders[0] + s.hunt.time_step * cmd.velocities[0]
        assert norm(after - centre) >= limit - 1e-12


def test_three_defenders_capture_a_slow_attacker():
    s = hunt((10.0, 10.0), (0.02, 0.0), [(7.0, 10.0), (12.0, 12.5), (12.0, 7.5)], time_limit=120.0)
    result = simulate(s, make_controller("voronoi", s))
    assert result.captured, result.termination


def test_by_name_on_the_command_line_and_as_a_sweep_strategy():
    s = hunt((10.0, 10.0), (0.02, 0.0), [(7.0, 10.0), (12.0, 12.5), (12.0, 7.5)])
    assert isinstance(make_controller("voronoi", s, prediction=False), VoronoiController)
    assert make_controller("voronoi", s).describe() == {"controller": "voronoi", "prediction": True}
    strategy = ControllerSpec.parse("voronoi")
    assert strategy.label == "voronoi" and isinstance(strategy.build(s), VoronoiController)
    with pytest.raises(MpcHuntError, match="^formulation: controller 'voronoi' solves no capture problem"):
        ControllerSpec.parse("voronoi:nlp")

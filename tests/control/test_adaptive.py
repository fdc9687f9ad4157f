"""The adapt controller (mpc_hunt/control/strategy.py): the online estimate feeds the capture problem's prediction."""

from __future__ import annotations

import pytest

from mpc_hunt.control.controllers import make_controller
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.world.belief import Belief
from mpc_hunt.world.scenario_io import builtin_scenario


def test_a_wrong_belief_is_corrected_from_the_track_and_the_hunt_is_captured():
    """The paper's obstacle hunt, the defenders believing R_agg 1.3 times too small and η three times too small:
    by the capture the model the capture problem predicts with holds the world's parameters."""
    world = builtin_scenario("paper-obstacles")
    controller = make_controller("adapt", world, belief=Belief(perception_radius=1.3, eta=3.0), formulation="rti",
                                 backend="hpipm", horizon=10)
    assert controller.prior.attacker.perception_radius == pytest.approx(1 / 1.3)
    result = simulate(world, controller)
    assert result.captured
    estimate, model = controller.estimate, controller.scenario
    assert estimate.identified
    # Noise-free track: recovered to the fit's precision (achieved 1e-13; the prior is 23 % and 200 % off).
    assert model.attacker.perception_radius == pytest.approx(world.attacker.perception_radius, rel=1e-6)
    assert model.hunt.k_d * model.hunt.eta == pytest.approx(world.hunt.k_d * world.hunt.eta, rel=1e-6)
    assert model.attacker.nominal_velocity == pytest.approx((0.0212132, -0.0212132), abs=1e-6)
    assert controller.describe()["controller"] == "adapt"

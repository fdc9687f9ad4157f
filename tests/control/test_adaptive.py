"""The adapt controller (mpc_hunt/control/strategy.py): the online estimate feeds the capture problem's prediction."""

from __future__ import annotations

import pytest

from mpc_hunt.control.spec import make_controller
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.world.belief import Belief
from mpc_hunt.world.scenario_io import builtin_scenario


@pytest.mark.slow
def test_a_wrong_belief_is_corrected_from_the_track_and_the_hunt_is_captured():
    """The paper's obstacle hunt, the defenders believing R_agg 1.3 times too small and η three times too small:
    by the capture the model the capture problem predicts with holds the world's parameters."""
    world = builtin_scenario("paper-obstacles")
    controller = make_controller("adapt", world, belief=Belief(perception_radius=1.3, eta=3.0), formulation="rti",
                                 backend="hpipm", horizon=10)
    assert controller.prior.perception_radius == pytest.approx(1 / 1.3) and controller.model is controller.prior
    hunt = controller.scenario
    result = simulate(world, controller)
    assert result.captured
    estimate, model = controller.estimate, controller.model
    assert estimate.identified and model is estimate.model
    # Noise-free track: recovered to the fit's precision (achieved 1e-13; the prior is 23 % and 200 % off).
    assert model.perception_radius == pytest.approx(world.attacker.perception_radius, rel=1e-6)
    assert model.gain == pytest.approx(world.hunt.k_d * world.hunt.eta, rel=1e-6)
    assert model.intent == pytest.approx((0.0212132, -0.0212132), abs=1e-6)
    # The capture problem and the enclose reference are posed with the model on the hunt the controller was
    # built on, which stays as given.
    assert controller.scenario is hunt and controller.reference.scenario is controller.posed()
    assert controller.posed() == model.scenario(hunt) != hunt
    assert controller.describe()["controller"] == "adapt"

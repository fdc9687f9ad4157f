"""Controllers by name, imported on first use (the registry's pattern, for the control layer)."""

from __future__ import annotations

from mpc_hunt.world.belief import Belief, believed
from mpc_hunt.world.names import load_class

CONTROLLERS = {
    "paper": "mpc_hunt.control.strategy:HuntingStrategy",
    "enclose": "mpc_hunt.control.strategy:EnclosingStrategy",
    "apf": "mpc_hunt.control.encircling:EncirclingController",
    "voronoi": "mpc_hunt.control.voronoi:VoronoiController",
    "contain": "mpc_hunt.control.strategy:ContainingStrategy",
    "adapt": "mpc_hunt.control.strategy:AdaptiveStrategy",
    "trap": "mpc_hunt.control.strategy:TrappingStrategy",
}
SOLVING = ("paper", "enclose", "contain", "adapt", "trap")     # the controllers that solve a capture problem (take solver settings)


def controller_objective(name: str) -> str:
    """The capture objective the solving controller ``name`` (one of :data:`SOLVING`) poses."""
    return load_class(CONTROLLERS, "controller", name).OBJECTIVE


def make_controller(name: str, scenario, *, belief: Belief = Belief(), rng=None, **options):
    """A fresh controller for ``scenario`` by name: ``paper``, the strategy with the paper's capture
    objective; ``enclose``, the same strategy with the enclose objective; ``apf``, the potential-field
    encirclement, and ``voronoi``, the Voronoi encirclement, with no optimisation; ``contain``, the capture
    problem tracking the Voronoi places with the attacker's observed velocity; ``trap``, the capture problem
    tracking a minimum-time shrink of the attacker's reachable set; ``adapt``, ``enclose`` re-estimating the
    attacker online.

    The controller is built on the defenders' ``belief`` of the attacker (:func:`mpc_hunt.world.belief.believed`;
    ``rng`` draws its heading error), never on the world's behaviour."""
    return load_class(CONTROLLERS, "controller", name)(believed(scenario, belief, rng), **options)

"""The world: a hunt declared as data (scenario, arena, the built-in scenarios) and the paper's model of it:
the fields (Eqs. 2–3), the attacker (Eq. 9), intercepts (Eqs. 7–8), the approaching stage (Eq. 6), the hunting
circle (Eqs. 4–5, 10–11) and separation. It imports nothing of the layers above."""

from mpc_hunt.world.belief import Belief
from mpc_hunt.world.ensemble import perturbed
from mpc_hunt.world.hunting_circle import CircleStatus, success_test
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Obstacle, Scenario
from mpc_hunt.world.scenario_io import builtin_names, builtin_scenario, load_scenario, resolve_scenario, save_scenario

__all__ = [
    "Attacker",
    "Belief",
    "CircleStatus",
    "Defender",
    "HuntParameters",
    "Obstacle",
    "Scenario",
    "builtin_names",
    "builtin_scenario",
    "load_scenario",
    "perturbed",
    "resolve_scenario",
    "save_scenario",
    "success_test",
]

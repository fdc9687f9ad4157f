"""How the world moves the attacker: behaviours by name, one file and one registry line each.

``apf`` is the paper's attacker (Eqs. 2 and 9; :mod:`mpc_hunt.world.attacker`),
the default, which every scenario without a ``behaviour`` keeps. The others are
evaders from the pursuit–evasion literature (docs/model.md, "Attacker
behaviours"): ``flee``, ``gap``, ``voronoi`` and ``noisy``; ``learned`` is a policy trained against the
recommended controller (``python studies/train_attacker.py``); ``minimax`` plans its best response to
where the defenders can be; ``ppo`` is a neural policy trained by PPO against the recommended controller
(``python studies/train_ppo.py``). Every behaviour
senses defenders within a radius, moves at most v_a, is repelled by obstacles
(Eq. 3) and never steps into one (:mod:`mpc_hunt.world.behaviours.base`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from mpc_hunt.world.behaviours.apf import ApfAttacker
from mpc_hunt.world.behaviours.flee import FleeingAttacker
from mpc_hunt.world.behaviours.gap import GapAttacker
from mpc_hunt.world.behaviours.learned import LearnedAttacker
from mpc_hunt.world.behaviours.minimax import MinimaxAttacker
from mpc_hunt.world.behaviours.noisy import NoisyAttacker
from mpc_hunt.world.behaviours.ppo import PpoAttacker
from mpc_hunt.world.behaviours.voronoi import VoronoiAttacker
from mpc_hunt.world.names import registered

if TYPE_CHECKING:
    from mpc_hunt.world.behaviours.base import Behaviour
    from mpc_hunt.world.scenario import Scenario

BEHAVIOURS: dict[str, Callable[[Scenario, np.random.Generator], Behaviour]] = {
    "apf": ApfAttacker,
    "flee": FleeingAttacker,
    "gap": GapAttacker,
    "voronoi": VoronoiAttacker,
    "noisy": NoisyAttacker,
    "learned": LearnedAttacker,
    "minimax": MinimaxAttacker,
    "ppo": PpoAttacker,
}
DEFAULT_BEHAVIOUR = "apf"


def make_behaviour(scenario: Scenario, rng: np.random.Generator) -> Behaviour:
    """A fresh behaviour for the attacker of ``scenario`` (``scenario.attacker.behaviour``); ``rng`` draws any
    randomness it has, so the same scenario and seed give the same hunt."""
    return registered(BEHAVIOURS, "attacker behaviour", scenario.attacker.behaviour)(scenario, rng)


def with_behaviour(scenario: Scenario, behaviour: str) -> Scenario:
    """``scenario`` with its attacker moved by ``behaviour`` in the world (a ``ScenarioError`` if it is unknown,
    or takes none of the attacker's ``sensing_radius`` or ``disturbance``)."""
    return dataclasses.replace(scenario, attacker=dataclasses.replace(scenario.attacker, behaviour=behaviour))

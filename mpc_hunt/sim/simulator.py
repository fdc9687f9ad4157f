"""The closed loop: the world integrates Eqs. 1–2; the controller only observes and commands.

Each step of length T: the controller sees the state at t; every defender moves
at its commanded velocity capped at its max speed (Eq. 1); the attacker moves
as its scenario's behaviour says (:mod:`mpc_hunt.world.behaviours`; the
paper's, its resultant of Eq. 9 plus its nominal intent capped at its max
speed, Eq. 2, by default), both evaluated at the state at t (explicit Euler).
The controller never learns the behaviour: it was built on a belief. A hunt ends when
the success test (Eqs. 4–5) has held for ``hold_time``, at ``time_limit``, or
if the state stops being finite, when the attacker leaves the scenario's arena
(if it has one), or when ``until`` (if given) says so of an observation. The
same scenario always gives the same result. Python's garbage collector is held off while the hunt runs and
collects between steps, once a step's command is applied (:mod:`mpc_hunt.sim.collector`), as a robot's loop
collects in its idle time. A hunt is a batch of one (:func:`mpc_hunt.sim.batch.simulate_batch`).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from mpc_hunt.control.controller import Controller, Observation
from mpc_hunt.control.recommended import PAPER
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.errors import OptionError
from mpc_hunt.sim.batch import simulate_batch
from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.world.behaviours.base import Behaviour
from mpc_hunt.world.scenario import Scenario

DEFAULT_SEED = 0


def check_seconds(name: str, value: object, error: type[Exception] = OptionError) -> None:
    """Refuse ``value`` for the setting ``name`` unless it is None or a positive, finite number of seconds."""
    if value is not None and not (
        isinstance(value, (int, float)) and not isinstance(value, bool) and 0 < value < float("inf")
    ):
        raise error(f"{name}: a positive, finite number of seconds or None, got {value!r}")


def simulate(
    scenario: Scenario,
    controller: Controller | None = None,
    *,
    prediction: bool = True,
    until: Callable[[Observation], bool] | None = None,
    progress: Callable[[float], None] | None = None,
    rng: np.random.Generator | None = None,
    behaviour: Behaviour | None = None,
    deadline: float | None = None,
    abandon_after: float | None = None,
) -> HuntResult:
    """Run one hunt. Without a controller, the paper's strategy as published (its capture stage
    :data:`~mpc_hunt.control.recommended.PAPER`, the one-step NLP on IPOPT) built by its spec on the defenders'
    default belief (:meth:`ControllerSpec.build <mpc_hunt.control.spec.ControllerSpec.build>`), never on the
    world's behaviour.

    ``rng`` draws whatever the attacker's behaviour draws (``noisy``); without one, a generator seeded
    with ``DEFAULT_SEED``, so the same scenario always gives the same hunt. ``behaviour`` moves the attacker
    instead of the scenario's (a policy under training, say).

    ``until`` stops the run (termination ``"stopped"``) before the first
    observation it returns true for; that observation is the last recorded state.
    ``progress``, if given, is called with the simulated time after each step. ``deadline`` (s), if given, is
    the capture stage's budget a step is counted against (:meth:`HuntResult.deadline_misses`), beside T; each
    step's time the hypervisor took from the machine is then read around it (``stolen_times``,
    :func:`~mpc_hunt.solving.step_timing.stolen`).
    ``abandon_after`` (s), if given, stops the run (termination ``"abandoned"``) once the capture stage's solves
    have failed for that long in a row: the hunt is then the fallback's, not the capture stage's.
    """
    check_seconds("deadline", deadline)
    check_seconds("abandon_after", abandon_after)
    controller = controller or ControllerSpec("paper", options={"prediction": prediction}, stage=PAPER).build(scenario)
    world = np.random.default_rng(DEFAULT_SEED) if rng is None else rng
    (result,) = simulate_batch(
        [scenario],
        [controller],
        [world],
        behaviours=[behaviour],
        until=until,
        progress=progress,
        deadline=deadline,
        abandon_after=abandon_after,
    )
    return result

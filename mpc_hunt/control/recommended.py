"""The capture-stage settings a solving controller runs with unless told otherwise, defined once for the command
line, the sweep and the environments.

RECOMMENDED_CONTROLLER with RECOMMENDED's solver settings is the strategy that
captured most often in the committed 500-hunt sweep of random hunts
(studies/sweep/, docs/robustness.md), every solve well inside the 0.1 s time
step: the enclose controller (docs/formulations.md, "Objectives") with its
capture problem on rti and HPIPM over ten steps. RECOMMENDED is the default of
every solving controller (:data:`~mpc_hunt.control.controllers.SOLVING`) by
name: ``mpc-hunt simulate --controller C``, the sweep's ``--strategy C`` and the
environments' controller C all run :func:`solver_settings` ``(C)``. PAPER is the
capture stage as published (the one-step NLP on IPOPT): ``mpc-hunt solve``, the
reproduction, the problem sets and the Python ``simulate(scenario)`` without a
controller use it.

A horizon is a whole number from 1 to :data:`MAX_HORIZON` (the capture
problem's own bound); :data:`horizon_argument` parses one as every command line does.
"""

from __future__ import annotations

import argparse

from mpc_hunt.arguments import count
from mpc_hunt.capture.problem import MAX_HORIZON, checked_horizon
from mpc_hunt.control import controllers
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.solving import registry

RECOMMENDED_CONTROLLER = "enclose"
RECOMMENDED = {"formulation": "rti", "backend": "hpipm", "horizon": 10}
PAPER = {"formulation": "nlp", "backend": "ipopt", "horizon": 1}
OTHER_HORIZON = 1       # the horizon of a formulation other than the default's, unless one is given

horizon_argument = count(MAX_HORIZON)
"""An argument type: a horizon, a whole number from 1 to MAX_HORIZON (argparse.ArgumentTypeError if not)."""


def parse_horizon(text: str) -> int:
    """A horizon from its text (a sweep strategy's fourth field); :class:`MpcHuntError` naming the bounds if not
    one."""
    try:
        return horizon_argument(text)
    except argparse.ArgumentTypeError as exc:
        raise MpcHuntError(f"horizon: {exc}") from None


def capture_settings(formulation: str | None = None, backend: str | None = None, horizon: int | None = None,
                     default: dict = RECOMMENDED) -> dict:
    """The capture stage (formulation, backend, horizon), each setting given or else ``default``'s: the default's
    backend and horizon go with the default's formulation; another formulation runs on its own default backend
    over OTHER_HORIZON steps. The pair is checked (known, compatible, installed: ``registry.check_pair``)."""
    formulation = formulation or default["formulation"]
    own = formulation == default["formulation"]
    backend = registry.check_pair(formulation, backend or (default["backend"] if own else None))
    steps = horizon if horizon is not None else (default["horizon"] if own else OTHER_HORIZON)
    return {"formulation": formulation, "backend": backend, "horizon": checked_horizon(steps)}


def solver_settings(controller: str, formulation: str | None = None, backend: str | None = None,
                    horizon: int | None = None, default: dict = RECOMMENDED) -> dict:
    """The solver settings controller ``controller`` runs with (``make_controller(controller, scenario,
    **settings)``): {} for a controller that solves no capture problem (which takes no settings), else
    :func:`capture_settings`, refused when the formulation does not pose the controller's objective."""
    if controller not in controllers.SOLVING:
        given = [name for name, value in (("formulation", formulation), ("backend", backend), ("horizon", horizon))
                 if value is not None]
        if given:
            raise MpcHuntError(f"{', '.join(given)}: controller {controller!r} solves no capture problem (only "
                               f"{', '.join(controllers.SOLVING)} take solver settings)")
        return {}
    settings = capture_settings(formulation, backend, horizon, default)
    objective = controllers.controller_objective(controller)
    posed = registry.formulation_class(settings["formulation"]).objectives
    if objective not in posed:
        raise MpcHuntError(f"formulation {settings['formulation']} poses the {' or '.join(posed)} objective, not "
                           f"the {objective} objective of controller {controller!r}")
    return settings

"""Controllers by name, one registry line each: a geometric controller is its class; a solving controller is its
reference (one file, :mod:`mpc_hunt.control.reference`) × the capture stage, registered as ``Solving(Reference)``."""

from __future__ import annotations

import inspect
from dataclasses import dataclass

import numpy as np

from mpc_hunt.errors import MpcHuntError, OptionError
from mpc_hunt.world.belief import Belief, believed
from mpc_hunt.control.containment import Containment
from mpc_hunt.control.encircling import EncirclingController
from mpc_hunt.control.enclosure import Enclosure
from mpc_hunt.control.reference import PaperObjective
from mpc_hunt.control.strategy import AdaptiveStrategy, HuntingStrategy
from mpc_hunt.control.trap import Trap
from mpc_hunt.control.voronoi import VoronoiController
from mpc_hunt.world.names import registered


@dataclass(frozen=True)
class Solving:
    """A solving controller's registry line: its reference × the capture stage (:class:`HuntingStrategy`)."""

    reference: type

    @property
    def OBJECTIVE(self) -> str:
        return self.reference.OBJECTIVE

    @property
    def SUMMARY(self) -> str:
        return self.reference.SUMMARY

    def __call__(self, scenario, **options) -> HuntingStrategy:
        return HuntingStrategy(scenario, self.reference, **options)


CONTROLLERS = {
    "paper": Solving(PaperObjective),
    "enclose": Solving(Enclosure),
    "apf": EncirclingController,
    "voronoi": VoronoiController,
    "contain": Solving(Containment),
    "adapt": AdaptiveStrategy,
    "trap": Solving(Trap),
}
# The controllers that solve a capture problem (take solver settings): those that pose an objective.
SOLVING = tuple(name for name, entry in CONTROLLERS.items() if hasattr(entry, "OBJECTIVE"))


def described() -> str:
    """Every registered controller with its summary, ``name: summary; ...`` (the CLI's help, the docs)."""
    return "; ".join(f"{name}: {entry.SUMMARY}" for name, entry in CONTROLLERS.items())


def table() -> str:
    """The registry as a Markdown table (docs/architecture.md holds it; a test compares)."""
    rows = [f"| `{name}` | {'the ' + entry.OBJECTIVE + ' objective' if name in SOLVING else 'no optimisation'} "
            f"| {entry.SUMMARY} |" for name, entry in CONTROLLERS.items()]
    return "\n".join(["| controller | capture stage | what it does |", "| --- | --- | --- |", *rows]) + "\n"


def controller_objective(name: str) -> str:
    """The capture objective the solving controller ``name`` (one of :data:`SOLVING`) poses."""
    return registered(CONTROLLERS, "controller", name).OBJECTIVE


def make_controller(name: str, scenario, *, belief: Belief = Belief(), rng=None, **options):
    """A fresh controller for ``scenario`` by its registered ``name`` (:data:`CONTROLLERS`; :func:`described`
    says what each does), with ``options`` (a solving controller's solver settings, ``prediction``).

    The controller is built on the defenders' ``belief`` of the attacker (:func:`mpc_hunt.world.belief.believed`;
    ``rng`` draws its heading error), never on the world's behaviour."""
    return registered(CONTROLLERS, "controller", name)(believed(scenario, belief, rng), **options)


def checked_controller(name: str, scenario, *, argument: str = "options", belief: Belief = Belief(), **options):
    """:func:`make_controller`'s controller, its settings checked now rather than at its first step, each refusal
    one :class:`~mpc_hunt.errors.OptionError` naming ``argument`` (the caller's name for ``options``).

    Checked: an unknown controller, a ``belief`` that is not one, an option its class does not take; the values
    its classes check (a horizon from 1 to ``MAX_HORIZON``, a positive time limit, a formulation and backend that
    pair, the objective); and the options passed through to the solver as they are (a solving controller's other
    keywords): with any, the problem the controller poses with its team round the attacker's start
    (:func:`_ring`) is solved once, and a solve that errs (the solver refused an option's name or value) is
    refused."""
    from mpc_hunt.capture.solution import Status
    from mpc_hunt.control.posing import posed_problem

    if not isinstance(name, str) or name not in CONTROLLERS:
        raise OptionError(f"controller: unknown controller {name!r} (available: {', '.join(CONTROLLERS)})")
    if not isinstance(belief, Belief):
        raise OptionError(f"belief: a Belief (mpc_hunt.world.belief), got {type(belief).__name__}")
    cls = registered(CONTROLLERS, "controller", name)
    parameters = inspect.signature(cls).parameters.values()
    if not any(p.kind is p.VAR_KEYWORD for p in parameters):       # a class that passes no option on
        taken = [p.name for p in parameters if p.kind is p.KEYWORD_ONLY]
        unknown = [k for k in options if k not in taken]
        if unknown:
            raise OptionError(f"{argument}: controller {name!r} takes no {', '.join(map(repr, unknown))} (its "
                              f"options: {', '.join(taken) or 'none'})")
    try:
        controller = make_controller(name, scenario, belief=belief, rng=np.random.default_rng(0), **options)
    except MpcHuntError as exc:
        raise OptionError(f"{argument}: {exc}") from None
    mpc = getattr(controller, "mpc", None)
    solver = None if mpc is None else mpc.solver
    passed = [k for k in options if solver is not None and k in solver.backend.options]
    if passed:
        problem = posed_problem(controller.scenario, _ring(controller.scenario), controller.horizon,
                                controller.objective)
        keys, backend = ", ".join(map(repr, passed)), solver.backend.name
        try:
            solution = solver.solve(problem)
        except Exception as exc:  # noqa: BLE001 - a solver library's own exception types (OSQPException, ...)
            first = str(exc).splitlines()[0] if str(exc) else ""
            raise OptionError(f"{argument}: {backend} refused its options {keys} ({type(exc).__name__}: {first}); "
                              f"check their names and values") from None
        if solution.status is Status.ERROR:
            raise OptionError(f"{argument}: {backend} erred with its options {keys} ({solution.message}); check "
                              f"their names and values")
    return controller


def _ring(scenario):
    """The attacker at its start, every defender within its perception radius (0.7 R_agg, evenly round it): a
    state at which both objectives plan the whole team."""
    from mpc_hunt.world.hunt_state import HuntState

    p_a = np.array(scenario.attacker.start, dtype=float)
    angles = 2 * np.pi * np.arange(len(scenario.defenders)) / len(scenario.defenders)
    ring = p_a + 0.7 * scenario.attacker.perception_radius * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    return HuntState(0.0, p_a, ring)

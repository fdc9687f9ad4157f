"""One controller with its settings, as the command line, the sweep, the environments and the Python API name it:
the one way a controller is built (:func:`make_controller` is a spec's keyword form).

A :class:`ControllerSpec` is a controller of :data:`~mpc_hunt.control.controllers.CONTROLLERS` and, for one that
solves a capture problem (:data:`~mpc_hunt.control.controllers.SOLVING`), its capture stage: formulation, backend
and horizon; with the options its class takes (``prediction``, ``time_limit``, ``score``, a solver's own options).
A field left unset takes its default (:mod:`mpc_hunt.control.recommended`), and the spec is checked when it is
made, each refusal a :class:`~mpc_hunt.errors.SettingError` naming the fields at fault. Its text form,
``controller[:formulation[:backend[:horizon]]]`` (:attr:`ControllerSpec.label`, :meth:`ControllerSpec.parse`), is a
sweep's strategy: ``enclose:rti:hpipm:10``, ``paper:qp:daqp:5``, ``apf``.
"""

from __future__ import annotations

import argparse
from dataclasses import InitVar, dataclass, field
from types import MappingProxyType
from typing import Any, Mapping, cast

import numpy as np

from mpc_hunt.arguments import count, shown
from mpc_hunt.capture.problem import MAX_HORIZON, horizon_error
from mpc_hunt.capture.solution import Status
from mpc_hunt.control import controllers
from mpc_hunt.control.posing import posed_problem
from mpc_hunt.control.recommended import OTHER_HORIZON, RECOMMENDED, RECOMMENDED_CONTROLLER
from mpc_hunt.errors import MpcHuntError, OptionError, SettingError
from mpc_hunt.solving import registry
from mpc_hunt.world.belief import Belief, believed
from mpc_hunt.world.hunt_state import HuntState

STAGE = ("formulation", "backend", "horizon")  # a solving controller's capture stage, in the label's order
FORM = "controller[:formulation[:backend[:horizon]]]"

horizon_argument = count(MAX_HORIZON)
"""An argument type: a horizon from its text, a whole number from 1 to MAX_HORIZON (else argparse.ArgumentTypeError
in :func:`~mpc_hunt.capture.problem.horizon_error`'s words)."""


@dataclass(frozen=True)
class ControllerSpec:
    """A controller by name with its capture stage and options, defaulted and checked once.

    A solving controller's unset formulation, backend and horizon are ``stage``'s (:data:`RECOMMENDED` unless
    told, e.g. :data:`PAPER`): its backend and horizon go with its formulation; another formulation runs on its own
    default backend over :data:`OTHER_HORIZON` steps. A controller that solves no capture problem takes none of
    them, and only the options its class names."""

    controller: str = RECOMMENDED_CONTROLLER
    formulation: str | None = None
    backend: str | None = None
    horizon: int | None = None
    options: Mapping[str, Any] = field(default_factory=dict, hash=False)
    stage: InitVar[Mapping[str, Any] | None] = None

    def __post_init__(self, stage: Mapping[str, Any] | None) -> None:
        name = self.controller
        if not isinstance(name, str) or name not in controllers.CONTROLLERS:
            raise SettingError(
                "controller", f"unknown controller {name!r} (available: {', '.join(controllers.CONTROLLERS)})"
            )
        options = _options(self.options)
        if name in controllers.SOLVING:
            settled = _stage(
                name,
                controllers.controller_objective(name),
                self.formulation,
                self.backend,
                self.horizon,
                stage or RECOMMENDED,
            )
        else:
            _refuse_settings(name, [f for f in STAGE if getattr(self, f) is not None] + list(options))
            settled = dict.fromkeys(STAGE)
        for key, value in settled.items():
            object.__setattr__(self, key, value)
        object.__setattr__(self, "options", MappingProxyType(options))

    @classmethod
    def of(
        cls,
        controller: str = RECOMMENDED_CONTROLLER,
        settings: Mapping[str, Any] | None = None,
        stage: Mapping[str, Any] | None = None,
    ) -> ControllerSpec:
        """The spec of ``controller`` with ``settings``, :func:`make_controller`'s keywords (its capture stage's
        fields and its options)."""
        rest = _mapping(settings or {})
        formulation, backend, horizon = (rest.pop(key, None) for key in STAGE)
        return cls(controller, formulation, backend, horizon, options=rest, stage=stage)

    @classmethod
    def parse(cls, text: str) -> ControllerSpec:
        """The spec written ``controller[:formulation[:backend[:horizon]]]`` (a sweep's strategy); a field left out
        or empty takes its default."""
        parts = text.split(":") if isinstance(text, str) else []
        if not parts or len(parts) > len(STAGE) + 1 or not parts[0]:
            raise OptionError(f"expected {FORM}, got {shown(str(text))}")
        name, given = parts[0], [part or None for part in parts[1:]]
        if name not in controllers.SOLVING and name in controllers.CONTROLLERS and len(parts) > 1:
            _refuse_settings(name, STAGE[: len(given)])
        horizon = given[2] if len(given) > 2 else None
        if horizon is not None:
            try:
                horizon = horizon_argument(horizon)
            except argparse.ArgumentTypeError as exc:
                raise SettingError("horizon", str(exc)) from None
        formulation, backend = (given + [None, None])[:2]
        return cls(name, formulation, backend, horizon)

    @property
    def capture_stage(self) -> tuple[str, str, int]:
        """A solving controller's formulation, backend and horizon, as settled on construction."""
        if self.formulation is None or self.backend is None or self.horizon is None:
            raise SettingError("controller", f"{self.controller} solves no capture problem")
        return self.formulation, self.backend, self.horizon

    @property
    def label(self) -> str:
        """The spec's text form (:meth:`parse`'s), every field written: how a sweep stores its strategy."""
        if self.controller not in controllers.SOLVING:
            return self.controller
        return f"{self.controller}:{self.formulation}:{self.backend}:{self.horizon}"

    @property
    def settings(self) -> dict[str, Any]:
        """:func:`make_controller`'s keywords: the capture stage (a solving controller's) and the options."""
        stage = {key: getattr(self, key) for key in STAGE} if self.controller in controllers.SOLVING else {}
        return stage | dict(self.options)

    def build(self, scenario, *, belief: Belief = Belief(), rng=None):
        """A fresh controller for ``scenario``: the registry's class (:data:`~mpc_hunt.control.controllers.CONTROLLERS`)
        with the spec's settings, built on the defenders' ``belief`` of the attacker
        (:func:`mpc_hunt.world.belief.believed`; ``rng`` draws its heading error), never on the world's behaviour."""
        return controllers.CONTROLLERS[self.controller](believed(scenario, belief, rng), **self.settings)

    def probed(self, scenario, *, belief: Belief = Belief(), argument: str = "options"):
        """:meth:`build`'s controller, built now rather than at a hunt's first step, each refusal one
        :class:`~mpc_hunt.errors.OptionError` naming ``argument`` (the caller's name for the options).

        Beyond the spec's own checks: what the controller's classes check (a positive time limit, say), and the
        options passed through to the solver as they are (a solving controller's other keywords): with any, the
        problem the controller poses with its team round the attacker's start (:func:`_ring`) is solved once, and a
        solve that errs (the solver refused an option's name or value) is refused."""
        if not isinstance(belief, Belief):
            raise OptionError(f"belief: a Belief (mpc_hunt.world.belief), got {type(belief).__name__}")
        try:
            controller = self.build(scenario, belief=belief, rng=np.random.default_rng(0))
        except MpcHuntError as exc:
            raise OptionError(f"{argument}: {exc}") from None
        mpc: Any = getattr(controller, "mpc", None)
        passed = [k for k in self.options if mpc is not None and k in mpc.solver.backend.options]
        if passed:
            solver, keys = mpc.solver, ", ".join(map(repr, passed))
            problem = posed_problem(
                controller.scenario, _ring(controller.scenario), controller.horizon, controller.objective
            )
            try:
                solution = solver.solve(problem)
            except Exception as exc:  # noqa: BLE001 - a solver library's own exception types (OSQPException, ...)
                first = str(exc).splitlines()[0] if str(exc) else ""
                raise OptionError(
                    f"{argument}: {solver.backend.name} refused its options {keys} "
                    f"({type(exc).__name__}: {first}); check their names and values"
                ) from None
            if solution.status is Status.ERROR:
                raise OptionError(
                    f"{argument}: {solver.backend.name} erred with its options {keys} "
                    f"({solution.message}); check their names and values"
                )
        return controller


def make_controller(name: str, scenario, *, belief: Belief = Belief(), rng=None, **settings):
    """A fresh controller for ``scenario`` by its registered ``name`` (:func:`~mpc_hunt.control.controllers.described`
    says what each does): ``ControllerSpec.of(name, settings).build(scenario, belief=belief, rng=rng)``, so a setting
    left out takes the spec's default, as ``mpc-hunt simulate --controller name`` does; ``settings`` are the spec's
    fields (``formulation``, ``backend``, ``horizon``) and the controller's options (``prediction``, ``time_limit``,
    ``score``, a solver's own), each refused one an :class:`~mpc_hunt.errors.OptionError` naming it."""
    return ControllerSpec.of(name, settings).build(scenario, belief=belief, rng=rng)


def _mapping(options: object) -> dict[str, Any]:
    """``options`` as a dict of settings by name."""
    if not isinstance(options, Mapping) or not all(isinstance(key, str) for key in options):
        raise SettingError("options", f"a dict of the controller's options by name, got {type(options).__name__}")
    return dict(options)


def _options(options: object) -> dict[str, Any]:
    """``options`` as a dict of a controller's options, none of them a field of the spec."""
    options = _mapping(options)
    fields = [key for key in options if key in ("controller",) + STAGE]
    if fields:
        raise SettingError(
            fields,
            "a field of the spec, not an option: give it as a field "
            f"(ControllerSpec({', '.join(f'{key}=...' for key in fields)}))",
        )
    return options


def _refuse_settings(name: str, given: list[str] | tuple[str, ...]) -> None:
    """Refuse what the non-solving controller ``name`` does not take: a capture stage, an option its class does not
    name."""
    taken = controllers.keyword_options(name)
    refused = [key for key in given if key not in taken]
    if refused:
        raise SettingError(
            refused,
            f"controller {name!r} solves no capture problem and takes only "
            f"{', '.join(taken) or 'no options'}: drop {'it' if len(refused) == 1 else 'them'}, "
            f"or use a controller that solves one ({', '.join(controllers.SOLVING)})",
        )


def _stage(
    name: str, objective: str, formulation: str | None, backend: str | None, horizon: object, default: Mapping[str, Any]
) -> dict[str, Any]:
    """The capture stage of the solving controller ``name``, each unset field ``default``'s (the class's
    docstring), checked: known, pairing and installed, a horizon in bounds, the pair posing ``objective``
    (:func:`~mpc_hunt.solving.registry.objective_refusal`)."""
    formulation = default["formulation"] if formulation is None else formulation
    try:
        registry.formulation_class(formulation)
    except MpcHuntError as exc:
        raise SettingError("formulation", str(exc)) from None
    own = formulation == default["formulation"]
    try:
        backend = registry.check_pair(formulation, default["backend"] if backend is None and own else backend)
    except MpcHuntError as exc:
        raise SettingError("backend", str(exc)) from None
    horizon = (default["horizon"] if own else OTHER_HORIZON) if horizon is None else horizon
    why = horizon_error(horizon)
    if why:
        raise SettingError("horizon", why)
    refusal = registry.objective_refusal(formulation, backend, objective)
    if refusal is not None:
        field = refusal.fields[0]
        raise SettingError(field, f"{refusal.reason} of controller {name!r}: use another {field}")
    return {"formulation": formulation, "backend": backend, "horizon": int(cast(int, horizon))}  # as checked


def _ring(scenario):
    """The attacker at its start, every defender within its perception radius (0.7 R_agg, evenly round it): a
    state at which both objectives plan the whole team."""
    p_a = np.array(scenario.attacker.start, dtype=float)
    angles = 2 * np.pi * np.arange(len(scenario.defenders)) / len(scenario.defenders)
    ring = p_a + 0.7 * scenario.attacker.perception_radius * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    return HuntState(0.0, p_a, ring)

"""Controllers by name, one registry line each: a geometric controller is its class; a solving controller is its
reference (one file, :mod:`mpc_hunt.control.reference`) × the capture stage, registered as ``Solving(Reference)``.
A controller is built by name through its spec, with its defaults (:func:`mpc_hunt.control.spec.make_controller`)."""

from __future__ import annotations

import inspect
from dataclasses import dataclass
from typing import Any, Protocol

from mpc_hunt import markdown
from mpc_hunt.control.containment import Containment
from mpc_hunt.control.controller import Controller
from mpc_hunt.control.encircling import EncirclingController
from mpc_hunt.control.enclosure import Enclosure
from mpc_hunt.control.ppo_team import PpoTeam
from mpc_hunt.control.reference import CaptureReference, PaperObjective
from mpc_hunt.control.strategy import AdaptiveStrategy, HuntingStrategy
from mpc_hunt.control.trap import Trap
from mpc_hunt.control.voronoi import VoronoiController
from mpc_hunt.world.names import registered


class Entry(Protocol):
    """A registry line: a controller's class, or a solving controller's :class:`Solving`; a solving one also has
    its ``OBJECTIVE``."""

    @property
    def SUMMARY(self) -> str: ...

    def __call__(self, *args: Any, **kwargs: Any) -> Controller: ...


@dataclass(frozen=True)
class Solving:
    """A solving controller's registry line: its reference × the capture stage (:class:`HuntingStrategy`)."""

    reference: type[CaptureReference]

    @property
    def OBJECTIVE(self) -> str:
        return self.reference.OBJECTIVE

    @property
    def SUMMARY(self) -> str:
        return self.reference.SUMMARY

    def __call__(self, scenario, **options) -> HuntingStrategy:
        return HuntingStrategy(scenario, self.reference, **options)


CONTROLLERS: dict[str, Entry] = {
    "paper": Solving(PaperObjective),
    "enclose": Solving(Enclosure),
    "apf": EncirclingController,
    "voronoi": VoronoiController,
    "contain": Solving(Containment),
    "adapt": AdaptiveStrategy,
    "trap": Solving(Trap),
    "ppo": PpoTeam,
}
# The controllers that solve a capture problem (take solver settings): those that pose an objective.
SOLVING = tuple(name for name, entry in CONTROLLERS.items() if hasattr(entry, "OBJECTIVE"))


def keyword_options(name: str) -> list[str]:
    """The options the non-solving controller ``name`` takes: its class's keyword-only arguments."""
    return [p.name for p in inspect.signature(CONTROLLERS[name]).parameters.values() if p.kind is p.KEYWORD_ONLY]


def described() -> str:
    """Every registered controller with its summary, ``name: summary; ...`` (the CLI's help, the docs)."""
    return "; ".join(f"{name}: {entry.SUMMARY}" for name, entry in CONTROLLERS.items())


def table() -> str:
    """The registry as a Markdown table (docs/architecture.md holds it; a test compares)."""
    rows = (
        [
            f"`{name}`",
            f"the {getattr(entry, 'OBJECTIVE')} objective" if name in SOLVING else "no optimisation",
            entry.SUMMARY,
        ]
        for name, entry in CONTROLLERS.items()
    )
    return "\n".join(markdown.table(["controller", "capture stage", "what it does"], "lll", rows)) + "\n"


def controller_objective(name: str) -> str:
    """The capture objective the solving controller ``name`` (one of :data:`SOLVING`) poses."""
    return getattr(registered(CONTROLLERS, "controller", name), "OBJECTIVE")

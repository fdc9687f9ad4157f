"""Formulations of the capture stage (Eqs. 12–15), registered by name."""

from __future__ import annotations

from formulations.base import Formulation, FormulationResult, shift_plan
from formulations.nlp import NLPFormulation
from formulations.qp import QPFormulation, SOCPFormulation
from formulations.sqp import SQPFormulation
from mpc_hunt.errors import UnknownNameError

FORMULATIONS = {cls.name: cls for cls in (NLPFormulation, QPFormulation, SQPFormulation, SOCPFormulation)}


def make_formulation(name: str) -> Formulation:
    """A formulation by name; an unknown name lists the available ones."""
    if name not in FORMULATIONS:
        raise UnknownNameError(f"unknown formulation {name!r} (available: {', '.join(FORMULATIONS)})")
    return FORMULATIONS[name]()


__all__ = ["FORMULATIONS", "Formulation", "FormulationResult", "make_formulation", "shift_plan"]

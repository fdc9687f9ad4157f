"""Solver backends, one module each, registered by name."""

from __future__ import annotations

from mpc_hunt.backends.base import BackendResult, NLPData, QPData, WarmStart
from mpc_hunt.backends.clarabel import ClarabelBackend
from mpc_hunt.backends.cvxpy import CvxpyBackend
from mpc_hunt.backends.ipopt import IpoptBackend
from mpc_hunt.backends.osqp import OsqpBackend
from mpc_hunt.errors import UnknownNameError

BACKENDS = {cls.name: cls for cls in (IpoptBackend, OsqpBackend, ClarabelBackend, CvxpyBackend)}


def make_backend(name: str, **options):
    """A fresh persistent backend by name; an unknown name lists the available ones."""
    if name not in BACKENDS:
        raise UnknownNameError(f"unknown backend {name!r} (available: {', '.join(BACKENDS)})")
    return BACKENDS[name](**options)


__all__ = ["BACKENDS", "BackendResult", "NLPData", "QPData", "WarmStart", "make_backend"]

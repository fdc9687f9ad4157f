"""Formulations and backends by name: one table line each, naming the class.

A backend module imports its solver package on first use, so ``import mpc_hunt``
pulls in no QP solver; the formulations are CasADi models and load CasADi. What a
formulation emits (``kind``: ``"nlp"``, ``"qp"``, ``"socp"``) and what a
backend accepts (``accepts``) decide which pairs work: compatibility is derived,
never listed. A backend whose solver package is missing is listed as
unavailable with its install hint.
"""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass

from mpc_hunt.errors import SettingError, SolverNotFoundError, UnknownNameError
from mpc_hunt.formulations.base import Formulation
from mpc_hunt.formulations.distributed import DistributedFormulation
from mpc_hunt.formulations.ms_nlp import MSNLPFormulation
from mpc_hunt.formulations.nlp import NLPFormulation
from mpc_hunt.formulations.qp import QPFormulation
from mpc_hunt.formulations.rti import RTIFormulation
from mpc_hunt.formulations.socp import SOCPFormulation
from mpc_hunt.formulations.sqp import SQPFormulation
from mpc_hunt.formulations.stage_sqp import StageSQPFormulation
from mpc_hunt.solving.backends.base import Backend
from mpc_hunt.solving.backends.clarabel import ClarabelBackend
from mpc_hunt.solving.backends.cvxpy import CvxpyBackend
from mpc_hunt.solving.backends.daqp import DaqpBackend
from mpc_hunt.solving.backends.daqp_condensed import DaqpCondensedBackend
from mpc_hunt.solving.backends.hpipm import HpipmBackend
from mpc_hunt.solving.backends.hpipm_codegen import HpipmCodegenBackend
from mpc_hunt.solving.backends.ipopt import IpoptBackend
from mpc_hunt.solving.backends.osqp import OsqpBackend
from mpc_hunt.world.names import registered

FORMULATIONS: dict[str, type[Formulation]] = {
    "nlp": NLPFormulation,
    "qp": QPFormulation,
    "sqp": SQPFormulation,
    "socp": SOCPFormulation,
    "ms-nlp": MSNLPFormulation,
    "rti": RTIFormulation,
    "stage-sqp": StageSQPFormulation,
    "distributed": DistributedFormulation,
}

BACKENDS: dict[str, type[Backend]] = {
    "ipopt": IpoptBackend,
    "osqp": OsqpBackend,
    "clarabel": ClarabelBackend,
    "cvxpy": CvxpyBackend,
    "daqp": DaqpBackend,
    "daqp-condensed": DaqpCondensedBackend,
    "hpipm": HpipmBackend,
    "hpipm-codegen": HpipmCodegenBackend,
}


def formulation_class(name: str) -> type[Formulation]:
    """The formulation registered as ``name``; an unknown name lists the registered ones."""
    return registered(FORMULATIONS, "formulation", name)


def backend_class(name: str) -> type[Backend]:
    """The backend registered as ``name`` (its module imports no solver until used)."""
    return registered(BACKENDS, "backend", name)


def installed(backend: str) -> bool:
    """Whether the solver package behind ``backend`` can be imported here."""
    return importlib.util.find_spec(backend_class(backend).package) is not None


def install_hint(backend: str) -> str:
    cls = backend_class(backend)
    return f"backend {backend!r} needs the Python package {cls.package!r}: pip install {cls.package}"


def compatible_backends(formulation: str) -> list[str]:
    """Every registered backend that accepts what ``formulation`` emits, installed or not."""
    kind = formulation_class(formulation).kind
    return [b for b in BACKENDS if kind in backend_class(b).accepts]


def stage_formulations() -> list[str]:
    """The formulations whose step is one stage-form Function (kind ``ocp-qp``): what a control loop
    (:mod:`mpc_hunt.solving.step`) and the C export run."""
    return [f for f in FORMULATIONS if formulation_class(f).kind == "ocp-qp"]


def stage_form_message(formulation: str) -> str:
    """Why ``formulation`` has no control loop's step or C export."""
    return (
        f"formulation: only the stage-form steps ({', '.join(stage_formulations())}) run as one Function "
        f"(a control loop, the C export), not {formulation!r}"
    )


def pairs(installed_only: bool = True, objective: str | None = None) -> list[tuple[str, str]]:
    """Every (formulation, backend) that works together (by default, only installed backends), or only those
    that pose ``objective`` (:func:`objective_refusal`)."""
    return [
        (f, b)
        for f in FORMULATIONS
        for b in compatible_backends(f)
        if not installed_only or installed(b)
        if objective is None or objective_refusal(f, b, objective) is None
    ]


def objective_refusal(formulation: str, backend: str | None, objective: str) -> SettingError | None:
    """Why ``formulation`` on ``backend`` cannot pose the capture ``objective``, None if it can: the one check of
    which objectives a pair poses (the formulation's ``objectives``; the backend's, None for every one; ``backend``
    None: the formulation's alone). The refusal names the field at fault, ``formulation`` or ``backend``."""
    posed = formulation_class(formulation).objectives
    if objective not in posed:
        return SettingError(
            "formulation",
            f"formulation {formulation} poses the {' or '.join(posed)} objective, not the {objective} objective",
        )
    taken = None if backend is None else backend_class(backend).objectives
    if taken is not None and objective not in taken:
        return SettingError(
            "backend",
            f"backend {backend} solves only the {' or '.join(taken)} objective's QPs, "
            f"not those of the {objective} objective",
        )
    return None


@dataclass(frozen=True)
class Pair:
    """A formulation and a backend that work together, as their classes; ``backend_name`` as asked for."""

    formulation: type[Formulation]
    backend: type[Backend]
    backend_name: str

    @property
    def closes_step(self) -> bool:
        """Whether the backend closes the formulation's step into one Function (kind ``ocp-qp``): a control loop's
        step and the C export."""
        return self.formulation.kind == "ocp-qp"


def resolve(formulation: str, backend: str | None = None) -> Pair:
    """``formulation`` and ``backend`` (the formulation's default if None) found and checked once.

    Raises :class:`UnknownNameError` for an unknown or incompatible name and
    :class:`SolverNotFoundError` when the backend's package is missing.
    """
    cls = formulation_class(formulation)
    backend = backend or cls.default_backend
    solver = backend_class(backend)
    if cls.kind not in solver.accepts:
        raise UnknownNameError(
            f"backend {backend!r} does not solve formulation {formulation!r} "
            f"(use one of: {', '.join(compatible_backends(formulation))})"
        )
    if not installed(backend):
        raise SolverNotFoundError(install_hint(backend))
    return Pair(cls, solver, backend)


def check_pair(formulation: str, backend: str | None) -> str:
    """The backend to use with ``formulation`` (its default if ``backend`` is None), checked (:func:`resolve`)."""
    return resolve(formulation, backend).backend_name

"""The accuracy settings of a benchmark: each level's violation tolerance and each backend's solver tolerances.

A level (``default``, ``high``, ``low``, ``solver``) sets the tolerances every
backend is handed (its ``ACCURACY`` table in :mod:`mpc_hunt.solving.backends`;
``solver``: none, each solver's own defaults, as qpbenchmark's default profile)
and the largest true violation, in metres, that the success rule accepts:
``default`` and ``solver`` 0.1 mm (an eightieth of a defender's step r_d = 8 mm,
a thousandth of R_safe: finer than the robots can act on), ``high`` 1e-8 m (exact
but for rounding), ``low`` 1 mm.
"""

from __future__ import annotations

from mpc_hunt import markdown
from mpc_hunt.solving import registry
from mpc_hunt.solving.backends.base import ACCURACIES

VIOLATION_TOLERANCE = {"default": 1e-4, "high": 1e-8, "low": 1e-3, "solver": 1e-4}  # m


def _settings(options: dict) -> str:
    return (
        ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in options.items())
        or "the solver's defaults"
    )


def accuracy_table() -> str:
    """One Markdown table: per level, the violation tolerance and what each registered backend is handed."""
    backends = list(registry.BACKENDS)
    rows = []
    for level in ACCURACIES:
        handed = [_settings(registry.backend_class(b).ACCURACY.get(level, {})) for b in backends]
        rows.append([level, f"{VIOLATION_TOLERANCE[level]:g}", *handed])
    header = ["accuracy", "violation tolerance (m)", *backends]
    return "\n".join(markdown.table(header, "lr" + "l" * len(backends), rows))

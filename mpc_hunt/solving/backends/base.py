"""The backend contract: what every backend takes, what it gives back, and the lifecycle they share.

A backend is a persistent solver object (osqp-style). The first ``solve`` of a
new ``key`` sets a solver up; later solves of that key only update numbers in
place and warm-start. :class:`Backend` owns that lifecycle (the cache by key,
the set-up counter, the timing, non-finite answers); a concrete backend
supplies ``setup``, ``update`` and ``run``, and declares which problem kinds it
``accepts`` and which Python package it needs. It imports that package on first
use, so listing or importing backends never loads a solver.
"""

from __future__ import annotations

import time
from collections import OrderedDict
from dataclasses import replace
from typing import Any, ClassVar

import numpy as np

from mpc_hunt.errors import OptionError, SolverError, UnknownNameError
from mpc_hunt.capture.solution import Solution, Status, WarmStart

ACCURACIES = ("default", "high", "low")
CACHE_SIZE = 16   # structures kept set up per backend (the controlled set changes during a hunt)


class Backend:
    """Base of every backend: set up once per key, then update and solve.

    ``time_limit`` (s) is handed to the solver as its own limit (a backend whose
    solver has none says so with ``TIME_LIMIT = False`` and refuses one); ``accuracy``
    (``default``, ``high``, ``low``) picks the tolerances of the class's
    ``ACCURACY`` table; other keyword options go to the solver as they are.
    """

    name: ClassVar[str]
    accepts: ClassVar[tuple[str, ...]]      # problem kinds: "nlp", "qp", "socp", "ocp-nlp", "ocp-qp"
    package: ClassVar[str]                  # the solver's import name
    install: ClassVar[str]                  # what to pip install
    ACCURACY: ClassVar[dict[str, dict[str, Any]]] = {}
    TIME_LIMIT: ClassVar[bool] = True       # whether the solver takes a wall-clock limit
    objectives: ClassVar[tuple[str, ...] | None] = None     # the objectives whose QPs it can solve (None: every one)

    def __init__(self, time_limit: float | None = None, accuracy: str = "default", **options):
        if accuracy not in ACCURACIES:
            raise UnknownNameError(f"unknown accuracy {accuracy!r} (available: {', '.join(ACCURACIES)})")
        number = isinstance(time_limit, (int, float, np.integer, np.floating)) and not isinstance(time_limit, bool)
        if time_limit is not None and not (number and 0 < time_limit < float("inf")):
            raise OptionError(f"time_limit: a positive, finite number of seconds or None, got {time_limit!r}")
        if time_limit is not None and not self.TIME_LIMIT:
            raise SolverError(f"backend {self.name} takes no time limit (its solver has none); drop the time limit "
                              f"or pick another backend")
        self.time_limit = time_limit
        self.accuracy = accuracy
        self.options = {**self.ACCURACY.get(accuracy, {}), **options}
        self.setups = 0
        self._cache: OrderedDict[tuple, Any] = OrderedDict()

    # What a concrete backend supplies.
    def setup(self, data) -> Any:
        """Build the solver for ``data``'s structure; returns the state kept for that key."""
        raise NotImplementedError

    def update(self, state: Any, data) -> None:
        """Hand the solver kept in ``state`` the new numbers of ``data`` (same structure)."""

    def run(self, state: Any, data, warm: WarmStart) -> Solution:
        """Solve; a :class:`Solution` with status, message, x, formulation_objective, iterations, duals."""
        raise NotImplementedError

    # The shared lifecycle.
    def prepared(self, data) -> tuple[Any, bool]:
        """The solver set up for ``data``'s key, and whether it was set up by this call (else kept from an earlier
        one): what :meth:`solve` and a control loop's step (:mod:`mpc_hunt.solving.loop`) share."""
        state = self._cache.get(data.key)
        if state is not None:
            self._cache.move_to_end(data.key)
            return state, False
        state = self.setup(data)
        self.setups += 1
        self._cache[data.key] = state
        if len(self._cache) > CACHE_SIZE:
            self._cache.popitem(last=False)
        return state, True

    def solve(self, data, warm: WarmStart | None = None) -> Solution:
        setup_time = 0.0
        t0 = time.perf_counter()
        try:
            state, new = self.prepared(data)
            if new:
                setup_time = time.perf_counter() - t0
                t0 = time.perf_counter()
            else:
                self.update(state, data)
            result = self.run(state, data, warm or WarmStart())
        except (RuntimeError, ValueError, ArithmeticError) as exc:  # the solver library gave up
            self._cache.pop(data.key, None)
            message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            return Solution(status=Status.ERROR, message=message, backend=self.name,
                            solver_time=time.perf_counter() - t0, setup_time=setup_time)
        solver_time = time.perf_counter() - t0
        if result.x is not None and not np.all(np.isfinite(result.x)):
            result = replace(result, x=None, formulation_objective=None, message=f"{result.message} (non-finite x)")
        if result.x is None and result.status.usable:
            result = replace(result, status=Status.ERROR, message=f"{result.message} (no solution returned)")
        return replace(result, backend=self.name, solver_time=solver_time, setup_time=setup_time)

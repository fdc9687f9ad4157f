"""The backend contract: what every backend takes, what it gives back, and the lifecycle they share.

A backend is a persistent solver object (osqp-style). The first ``solve`` of a
new ``key`` sets a solver up; later solves of that key only update numbers in
place and warm-start. :class:`Backend` owns that lifecycle (the cache by key,
the set-up counter, the timing, non-finite answers, the budget); a concrete
backend supplies ``setup``, ``update`` and ``run``, and declares which problem
kinds it ``accepts`` and which Python package it needs. It imports that package
on first use, so listing or importing backends never loads a solver.

The budget has one name per kind on every backend: ``time_limit`` (seconds) and
``max_iter`` (iterations), each handed to the solver under its own name
(``NATIVE``). A solver that does not stop itself on the clock (``CLOCK = False``:
DAQP, whose clock is read only inside long inner loops) gets its time limit as
an iteration cap from its measured cost: a solve of k iterations takes a fixed
cost plus k times a cost per iteration, measured on the CPU time of its last
solves (a structure's first, slower by its allocations, apart): the fixed cost
fitted robustly (Theil–Sen), the cost per iteration bounded by the largest a
recent solve of several iterations has shown; the cap is the limit less the
fixed cost over 1.5 times that bound (:meth:`Backend.iteration_cap`). The time limit is the step's: while a step is
under way (:meth:`Backend.step_within`, opened by the solver and the control
loop), every solve of it is handed what is left of the step's limit, a solver
with a clock that less what a solve spends outside that clock, measured
against the solve time the solver reports (:meth:`Backend.clock_limit`), so
that a step of several QPs (``sqp``), or one whose linearisation came first,
ends within its limit, not each QP within it. A solve that ran past its time
limit all the same returns ``time_limit``, never ``optimal``. The solver's own names for the
budget and any option the solver does not know are refused when the backend is
made, each in one line naming the key.
"""

from __future__ import annotations

import difflib
import math
import time
from collections import OrderedDict, deque
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import replace
from typing import Any, ClassVar

import numpy as np

from mpc_hunt.capture.certificate import Certificate, qp_certificate
from mpc_hunt.capture.data import QPData
from mpc_hunt.capture.iteration import PACE_MARGIN
from mpc_hunt.capture.solution import Solution, Status, WarmStart
from mpc_hunt.errors import OptionError, SolverError, UnknownNameError, field_name

# The accuracy profiles: ours, tuned per backend (default), tighter (high), looser (low), and each solver's own
# defaults (solver), as qpbenchmark's "default" profile runs them (docs/benchmarks.md).
ACCURACIES = ("default", "high", "low", "solver")
CACHE_SIZE = 16  # structures kept set up per backend (the controlled set changes during a hunt)
MAX_ITERATIONS = 1_000_000  # the largest iteration cap taken
FIRST_CAP = 100  # a clockless solver's cap under a time limit before any time per iteration is measured
PACE_SOLVES = 32  # the last solves a clockless solver's cost (fixed + per iteration) is fitted to
BOUND_ITERATIONS = 8  # the fewest iterations of a solve whose own cost per iteration counts towards the bound
MIN_SLICE = 1e-6  # s: the clock limit a solver is handed when its step's time is already spent (it stops at once)
BUDGET = ("time_limit", "max_iter")


def _number(value: object) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)


class Backend:
    """Base of every backend: set up once per key, then update and solve.

    ``time_limit`` (s) and ``max_iter`` are the budget of every solve (the module's docstring); ``accuracy``
    (:data:`ACCURACIES`) picks the tolerances of the class's ``ACCURACY`` table; other keyword options
    go to the solver as they are, each checked against what the solver takes (:meth:`option_names`).
    """

    name: ClassVar[str]
    accepts: ClassVar[tuple[str, ...]]  # problem kinds: "nlp", "qp", "socp", "ocp-nlp", "ocp-qp"
    # The step its C export writes (mpc_hunt.solving.export): "hpipm" (CasADi's, built against this machine's HPIPM
    # and BLASFEO) or "condensed" (with DAQP's sources, for any target); None: no export.
    exports: ClassVar[str | None] = None
    package: ClassVar[str]  # the solver's import name, pip installed by the same name
    ACCURACY: ClassVar[dict[str, dict[str, Any]]] = {}
    TIME_LIMIT: ClassVar[bool] = True  # whether it takes a time limit at all
    CLOCK: ClassVar[bool] = True  # whether the solver stops itself on the clock (else: an iteration cap)
    MAX_ITER: ClassVar[int] = 1000  # the iteration cap without max_iter
    NATIVE: ClassVar[dict[str, str]] = {}  # the solver's own names of time_limit and max_iter
    LOOP_CERTIFICATE: ClassVar[bool] = False  # whether its loop step writes its QP's certificate (output 5)
    objectives: ClassVar[tuple[str, ...] | None] = None  # the objectives whose QPs it can solve (None: every one)

    def __init__(
        self, time_limit: float | None = None, accuracy: str = "default", *, max_iter: int | None = None, **options
    ):
        if accuracy not in ACCURACIES:
            raise UnknownNameError(f"accuracy: unknown {accuracy!r} (available: {', '.join(ACCURACIES)})")
        if time_limit is not None and not (_number(time_limit) and 0 < time_limit < float("inf")):
            raise OptionError(f"time_limit: a positive, finite number of seconds or None, got {time_limit!r}")
        if time_limit is not None and not self.TIME_LIMIT:
            raise SolverError(
                f"{field_name('time_limit')}: backend {self.name} takes none (its step is one call "
                f"that nothing can stop); bound it with {field_name('max_iter')}, drop "
                f"{field_name('time_limit')} or pick another backend"
            )
        if max_iter is not None and not (
            _number(max_iter) and float(max_iter).is_integer() and 1 <= max_iter <= MAX_ITERATIONS
        ):
            raise OptionError(
                f"max_iter: a whole number of iterations from 1 to {MAX_ITERATIONS} or None, got {max_iter!r}"
            )
        self._check_options(options)
        self.time_limit = None if time_limit is None else float(time_limit)
        self.max_iter = None if max_iter is None else int(max_iter)
        self.accuracy = accuracy
        self.options = {**self.ACCURACY.get(accuracy, {}), **options}
        self.setups = 0
        self._solves: deque[tuple[float, int, bool]] = deque(maxlen=PACE_SOLVES)  # (seconds, iterations, stopped)
        self._cache: OrderedDict[tuple, Any] = OrderedDict()
        self._outside: deque[float] = deque(maxlen=PACE_SOLVES)  # s of each solve outside the solver's own clock
        self._outside_fit: float | None = None  # outside_clock(), of the solves recorded so far
        self._fit: tuple[float, float, float] | None = None  # cost() and iteration_time(), of the solves so far
        self._deadline: float | None = None  # perf_counter s by which the step under way must end (None: no step)
        self._tails: deque[float] = deque(maxlen=PACE_SOLVES)  # s of CPU a solve ran after its clock's last check
        self._handed_at: float | None = None  # perf_counter s the solve under way read its clock_limit (None: not)

    @classmethod
    def option_names(cls) -> frozenset[str] | None:
        """The options the solver takes (None: the solver checks them itself when it is set up)."""
        return None

    def _check_options(self, options: dict) -> None:
        own = {native: ours for ours, native in self.NATIVE.items()}
        for key in options:
            if key in own or key in BUDGET:
                raise OptionError(
                    f"{key}: the budget is given as {own.get(key, key)}=..., the same name on every "
                    f"backend (not as a solver option)"
                    if key in own
                    else f"{key}: give it as the budget {key}=..., not as a solver option"
                )
        names = self.option_names()
        unknown = [key for key in options if names is not None and key not in names]
        if unknown:
            near = difflib.get_close_matches(unknown[0], sorted(names or ()), n=1)
            hint = f"did you mean {near[0]!r}?" if near else "see the solver's documentation for its options"
            raise OptionError(f"{unknown[0]}: not an option of backend {self.name} ({hint})")

    def cost(self) -> tuple[float, float]:
        """(fixed, per iteration) CPU seconds of a solve, a bound for a cap, measured on the last solves: the fixed
        cost fitted by Theil–Sen (the median of the slopes between pairs of solves of different iteration counts,
        then the median of what each solve leaves over at that slope), the cost per iteration the largest of that
        slope and the own cost per iteration (its time less the fixed cost, over its iterations) of each solve of at
        least :data:`BOUND_ITERATIONS`: an active-set solver's iterations cost several times more in one solve than
        in another (DAQP's at N = 10: 0.01 to 0.09 ms, measured), so a slope fitted to them all undershoots the
        dearest, which a cap must cover (a short solve's own cost is left out: the fixed cost's noise over a few
        iterations would lower the cap, which shortens the solves, which lowers it further). With one iteration
        count only, no fixed cost. (0, 0) before any solve. Fitted once per solve recorded."""
        return self._fits()[:2]

    def iteration_time(self) -> float:
        """The typical cost of one iteration (s of CPU): the Theil–Sen slope of :meth:`cost`, not its bound (what a
        solver with a clock may run past its limit: one iteration)."""
        return self._fits()[2]

    def _fits(self) -> tuple[float, float, float]:
        if self._fit is None:
            self._fit = self._fitted()
        return self._fit

    def _fitted(self) -> tuple[float, float, float]:
        if not self._solves:
            return 0.0, 0.0, 0.0
        done = [(t, k) for t, k, stopped in self._solves if not stopped]
        if not done:  # only solves its clock stopped: their whole cost per iteration, an overestimate
            per_iteration = float(np.median([t / max(k, 1) for t, k, _ in self._solves]))
            return 0.0, per_iteration, per_iteration
        t, k = (np.array(v, dtype=float) for v in zip(*done))
        k = np.maximum(k, 1.0)
        dk, dt = k[:, None] - k[None, :], t[:, None] - t[None, :]
        apart = dk > 0
        fixed, slope = 0.0, float(np.median(t / k))  # one iteration count (or no rising cost): no fixed cost
        if apart.any() and np.median(dt[apart] / dk[apart]) > 0:
            slope = float(np.median(dt[apart] / dk[apart]))
            fixed = max(0.0, float(np.median(t - slope * k)))
        long = k >= BOUND_ITERATIONS
        own = float(np.max((t[long] - fixed) / k[long])) if long.any() else 0.0
        return fixed, max(slope, own), slope

    def record_pace(self, seconds: float, iterations: int, stopped: bool = False) -> None:
        """Count a solve (not a structure's first) of ``iterations`` that took ``seconds`` of the CPU
        (``time.thread_time``: a solve held up by the machine is not a dearer one) towards :meth:`cost`.
        ``stopped``: the solver's own clock ended it, so its time is the limit it was handed, whatever its
        iterations cost: left out of the fit while a solve that ran its course is in the window (such solves,
        their times alike and their counts apart, flattened the slope to a tenth of an iteration's cost and
        Clarabel's steps ran past their limit by up to 1.2 ms, measured)."""
        if iterations >= 1:
            self._solves.append((seconds, iterations, stopped))
            self._fit = None

    @contextmanager
    def step_within(self, start: float) -> Iterator[None]:
        """A step started at ``start`` (``time.perf_counter()`` s): until it ends, every solve shares the time limit
        from there (:meth:`time_left`); a step opened inside another keeps the outer one's deadline."""
        outer = self._deadline
        if self.time_limit is not None and outer is None:
            self._deadline = start + self.time_limit
        try:
            yield
        finally:
            self._deadline = outer

    def set_up_within_step(self, seconds: float) -> None:
        """A set-up of ``seconds`` (a structure's, once; a step rebuilt for a new cap) inside the step under way:
        not the step's time, so its deadline moves by as much."""
        if self._deadline is not None:
            self._deadline += seconds

    def time_left(self) -> float | None:
        """Seconds left of the time limit (None: no limit): of the step under way, else the whole limit."""
        if self.time_limit is None:
            return None
        return self.time_limit if self._deadline is None else self._deadline - time.perf_counter()

    def outside_clock(self) -> float:
        """Seconds a solve spends outside the solver's own clock once it has read its :meth:`clock_limit` (handing
        the solver the data, reading the answer back): :data:`PACE_MARGIN` × the median, over the last solves, of
        each one's time from that read less the solve time its solver reported (0 before any, or for a solver that
        reports none). Not the largest: one slow solve would leave the next ones no time at all (measured with
        CVXPY's canonicalisation inside: runs of 33 failed steps); CVXPY now reads it after canonicalising."""
        if self._outside_fit is None:
            self._outside_fit = PACE_MARGIN * float(np.median(self._outside)) if self._outside else 0.0
        return self._outside_fit

    def record_tail(self, seconds: float) -> None:
        """Count ``seconds`` of the CPU a solve spent after its solver last read its clock, work the solver does
        not stop on its limit (OSQP's polish of a solved QP, its refactorisation for a new rho), towards
        :meth:`tail`."""
        if seconds > 0:
            self._tails.append(seconds)

    def tail(self) -> float:
        """The dearest of the recent solves' tails (:meth:`record_tail`; 0 before any): what a solver with a clock
        may still run once its clock has said the solve fits, not covered by one iteration."""
        return max(self._tails, default=0.0)

    def clock_limit(self) -> float | None:
        """The limit a solver with a clock is handed for the solve about to run: the :meth:`time_left` less what
        the solve will spend outside the solver's clock (:meth:`outside_clock`) and less :data:`PACE_MARGIN` × its
        typical cost per iteration (:meth:`iteration_time`: a solver reads its clock once an iteration, so it stops
        up to one iteration past its limit; the bound of :meth:`cost` there cost CVXPY's steps at N = 5 runs of up
        to 60 failed solves) and less :data:`PACE_MARGIN` × its :meth:`tail`, the dearest recent work it did after
        its last clock check, at least :data:`MIN_SLICE` (None: no limit). The read is remembered: the solve's time
        outside its solver's clock is measured from it."""
        left = self.time_left()
        if left is None:
            return None
        self._handed_at = time.perf_counter()
        reserve = self.outside_clock() + PACE_MARGIN * (self.iteration_time() + self.tail())
        return max(left - reserve, MIN_SLICE)

    def iteration_cap(self, left: float | None = None) -> int:
        """The iteration cap of the next solve: ``max_iter`` (else the class's), and for a solver without a clock
        under a time limit what fits in ``left`` seconds (by default the :meth:`time_left`): that less the fixed
        :meth:`cost` over :data:`PACE_MARGIN` × the cost per iteration (:data:`FIRST_CAP` before a solve is
        measured)."""
        cap = self.max_iter or self.MAX_ITER
        left = self.time_left() if left is None else left
        if left is None or self.CLOCK:
            return cap
        fixed, per_iteration = self.cost()
        if per_iteration <= 0:
            return min(cap, FIRST_CAP)
        return max(1, min(cap, math.floor((left - fixed) / (PACE_MARGIN * per_iteration))))

    # What a concrete backend supplies.
    def setup(self, data) -> Any:
        """Build the solver for ``data``'s structure; returns the state kept for that key."""
        raise NotImplementedError

    def update(self, state: Any, data) -> None:
        """Hand the solver kept in ``state`` the new numbers of ``data`` (same structure)."""

    def run(self, state: Any, data, warm: WarmStart) -> Solution:
        """Solve; a :class:`Solution` with status, message, x, formulation_objective, iterations, duals."""
        raise NotImplementedError

    def certify(self, state: Any, data, result: Solution) -> Certificate | None:
        """The certificate of ``result`` (a solution with an x), computed after the solve's time is taken: our work,
        not the solver's. Here a QP's, from its data and the returned multipliers (None without them)."""
        y = result.duals.y
        if result.x is None or y is None or not isinstance(data, QPData) or len(y) != data.A.shape[0]:
            return result.certificate
        return qp_certificate(data.P, data.q, data.A, data.l, data.u, result.x, y, data.cones)

    # The shared lifecycle.
    def prepared(self, data) -> tuple[Any, bool]:
        """The solver set up for ``data``'s key, and whether it was set up by this call (else kept from an earlier
        one): what :meth:`solve` and a control loop's step (:mod:`mpc_hunt.solving.step`) share."""
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
                self.set_up_within_step(setup_time)
            cpu, self._handed_at = time.thread_time(), None
            if not new:
                self.update(state, data)
            result = self.run(state, data, warm or WarmStart())
        except (RuntimeError, ValueError, ArithmeticError) as exc:  # the solver library gave up
            self._cache.pop(data.key, None)
            message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            return Solution(
                status=Status.ERROR,
                message=message,
                backend=self.name,
                solver_time=time.perf_counter() - t0,
                setup_time=setup_time,
            )
        solver_time = time.perf_counter() - t0
        left = self.time_left()  # read before our own work on the answer (the certificate): not the solver's time
        overran = left is not None and (left < 0 if self._deadline is not None else solver_time > left)
        if not new:
            self.record_pace(
                time.thread_time() - cpu, result.iterations, self.CLOCK and result.status is Status.TIME_LIMIT
            )
            reported = result.extras.get("reported_solve_time_s")
            if reported is not None:  # from the clock_limit read (what came before it was out of the time left)
                since = solver_time if self._handed_at is None else t0 + solver_time - self._handed_at
                self._outside.append(max(since - float(reported), 0.0))
                self._outside_fit = None
        if result.x is not None and not np.all(np.isfinite(result.x)):
            result = replace(result, x=None, formulation_objective=None, message=f"{result.message} (non-finite x)")
        if result.x is None and result.status.usable:
            result = replace(result, status=Status.ERROR, message=f"{result.message} (no solution returned)")
        if result.x is not None:
            result = replace(result, certificate=self.certify(state, data, result))
        if overran and result.status.usable:
            result = replace(
                result,
                status=Status.TIME_LIMIT,
                message=f"{result.message}, after {solver_time:.3g} s: past the {self.time_limit:g} s limit",
            )
        return replace(result, backend=self.name, solver_time=solver_time, setup_time=setup_time)

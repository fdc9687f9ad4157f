"""Stopping a solver between two of its iterations once what is left of the step's limit would not fit another.

A solver handed a time limit reads its clock once an iteration, so it ends up to one iteration past it. One that
calls back after each iteration (IPOPT's iteration callback, Clarabel's termination callback) is stopped instead
when the time left would not fit :data:`~mpc_hunt.capture.iteration.PACE_MARGIN` times the longest iteration of
this solve, or of the last :data:`RECENT_SOLVES` solves (which budget a solve's first iteration), plus the
dearest work those solves did after their last call back (IPOPT's finish: 0.5 ms typically, once 4.7 ms, measured
at N = 1 and 5): the iterations timed as they run, not a cost fitted to earlier solves.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Iterator
from contextlib import contextmanager

from mpc_hunt.capture.iteration import PACE_MARGIN

RECENT_SOLVES = 8  # the solves whose longest iteration budgets a new solve's first (under a time limit)


class IterationDeadline:
    """The deadline of the solve under way and the iterations timed so far (the module's docstring)."""

    def __init__(self) -> None:
        self.until = float("inf")
        self.last = self.longest = self.carried = self.cpu = self.reserve = 0.0
        self.called = False  # whether the solve under way has called back yet
        self.earlier: deque[float] = deque(maxlen=RECENT_SOLVES)  # the longest iteration of each recent solve
        self.tails: deque[float] = deque(maxlen=RECENT_SOLVES)  # s of CPU each ran after its last call back

    def start(self, left: float) -> None:
        """A solve starts with ``left`` seconds of its step's limit; its first iteration is budgeted as the
        longest of the recent solves' (the one before it ended on that iteration's clock)."""
        if self.longest > 0:
            self.earlier.append(self.longest)
        self.last, self.cpu, self.called = time.perf_counter(), time.thread_time(), False
        self.until, self.longest, self.carried = self.last + left, 0.0, max(self.earlier, default=0.0)
        self.reserve = max(self.tails, default=0.0)

    def passed(self) -> bool:
        """Called after each iteration: whether the solve stops here, the time left not fitting another."""
        now = time.perf_counter()
        self.longest, self.last, self.cpu = max(self.longest, now - self.last), now, time.thread_time()
        self.called = True
        return self.until - now < PACE_MARGIN * max(self.longest, self.carried) + self.reserve

    def finish(self) -> None:
        """Called when the solve has returned: what it ran after its last call back (on the CPU: a finish held up
        by the machine is not a dearer one) is reserved in the next solves; a solve that never called back (a
        solver made anew, without the callback) measured none."""
        if self.called:
            self.tails.append(time.thread_time() - self.cpu)


@contextmanager
def watched(deadline: IterationDeadline | None, left: float | None) -> Iterator[None]:
    """The solve inside the block watched by ``deadline`` from ``left`` seconds of its step's limit (started, then
    finished once it has returned); nothing without a deadline or a limit."""
    if deadline is None or left is None:
        yield
        return
    deadline.start(left)
    yield
    deadline.finish()

"""Python's garbage collector held off during a hunt's steps and run between them, as a real-time loop runs it.

The cyclic collector runs when allocations pass a threshold, wherever that falls: a full collection in a process
holding CVXPY's expression trees takes tens of milliseconds of CPU (33 ms measured in an own-loop hunt of
``socp`` on CVXPY at N = 10, whose step then ran 52 ms past its 20 ms limit on the CPU), which would land in
whichever step's solve tripped it. A robot's control loop holds the collector off and collects in its idle time,
after a step's command is sent and before the next tick: :func:`collecting_between_steps` does the same for a
simulated hunt. Automatic collection is off for the hunt; after each step the hunt calls ``collect()``, which runs
the generation the collector itself would have run by now (the oldest whose count is past its threshold), so that
nothing is collected less, only at another moment.
"""

from __future__ import annotations

import gc
from collections.abc import Callable, Iterator
from contextlib import contextmanager


def collect_due() -> None:
    """Collect the oldest generation whose count is past its threshold (none when none is)."""
    counts, thresholds = gc.get_count(), gc.get_threshold()
    due = [g for g in range(len(thresholds)) if thresholds[g] and counts[g] > thresholds[g]]
    if due:
        gc.collect(max(due))


@contextmanager
def collecting_between_steps() -> Iterator[Callable[[], None]]:
    """``with collecting_between_steps() as collect: ...`` — automatic collection off inside (restored after, as it
    was), ``collect()`` to run between steps."""
    was_on = gc.isenabled()
    gc.disable()
    try:
        yield collect_due if was_on else (lambda: None)
    finally:
        if was_on:
            gc.enable()

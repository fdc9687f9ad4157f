"""A control step's timed section: Python's garbage collector held off until it ends, its time off the CPU measured.

A step that overran its time limit did so either because its code ran long or because the machine took its core
away (another process ran, or it waited on the disk): the first is the solver's and ours to bound, the second the
machine's, which a robot's control loop avoids by running on a core of its own under a real-time scheduler. The
process's CPU time (``time.process_time``, every thread's) tells them apart: the wall time less the CPU time over
the step is its time off the CPU (if anything too small, as it counts threads running beside the step).

Python's cyclic garbage collector runs when allocations pass a threshold, wherever that falls: a full collection
of a process holding CVXPY's expression trees takes tens of milliseconds of CPU, which would land in whichever step
tripped it. As real-time Python loops do, the collector is held off while the step runs and runs, if due, after
it: between steps, where a robot's loop idles until its next tick. Nothing is collected less, only later.
"""

from __future__ import annotations

import gc
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass


@dataclass
class StepTiming:
    off_cpu: float = 0.0  # s: wall time less CPU time over the step, at least 0 (set when the step ends)


@contextmanager
def timed_step() -> Iterator[StepTiming]:
    """``with timed_step() as timing: ...`` then ``timing.off_cpu``; the collector, if it was on, is off inside."""
    timing = StepTiming()
    collecting = gc.isenabled()
    gc.disable()
    wall, cpu = time.perf_counter(), time.process_time()
    try:
        yield timing
    finally:
        timing.off_cpu = max((time.perf_counter() - wall) - (time.process_time() - cpu), 0.0)
        if collecting:
            gc.enable()

"""A control step's time off the CPU: its wall time less the process's CPU time over it.

A step that overran its time limit did so either because its code ran long or because the machine took its core
away (another process ran, or it waited on the disk): the first is the solver's and ours to bound, the second the
machine's, which a robot's control loop avoids by running on a core of its own under a real-time scheduler. The
process's CPU time (``time.process_time``, every thread's) tells them apart: the wall time less the CPU time over
the step is its time off the CPU (if anything too small, as it counts threads running beside the step).
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass


@dataclass
class StepTiming:
    off_cpu: float = 0.0  # s: wall time less CPU time over the step, at least 0 (set when the step ends)


@contextmanager
def timed_step() -> Iterator[StepTiming]:
    """``with timed_step() as timing: ...`` then ``timing.off_cpu``."""
    timing = StepTiming()
    wall, cpu = time.perf_counter(), time.process_time()
    try:
        yield timing
    finally:
        timing.off_cpu = max((time.perf_counter() - wall) - (time.process_time() - cpu), 0.0)

"""A control step's time off the CPU: its wall time less the process's CPU time over it.

A step that overran its time limit did so either because its code ran long or because the machine took its core
away (another process ran, or it waited on the disk): the first is the solver's and ours to bound, the second the
machine's, which a robot's control loop avoids by running on a core of its own under a real-time scheduler. The
process's CPU time (``time.process_time``, every thread's) tells them apart: the wall time less the CPU time over
the step is its time off the CPU (if anything too small, as it counts threads running beside the step).

On a virtual machine the hypervisor can take the core from under the whole guest (its *steal* time): the guest's
clocks keep counting the process as running, so a step held up that way looks like the step's own work. The
machine's steal over a step (:func:`stolen`, read from ``/proc/stat`` in the kernel's ticks of 10 ms, summed over
its CPUs: at most the step's own, which ran on one of them) tells those apart; the simulator reads it around each
control step, outside the step's time.
"""

from __future__ import annotations

import os
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


try:
    _TICK = 1.0 / os.sysconf("SC_CLK_TCK")
except (AttributeError, ValueError, OSError):  # no sysconf: no ticks to read either
    _TICK = 0.01


def stolen() -> float:
    """Seconds the hypervisor has taken from this machine's CPUs since boot (the steal column of ``/proc/stat``'s
    first line, summed over its CPUs); 0.0 where the kernel does not report it (not Linux, not virtualised)."""
    try:
        with open("/proc/stat", "rb") as stat:
            fields = stat.readline().split()
        return int(fields[8]) * _TICK
    except (OSError, IndexError, ValueError):
        return 0.0

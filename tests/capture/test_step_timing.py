"""A step's time off the CPU: its wall time less the process's CPU time."""

from __future__ import annotations

import time

from mpc_hunt.solving.step_timing import timed_step


def test_a_step_that_waits_is_off_the_cpu_and_one_that_computes_is_not():
    start = time.perf_counter()
    with timed_step() as waiting:
        time.sleep(0.05)
    assert 0.045 < waiting.off_cpu <= time.perf_counter() - start
    start, cpu = time.perf_counter(), time.process_time()
    with timed_step() as computing:
        while time.process_time() - cpu < 0.05:  # 50 ms of CPU, however long the machine makes it take
            pass
    wall = time.perf_counter() - start
    assert abs(computing.off_cpu - max(wall - 0.05, 0.0)) < 0.005

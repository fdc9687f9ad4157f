"""A step's timed section: its time off the CPU, and the garbage collector held off inside it."""

from __future__ import annotations

import gc
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


def test_the_collector_is_held_off_inside_a_step_and_restored_after_it():
    assert gc.isenabled()
    collections = []
    gc.callbacks.append(lambda phase, info: collections.append(phase))
    try:
        with timed_step():
            assert not gc.isenabled()
            cycles = []
            for _ in range(50_000):  # far past generation 0's threshold: cycles the collector would free
                a: list = []
                a.append(a)
                cycles.append(a) if len(cycles) < 10 else None
            assert collections == []
        assert gc.isenabled()
        gc.disable()
        with timed_step():
            pass
        assert not gc.isenabled()  # off before, off after
    finally:
        gc.enable()
        gc.callbacks.pop()

"""Python's collector held off during a hunt's steps and run between them (mpc_hunt/sim/collector.py)."""

from __future__ import annotations

import gc

from conftest import capture_stage_scenario
from mpc_hunt import simulate
from mpc_hunt.control.spec import make_controller
from mpc_hunt.sim.collector import collect_due, collecting_between_steps


def cycles(count: int) -> None:
    """``count`` reference cycles made and dropped: garbage only the cyclic collector frees."""
    for _ in range(count):
        a: list = []
        a.append(a)


def test_the_collector_is_off_inside_and_restored_after():
    assert gc.isenabled()
    with collecting_between_steps():
        assert not gc.isenabled()
    assert gc.isenabled()
    gc.disable()
    try:
        with collecting_between_steps() as collect:
            collect()
        assert not gc.isenabled()  # off before: off after, and nothing collected by us
    finally:
        gc.enable()


def test_collect_runs_the_generation_that_is_due_and_none_before():
    runs: list[int] = []

    def record(phase, info):
        if phase == "start":
            runs.append(info["generation"])

    gc.callbacks.append(record)
    try:
        with collecting_between_steps() as collect:
            gc.collect()
            collect()
            assert runs == [2]  # (the full collection above): nothing was due after it
            cycles(2 * gc.get_threshold()[0])
            assert runs == [2]  # held off, however much is due
            collect()
            assert len(runs) == 2 and gc.get_count()[0] < gc.get_threshold()[0]
        collect_due()
    finally:
        gc.callbacks.remove(record)


def test_no_collection_starts_inside_a_hunts_step_and_the_hunt_collects_between_them():
    scenario = capture_stage_scenario(2.0)
    controller = make_controller("paper", scenario, formulation="qp", backend="osqp", horizon=3)
    inside, events = [False], []
    command = controller.command

    def step(observation):
        events.append("step")
        inside[0] = True
        cycles(2 * gc.get_threshold()[0])  # a step that makes more garbage than the threshold
        try:
            return command(observation)
        finally:
            inside[0] = False

    def record(phase, info):
        if phase == "start":
            events.append("inside" if inside[0] else "between")

    controller.command = step  # type: ignore[method-assign]
    gc.callbacks.append(record)
    try:
        simulate(scenario, controller)
    finally:
        gc.callbacks.remove(record)
    last = len(events) - 1 - events[::-1].index("step")
    assert "inside" not in events and "between" in events[:last]  # (not only once the hunt is over)

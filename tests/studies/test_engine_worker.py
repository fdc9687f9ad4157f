"""The engine study's worker solves each hunt's capture steps again alone: the same steps, from the same inputs and
warm starts, so the same plans (what lets the study set a hunt's cost against its steps')."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT / "studies") not in sys.path:
    sys.path.insert(0, str(ROOT / "studies"))

import engine_worker  # noqa: E402

from mpc_hunt.sim import simulator  # noqa: E402
from mpc_hunt.solving.step import CaptureStep  # noqa: E402


def _hunts():
    return [engine_worker.hunt(46, i, "trap", time_limit=2.0) for i in range(2)]


def test_the_steps_solved_alone_are_the_hunts_own():
    results, hunting, alone, solves, differ = engine_worker.with_qps_alone(_hunts())
    assert solves == sum(len(r.solve_times) for r in results) == 2 * 20
    assert differ == 0.0 and 0.0 < alone < hunting


def test_steps_solved_alone_from_other_starts_are_told_apart(monkeypatch):
    # Replayed cold (the warm start dropped outside the hunt), the real-time iteration linearises elsewhere.
    in_hunt, load, simulate = [False], CaptureStep.load, simulator.simulate

    def hunting(*args, **kwargs):
        in_hunt[0] = True
        try:
            return simulate(*args, **kwargs)
        finally:
            in_hunt[0] = False

    monkeypatch.setattr(simulator, "simulate", hunting)
    monkeypatch.setattr(CaptureStep, "load", lambda self, problem, plan=None: load(self, problem,
                                                                                   plan if in_hunt[0] else None))
    assert engine_worker.with_qps_alone(_hunts())[4] > 1e-6

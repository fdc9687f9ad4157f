"""The engine study's worker solves each hunt's capture steps again alone: the same steps, from the same inputs and
warm starts, so the same plans (what lets the study set a hunt's cost against its steps')."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
for folder in (ROOT / "studies", ROOT):
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))

import engine_worker  # noqa: E402

from mpc_hunt.sim import simulator  # noqa: E402
from mpc_hunt.solving.step import CaptureStep  # noqa: E402
from studies import engine  # noqa: E402


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


def test_the_study_gives_each_ratio_with_its_range_over_its_runs():
    def run(before_s, now_s, alone_s, route_s, route_alone_s):
        return {"before": {"hunts_per_s": 16 / before_s, "process_seconds": 2 * before_s},
                "now": {"hunts_per_s": 16 / now_s, "process_seconds": 2 * now_s, "qp_seconds": alone_s},
                "on_route": {"hunts_per_s": 16 / route_s, "process_seconds": 2 * route_s, "qp_seconds": route_alone_s}}

    first, second = engine.ratios(run(40, 30, 40, 20, 20)), engine.ratios(run(50, 30, 45, 25, 20))
    assert first == {"vs_before": 40 / 30, "whole_over_alone": 1.5, "bound": 2.0, "route_vs_before": 2.0,
                     "route_whole_over_alone": 2.0, "route_bound": 4.0}
    text = engine.spread([first, second])
    assert "against before 1.33x to 1.67x, whole / steps alone 1.33 to 1.50, the bound 2.0x to 2.2x" in text
    assert "on the DAQP step 2.00x to 2.00x, 2.00 to 2.50 and 4.0x to 5.0x" in text

"""The engine study's worker solves each hunt's capture steps again alone: the same steps, from the same inputs and
warm starts, so the same plans (what lets the study set a hunt's cost against its steps')."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

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
    results, hunting, alone, solves, differ, together = engine_worker.with_qps_alone(_hunts())
    assert solves == sum(len(r.solve_times) for r in results) == 2 * 20
    assert differ == 0.0 and 0.0 < alone < hunting
    assert together["difference"] == 0.0 and 0.0 < together["seconds"] < hunting   # in one call: the same plans


def test_one_call_solves_each_step_from_its_own_inputs():
    hunt = _hunts()[0]
    step_of = {}
    solve = hunt[1].mpc.solver.solve

    def kept(problem, plan=None, duals=None):
        step_of.setdefault("args", (problem, plan))
        return solve(problem, plan, duals)

    hunt[1].mpc.solver.solve = kept
    simulator.simulate(*hunt[:2], rng=hunt[2])
    step = hunt[1].mpc.solver.step_for(step_of["args"][0])
    step.load(*step_of["args"])
    step.step()
    other = step.reference.reshape(-1) + 0.01    # a second step's own warm start: its plan is another
    seconds, plans = engine_worker.in_one_call(step, np.array([step.theta, step.theta]),
                                               np.array([step.reference.reshape(-1), other]))
    assert seconds > 0 and np.array_equal(plans[0], step.plan.reshape(-1)) and not np.array_equal(plans[1], plans[0])


def test_a_step_that_is_not_one_casadi_function_is_not_solved_in_one_call():
    hunts = [engine_worker.hunt(46, 0, "trap:rti:daqp-condensed:10", time_limit=2.0)]
    assert engine_worker.with_qps_alone(hunts)[5] is None


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
                "now": {"hunts_per_s": 16 / now_s, "process_seconds": 2 * now_s, "qp_seconds": alone_s,
                        "one_call": {"seconds": alone_s / 1.25}},
                "on_route": {"hunts_per_s": 16 / route_s, "process_seconds": 2 * route_s, "qp_seconds": route_alone_s}}

    first, second = engine.ratios(run(40, 30, 40, 20, 20)), engine.ratios(run(50, 30, 45, 25, 20))
    assert first == {"vs_before": 40 / 30, "whole_over_alone": 1.5, "bound": 2.0, "route_vs_before": 2.0,
                     "route_whole_over_alone": 2.0, "route_bound": 4.0, "alone_over_one_call": 1.25}
    text = engine.spread([first, second])
    assert "against before 1.33x to 1.67x, whole / steps alone 1.33 to 1.50, the bound 2.0x to 2.2x" in text
    assert "on the DAQP step 2.00x to 2.00x, 2.00 to 2.50 and 4.0x to 5.0x" in text

"""One budget on every backend: time_limit and max_iter under one name each, honoured, their hits their own
statuses; options checked against what each solver takes."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import problem_at, small_scenario

from mpc_hunt import CaptureSolver, Status, make_controller
from mpc_hunt.capture.iteration import PACE_MARGIN, another_fits
from mpc_hunt.errors import MpcHuntError, OptionError
from mpc_hunt.solving import registry
from mpc_hunt.solving.backends.base import MIN_SLICE, PACE_SOLVES
from mpc_hunt.solving.backends.daqp import DaqpBackend

ATTEMPTS = 3  # a wall-clock measurement repeated on a busy machine, where a preemption only ever inflates it

INSTALLED = [b for b in registry.BACKENDS if registry.installed(b)]


def test_osqp_stops_at_max_iter_and_says_so(scenario):
    solution = CaptureSolver("qp", "osqp", max_iter=10).solve(problem_at(scenario, 10))
    assert solution.status is Status.ITERATION_LIMIT and solution.iterations == 10
    assert "max" in solution.message.lower() and "iter" in solution.message.lower()


@pytest.mark.parametrize("backend", ["osqp", "clarabel", "daqp", "cvxpy", "ipopt", "hpipm"])
def test_every_backend_takes_max_iter_by_that_name(scenario, backend):
    formulation = next(f for f in registry.FORMULATIONS if backend in registry.compatible_backends(f))
    solution = CaptureSolver(formulation, backend, max_iter=1).solve(problem_at(scenario, 5))
    assert solution.status is Status.ITERATION_LIMIT, (solution.status, solution.message)
    assert solution.iterations <= (2 if backend == "ipopt" else 1)   # IPOPT counts its initial point's too


@pytest.mark.parametrize("backend", INSTALLED)
def test_an_unknown_option_is_one_line_naming_it(backend):
    formulation = next(f for f in registry.FORMULATIONS if backend in registry.compatible_backends(f))
    with pytest.raises(MpcHuntError, match="tolerence") as caught:
        CaptureSolver(formulation, backend, tolerence=1e-6)
    assert "\n" not in str(caught.value)


@pytest.mark.parametrize("backend,native", [("daqp", "iter_limit"), ("hpipm", "iter_max"), ("ipopt", "max_wall_time"),
                                            ("ipopt", "max_cpu_time")])
def test_the_solvers_own_budget_names_point_to_ours(backend, native):
    formulation = next(f for f in registry.FORMULATIONS if backend in registry.compatible_backends(f))
    with pytest.raises(OptionError, match=f"{native}: the budget is given as (max_iter|time_limit)="):
        CaptureSolver(formulation, backend, **{native: 5})


def test_a_misspelled_setting_of_a_controller_is_refused_at_once():
    scenario = small_scenario()
    with pytest.raises(OptionError, match="formulaton"):
        make_controller("paper", scenario, formulaton="qp")
    with pytest.raises(OptionError, match="bogus"):
        make_controller("trap", scenario, bogus=1)


def test_a_usable_solve_past_its_time_limit_is_a_time_limit_not_optimal(scenario):
    # A limit no solve can meet: DAQP stops itself or finishes after it; HPIPM's step, which reads no clock, after.
    assert CaptureSolver("qp", "daqp", time_limit=1e-7).solve(problem_at(scenario, 3)).status is Status.TIME_LIMIT
    step = CaptureSolver("rti", "hpipm", time_limit=1e-7).solve(problem_at(scenario, 3))
    assert step.status is Status.TIME_LIMIT and "past the 1e-07 s limit" in step.message


def test_daqp_turns_its_time_limit_into_an_iteration_cap_from_its_measured_cost():
    backend = DaqpBackend(time_limit=0.01)
    assert backend.iteration_cap() == 100                  # nothing measured yet: the first-solve cap
    backend.record_pace(0.5e-3, 10)                        # one iteration count: 0.05 ms an iteration, no fixed cost
    assert backend.cost() == pytest.approx((0.0, 5e-5)) and backend.iteration_cap() == int(0.01 / (PACE_MARGIN * 5e-5))
    for k in (2, 4, 8, 16):                                # 1 ms fixed + 0.2 ms an iteration: both recovered
        backend.record_pace(1e-3 + 2e-4 * k, k)
    fixed, per_iteration = backend.cost()
    assert fixed == pytest.approx(1e-3, rel=0.05) and per_iteration == pytest.approx(2e-4, rel=0.05)
    assert backend.iteration_cap() == int((0.01 - fixed) / (PACE_MARGIN * per_iteration))    # (10 − 1) / 0.3: 30
    backend.record_pace(1e-3 + 6e-4 * 3, 3)                # a short solve's own cost: noise, not counted
    assert backend.cost()[1] == pytest.approx(2e-4, rel=0.05)
    backend.record_pace(1e-3 + 6e-4 * 10, 10)              # one solve's iterations three times dearer: the bound
    fixed, per_iteration = backend.cost()                  # follows the dearest, the fixed cost stays
    assert fixed == pytest.approx(1e-3, rel=0.05) and per_iteration == pytest.approx(6e-4, rel=0.05)
    assert backend.iteration_cap() == int((0.01 - fixed) / (PACE_MARGIN * per_iteration))    # (10 − 1) / 0.9: 10
    assert backend.iteration_time() == pytest.approx(2e-4, rel=0.25)   # the typical iteration: the slope
    for k in np.resize((3, 4, 5), PACE_SOLVES):            # until it leaves the solves measured
        backend.record_pace(1e-3 + 2e-4 * k, k)
    assert backend.cost()[1] == pytest.approx(2e-4, rel=0.05)
    assert DaqpBackend(time_limit=0.01, max_iter=3).iteration_cap() == 3
    assert DaqpBackend().iteration_cap() == DaqpBackend.MAX_ITER


def test_a_fixed_cost_does_not_eat_the_iterations_a_limit_leaves():
    """A step whose fixed cost (linearisation, read-back) dwarfs its iterations: the cap is what the limit leaves
    after it, not the limit over the time per iteration of short solves (which counts the fixed cost many times)."""
    backend = DaqpBackend(time_limit=0.02)
    for k in (4, 6, 8, 6, 5, 7):
        backend.record_pace(0.6e-3 + 0.08e-3 * k, k)       # ~1 ms steps of ~6 iterations
    assert backend.iteration_cap() == int((0.02 - 0.6e-3) / (PACE_MARGIN * 0.08e-3)) == 161
    assert int(0.02 / (PACE_MARGIN * np.median([(0.6e-3 + 0.08e-3 * k) / k for k in (4, 6, 8, 6, 5, 7)]))) < 80


def test_a_solve_measures_the_pace_its_cap_is_made_from(scenario):
    # HPIPM's step (an interior point: always several iterations), on its loop.
    solver = CaptureSolver("rti", "hpipm", time_limit=0.5)
    solver.solve(problem_at(scenario, 3))
    assert solver.backend.cost() == (0.0, 0.0)             # a structure's first solve is not counted
    assert solver.solve(problem_at(scenario, 3)).iterations >= 3
    fixed, per_iteration = solver.backend.cost()
    assert per_iteration > 0 and solver.backend.iteration_cap() == min(
        solver.backend.MAX_ITER, int((0.5 - fixed) / (PACE_MARGIN * per_iteration)))


def test_a_step_of_several_qps_shares_one_time_limit(scenario):
    """sqp's QPs are handed what is left of the step's limit, less their time outside the solver's clock, each less
    than the one before; once it is spent no QP starts, and the step ends ``time_limit`` with the last usable plan."""
    solver = CaptureSolver("sqp", "osqp", time_limit=5.0)
    handed, clock, fixed, solved = [], [], [], []
    solve = solver.backend.solve

    def recording(data, warm=None):
        clock.append(solver.backend.time_left())
        fixed.append(solver.backend.outside_clock())
        handed.append(solver.backend.clock_limit())       # read last: the clock has only moved on
        solved.append(solve(data, warm))
        return solved[-1]

    solver.backend.solve = recording
    problem = problem_at(scenario, 10)
    solver.solve(problem)                                  # the structure's set-up: not the step's time
    handed.clear(), clock.clear(), fixed.clear()
    assert solver.solve(problem).status.usable and len(handed) >= 2
    assert all(a > b for a, b in zip(clock, clock[1:])) and 4.9 < clock[0] <= 5.0
    assert all(c - f - 0.5 < h <= c - f for h, c, f in zip(handed, clock, fixed)) and max(fixed) > 0

    solved.clear()                                         # one second for the first QP, then nothing left
    solver.backend.time_left = lambda: 1.0 if not solved else -1e-9
    step = solver.solve(problem)
    assert step.status is Status.TIME_LIMIT and "the step's time limit reached" in step.message
    assert len(solved) == 1 and solved[0].status.usable and step.plan is not None
    assert step.iterations == solved[0].iterations


def test_a_solver_with_a_clock_is_handed_the_time_left_and_stops_when_there_is_none(scenario):
    import time

    problem = problem_at(scenario, 10)
    for _ in range(ATTEMPTS):                              # wall clocks: the least disturbed of a few solvers
        solver = CaptureSolver("qp", "osqp", time_limit=0.5, polishing=False)
        solver.solve(problem)                              # the structure's set-up: nothing measured
        assert solver.backend.outside_clock() == 0.0 and solver.backend.clock_limit() == 0.5
        for _ in range(3):
            solver.solve(problem)
        backend = solver.backend
        outside, per_iteration = backend.outside_clock(), backend.iteration_time()
        if outside < 0.01 and per_iteration < 1e-3:
            break
    assert 0 < outside < 0.01 and 0 < per_iteration < 1e-3  # (OSQP's iteration: microseconds)
    tail = backend.tail()                                  # (a refactorisation for a new rho, if any: see below)
    assert backend.clock_limit() == pytest.approx(0.5 - outside - PACE_MARGIN * (per_iteration + tail))
    backend.record_pace(0.1, 50)                           # one dear solve: it raises the bound a cap needs,
    assert backend.cost()[1] > 1e-3 and backend.iteration_time() < 1e-3   # not what a clock's last iteration costs
    assert backend.clock_limit() == pytest.approx(0.5 - outside - PACE_MARGIN * (backend.iteration_time() + tail))
    with backend.step_within(time.perf_counter() - 1.0):   # a step whose time is spent before its QP starts
        assert backend.clock_limit() == MIN_SLICE
        late = solver.formulation.solve(problem, backend, None, None)
    assert late.status is Status.TIME_LIMIT and late.iterations <= 1
    assert backend.time_left() == 0.5                      # the step over, the limit is whole again


def test_osqps_polish_after_its_last_clock_check_is_reserved_from_the_limit_it_is_handed(scenario):
    """OSQP polishes a solved QP without reading its clock again: the dearest recent polish (its tail) is
    reserved, with the margin, from the time left it is handed."""
    solver = CaptureSolver("qp", "osqp", time_limit=0.5)   # polishing on, as the backend runs it
    problem = problem_at(scenario, 10)
    solves = [solver.solve(problem) for _ in range(4)]
    backend = solver.backend
    assert all(s.status is Status.OPTIMAL for s in solves)
    assert 0 < backend.tail() < 0.01                       # a polish of this QP: a fraction of a millisecond
    assert backend.clock_limit() == pytest.approx(
        0.5 - backend.outside_clock() - PACE_MARGIN * (backend.iteration_time() + backend.tail()))
    unpolished = CaptureSolver("qp", "osqp", time_limit=0.5, polishing=False, adaptive_rho=False)
    for _ in range(3):
        unpolished.solve(problem)
    assert unpolished.backend.tail() == 0.0                # nothing past its clock: nothing reserved


def test_the_work_after_a_solvers_last_call_back_is_reserved_in_the_next_solves():
    """What a solve ran after its last iteration's call back (IPOPT's and Clarabel's finish), on the CPU, is
    reserved in the next solves' stops: a solve stops once the time left would not fit it beside an iteration."""
    import time

    from mpc_hunt.solving.backends.iteration_deadline import RECENT_SOLVES, IterationDeadline

    def busy(seconds: float) -> None:  # CPU time, as the finish is measured
        end = time.thread_time() + seconds
        while time.thread_time() < end:
            pass

    deadline = IterationDeadline()
    deadline.start(10.0)
    busy(0.02)
    deadline.finish()                                       # never called back (a solver made anew): no finish
    assert not deadline.tails
    deadline.start(10.0)
    assert not deadline.passed()
    busy(0.02)                                              # 20 ms of work after the last call back
    deadline.finish()
    deadline.start(0.03)                                    # 30 ms left: an iteration of ~0 ms and 20 ms fit
    assert not deadline.passed()
    deadline.finish()
    deadline.start(0.015)                                   # 15 ms left would not fit the 20 ms finish
    assert deadline.passed()
    deadline.finish()
    for _ in range(RECENT_SOLVES):                          # quick finishes push the dear one out
        deadline.start(10.0)
        deadline.passed()
        deadline.finish()
    deadline.start(0.015)
    assert not deadline.passed()


def test_solves_a_clock_stopped_do_not_flatten_the_cost_of_an_iteration():
    """A solve its own clock stopped took the limit it was handed whatever its iterations cost: fitted with the
    others, a run of them (alike in time, apart in iterations) pulls the slope towards zero and with it the margin
    left for a clock's last iteration."""
    from mpc_hunt.solving.backends.clarabel import ClarabelBackend

    backend = ClarabelBackend(time_limit=0.02)
    for k in (6, 8, 10, 12):
        backend.record_pace(1e-3 + 0.5e-3 * k, k)          # ran their course: 0.5 ms an iteration
    for k in range(30, 38):
        backend.record_pace(0.018, k, stopped=True)        # stopped at the 18 ms handed, 30 to 37 iterations
    assert backend.iteration_time() == pytest.approx(0.5e-3)
    only_stopped = ClarabelBackend(time_limit=0.02)
    for k in (30, 36):
        only_stopped.record_pace(0.018, k, stopped=True)  # nothing else: their whole cost per iteration
    assert only_stopped.iteration_time() == pytest.approx(np.median([0.018 / 30, 0.018 / 36]))


def test_a_solve_its_clock_stopped_is_recorded_as_stopped(scenario, monkeypatch):
    solver = CaptureSolver("qp", "clarabel", time_limit=0.5)
    problem = problem_at(scenario, 10)
    solver.solve(problem)                                  # the structure's set-up: nothing measured
    full = solver.solve(problem).extras["reported_solve_time_s"]
    assert [stopped for _, _, stopped in solver.backend._solves] == [False]
    monkeypatch.setattr(solver.backend, "clock_limit", lambda: full / 2)   # Clarabel's clock stops it half-way
    stopped = solver.solve(problem)
    assert stopped.status is Status.TIME_LIMIT and stopped.iterations >= 1
    assert [stopped for _, _, stopped in solver.backend._solves] == [False, True]


def test_the_time_outside_a_solvers_clock_is_measured_from_the_limit_it_is_handed(scenario, monkeypatch):
    """CVXPY writes its data, then reads the time left and hands it to Clarabel, then reads the answer back: what
    is subtracted from the time left is the margin times the median of each solve's time from that read less the
    solver's reported time, so the canonicalisation before the read, already out of the time left, is not. Its
    canonicalisation made 0.1 s longer here, so the two cannot be confused on a busy machine either."""
    import time

    import cvxpy as cp

    canonicalise = cp.Problem.get_problem_data

    def slow(*args, **kwargs):
        time.sleep(0.1)
        return canonicalise(*args, **kwargs)

    monkeypatch.setattr(cp.Problem, "get_problem_data", slow)
    solver = CaptureSolver("qp", "cvxpy", time_limit=1.0)
    problem = problem_at(scenario, 3)
    solver.solve(problem)
    solves = [solver.solve(problem) for _ in range(5)]
    assert min(s.solver_time - s.extras["reported_solve_time_s"] for s in solves) > 0.1      # the sleep is in
    assert 0 < solver.backend.outside_clock() < PACE_MARGIN * 0.1 / 2                       # and not out of it


@pytest.mark.parametrize("left,spent,count,starts", [
    (None, 9.0, 3, True),       # no limit
    (1e-9, 5.0, 0, True),       # the first QP always runs
    (0.016, 0.010, 1, True),    # 16 ms left, QPs of 10 ms: 1.5 × 10 = 15 fits
    (0.014, 0.010, 1, False),   # 14 ms does not
    (0.016, 0.030, 3, True),
    (-1.0, 0.001, 2, False),
])
def test_a_further_qp_starts_only_when_the_time_left_covers_the_margin_times_the_mean_qp(left, spent, count, starts):
    assert another_fits(left, spent, count) is starts


def test_a_stage_step_starts_no_qp_that_would_not_fit(scenario, monkeypatch):
    """HPIPM's step reads no clock: once started a QP runs to its cap, so the loop starts one only if it fits."""
    solver = CaptureSolver("stage-sqp", "hpipm", time_limit=5.0)
    problem = problem_at(scenario, 5)
    solver.solve(problem)
    loop = solver.step_for(problem)
    monkeypatch.setattr(solver.backend, "time_left", lambda: 1e-9)   # never enough for a second QP
    loop.load(problem)
    assert loop.step() is Status.TIME_LIMIT and loop.qps == 1


def test_ipopt_stops_when_the_time_left_would_not_fit_another_iteration(scenario):
    """IPOPT's own max_wall_time is fixed when CasADi builds it and read once an iteration: under a step's limit
    its iteration callback stops it first, as a time_limit, when what is left would not fit another iteration."""
    import time

    solver = CaptureSolver("nlp", "ipopt", time_limit=5.0)
    problem = problem_at(scenario, 5)
    assert solver.solve(problem).status is Status.OPTIMAL       # 5 s: the callback lets it converge
    with solver.backend.step_within(time.perf_counter() - 5.0 + 1e-4):   # 0.1 ms left of the step
        late = solver.formulation.solve(problem, solver.backend, None, None)
    assert late.status is Status.TIME_LIMIT and late.message == "User_Requested_Stop" and late.iterations <= 1


def test_clarabel_stops_when_the_time_left_would_not_fit_another_iteration(scenario):
    """Clarabel reads its clock once an iteration; under a step's limit its termination callback stops it first,
    as a time_limit, when what is left would not fit another iteration (here: one iteration's time left)."""
    import time

    solver = CaptureSolver("socp", "clarabel", time_limit=5.0)
    problem = problem_at(scenario, 10)
    solver.solve(problem)                                   # the structure's set-up
    full = solver.solve(problem)
    assert full.status is Status.OPTIMAL and full.iterations > 3   # 5 s: the callback lets it converge
    one = full.extras["reported_solve_time_s"] / full.iterations   # about one iteration
    with solver.backend.step_within(time.perf_counter() - 5.0 + 2 * one):
        late = solver.formulation.solve(problem, solver.backend, None, None)
    assert late.status is Status.TIME_LIMIT and late.message == "CallbackTerminated"
    # Its time is its set-up before the first check (the KKT system's factorisation: 2-4 ms on a loaded machine,
    # measured) and no more: less than the full solve's.
    assert late.iterations < full.iterations and late.solver_time < full.solver_time


def test_cvxpy_stops_clarabel_by_its_callback_when_the_time_left_would_not_fit_another_iteration(scenario):
    """CVXPY keeps the Clarabel solver it made and updates it for the next solve: the deadline's callback is set on
    it, so under a step's limit it stops between iterations, as a time_limit, as Clarabel run directly does."""
    import time

    solver = CaptureSolver("socp", "cvxpy", time_limit=5.0)
    problem = problem_at(scenario, 10)
    solver.solve(problem)                                   # the structure's set-up: CVXPY makes its solver
    full = solver.solve(problem)
    assert full.status is Status.OPTIMAL and full.iterations > 3   # 5 s: the callback lets it converge
    one = full.extras["reported_solve_time_s"] / full.iterations
    with solver.backend.step_within(time.perf_counter() - 5.0 + 2 * one):
        late = solver.formulation.solve(problem, solver.backend, None, None)
    assert late.status is Status.TIME_LIMIT and late.message == "CallbackTerminated (CLARABEL)"
    assert late.iterations < full.iterations


def test_ipopt_budgets_a_solves_first_iteration_as_the_recent_solves_longest():
    """Before its first iteration a solve has measured none: the callback budgets it as the longest iteration of the
    recent solves, so a solve whose time left would not fit that one stops at once; one solve's own longest does not
    carry past RECENT_SOLVES solves."""
    import time

    from mpc_hunt.solving.backends.ipopt import _deadline
    from mpc_hunt.solving.backends.iteration_deadline import RECENT_SOLVES

    deadline = _deadline(1, 1, 1)
    stop = bytearray(8)

    def iteration(after: float = 0.0) -> float:
        time.sleep(after)
        deadline.eval_buffer(None, [stop])
        return memoryview(stop).cast("d")[0]

    deadline.pace.start(10.0)
    assert iteration(0.05) == 0.0                           # 10 s left: on it goes; its iteration took 50 ms
    deadline.pace.start(0.06)                                    # 60 ms left < 1.5 × 50 ms: no iteration started
    assert iteration() == 1.0
    for _ in range(RECENT_SOLVES):                          # solves of short iterations push the long one out
        deadline.pace.start(10.0)
        iteration(0.001)
    deadline.pace.start(0.06)
    assert iteration() == 0.0


def test_the_interpreted_hpipm_step_is_rebuilt_once_its_cap_no_longer_fits(scenario, monkeypatch):
    """CasADi fixes HPIPM's ``iter_max`` when the step is built, before any solve is measured; once the measured
    cost says that fewer iterations fit in the limit, the loop rebuilds the step with three quarters of them (a
    set-up, not the step's time), and its steps stop there; once twice its cap fits again, it is raised."""
    problem = problem_at(scenario, 3)
    solver = CaptureSolver("rti", "hpipm", time_limit=0.5)
    free = solver.solve(problem)
    assert free.success and free.iterations > 3 and free.setup_time > 0          # built with the first cap: 100
    again = solver.solve(problem)
    assert again.success and again.setup_time == 0                               # nothing measured says otherwise
    monkeypatch.setattr(solver.backend, "cost", lambda: (0.0, 0.05))              # 0.05 s an iteration: 6 fit
    capped = solver.solve(problem)                                                # rebuilt with 3/4 of them: 4
    assert capped.setup_time > 0 and capped.status is Status.ITERATION_LIMIT and capped.iterations == 4
    assert capped.solve_time < capped.setup_time + 0.5
    kept = solver.solve(problem)
    assert kept.setup_time == 0 and kept.iterations == 4                          # rebuilt once, not at each step
    monkeypatch.setattr(solver.backend, "cost", lambda: (0.0, 0.045))             # 7 fit: under twice the cap
    assert solver.solve(problem).setup_time == 0
    monkeypatch.setattr(solver.backend, "cost", lambda: (0.0, 0.005))             # the dear solves gone: 66 fit
    raised = solver.solve(problem)                                                # rebuilt with 49
    assert raised.setup_time > 0 and raised.success and raised.iterations == free.iterations


def test_a_step_starts_no_qp_whose_fixed_cap_would_not_fit_what_is_left(scenario, monkeypatch):
    """stage-sqp on the interpreted HPIPM step: once a QP has run, a further one starts only if its longest (the
    fixed cost and its cap at the measured bound per iteration: it reads no clock) fits in what is left."""
    problem = problem_at(scenario, 3)
    solver = CaptureSolver("stage-sqp", "hpipm", time_limit=0.5)
    solver.solve(problem)                                                         # set up: nothing measured
    assert solver.solve(problem).extras["qps"] > 1                                # its QPs fit: several run
    step = solver.step_for(problem).step_function
    monkeypatch.setattr(solver.backend, "cost", lambda: (0.01, 0.002))
    assert step.cap == 100 and solver.backend.longest_qp(step) == pytest.approx(0.01 + 100 * 0.002)
    monkeypatch.setattr(solver.backend, "longest_qp", lambda step: 0.6)           # more than the whole limit
    one = solver.solve(problem)
    assert one.extras["qps"] == 1 and one.status is Status.TIME_LIMIT

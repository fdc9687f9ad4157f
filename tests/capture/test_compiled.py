"""The compiled step (``hpipm-codegen``): the interpreted ``rti``/``hpipm`` step's plan, built once, never required."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from conftest import ATTACKER, small_scenario
from mpc_hunt import CaptureProblem, CaptureSolver
from mpc_hunt.solving import compiled
from mpc_hunt.solving.backends import hpipm_codegen

# One defender inside R_agg, one held outside it, one obstacle, N = 2: a structure gcc compiles in seconds.
DEFENDERS = ATTACKER + np.array([[0.7, 0.0], [-3.0, 0.0]])


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("MPC_HUNT_CACHE", str(tmp_path))
    return tmp_path


def _problem() -> CaptureProblem:
    return CaptureProblem.at_state(small_scenario(defenders=2), ATTACKER, DEFENDERS, horizon=2)


@pytest.mark.parametrize("level", ["-O1", "-O3"])
def test_the_compiled_step_takes_the_interpreted_steps_iterations_to_its_plan(cache, level):
    """HPIPM's options the generator leaves unset are its defaults. Unset, they hold what the stack held, which
    may happen to work: gcc's -ftrivial-auto-var-init=pattern fills them with a fixed pattern, and then HPIPM runs
    to its iteration limit at -O1 and at -O3 (checked with the defaults taken out of the patch)."""
    problem = _problem()
    interpreted = CaptureSolver("rti", "hpipm").solve(problem)
    with warnings.catch_warnings():
        warnings.simplefilter("error", compiled.CompilationWarning)
        solver = CaptureSolver("rti", "hpipm-codegen", flags=(level, "-ftrivial-auto-var-init=pattern", "-fPIC", "-shared"))
        first, again = solver.solve(problem), solver.solve(problem)      # HPIPM's memory, allocated once, reused
    assert interpreted.success and first.success and again.success, (first.message, again.message)
    assert first.iterations == interpreted.iterations
    np.testing.assert_allclose(first.plan, interpreted.plan, atol=1e-9)
    np.testing.assert_array_equal(again.plan, first.plan)
    assert len(list(cache.glob("step-*.so"))) == 1


def test_a_cached_step_is_loaded_not_built_again(cache, monkeypatch):
    problem = _problem()
    built = CaptureSolver("rti", "hpipm-codegen").solve(problem)

    def no_compiler(*args, **kwargs):
        raise AssertionError(f"compiled again: {args[0]}")

    monkeypatch.setattr(compiled.subprocess, "run", no_compiler)
    loaded = CaptureSolver("rti", "hpipm-codegen").solve(problem)
    np.testing.assert_array_equal(loaded.plan, built.plan)


@pytest.mark.parametrize("cc", ["/nonexistent/cc", "false"])
def test_without_a_compiler_or_with_a_failing_one_the_interpreted_step_runs_after_one_warning(cache, monkeypatch,
                                                                                                  cc):
    monkeypatch.setenv("CC", cc)
    problem = _problem()
    with pytest.warns(compiled.CompilationWarning, match="runs interpreted") as caught:
        solver = CaptureSolver("rti", "hpipm-codegen")
        plans = [solver.solve(problem).plan for _ in range(2)]
    assert len(caught) == 1
    np.testing.assert_array_equal(plans[0], CaptureSolver("rti", "hpipm").solve(problem).plan)
    assert not list(cache.glob("step-*.so"))


def test_a_generator_that_writes_otherwise_is_refused_not_patched_blindly():
    with pytest.raises(RuntimeError, match="mode"):
        hpipm_codegen.patch("int main(void) { return 0; }")


def test_the_compiled_steps_cap_is_the_one_its_time_left_allows_at_each_call(cache, monkeypatch):
    """Its generated cap is a number in the code; each call takes the backend's cap of the moment, at most that
    one, so that under a time limit the cap follows the measured cost (the interpreted step is rebuilt instead)."""
    problem = _problem()
    solver = CaptureSolver("rti", "hpipm-codegen")
    free = solver.solve(problem)
    assert free.success and free.iterations > 2
    monkeypatch.setattr(solver.backend, "iteration_cap", lambda: 2)
    capped = solver.solve(problem)
    assert capped.status.value == "iteration_limit" and capped.iterations == 2
    monkeypatch.setattr(solver.backend, "iteration_cap", lambda: 10_000)  # above the generated cap: that one
    again = solver.solve(problem)
    assert again.success and again.iterations == free.iterations
    np.testing.assert_array_equal(again.plan, free.plan)

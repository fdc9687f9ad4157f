"""The hunt's record of its capture stage in its loop: per solve, its set-up, status, certificate and the applied
plan's true violations; a deadline checked when the hunt starts."""

from __future__ import annotations


import numpy as np
import pytest

from conftest import capture_stage_scenario
from mpc_hunt import simulate
from mpc_hunt.control.spec import make_controller
from mpc_hunt.errors import OptionError


def test_every_solve_is_recorded_with_its_set_up_status_certificate_and_violations():
    scenario = capture_stage_scenario(2.0)
    result = simulate(scenario, make_controller("paper", scenario, formulation="qp", backend="daqp", horizon=3,
                                                score=True), deadline=1.0)
    n = len(result.solve_times)
    assert n > 0 and len(result.setup_times) == len(result.solve_statuses) == len(result.certificates) == n
    assert result.setup_times[0] > 0 and np.all(result.setup_times[1:] == 0)     # one structure, set up once
    assert not np.any(np.isnan(result.certificates)) and not np.any(np.isnan(result.applied_violations))
    assert result.to_dict()["solve_time"]["deadline_misses"]["over_deadline"] == 0


@pytest.mark.parametrize("deadline", [0.0, -1.0, float("inf"), float("nan"), True, "0.02"])
def test_a_deadline_that_is_no_duration_is_refused(deadline):
    with pytest.raises(OptionError, match="deadline"):
        simulate(capture_stage_scenario(2.0), deadline=deadline)

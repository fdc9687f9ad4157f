"""The separation filter keeps every pair of defenders apart in every stage (mpc_hunt/world/separation.py)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from mpc_hunt.world.geometry import norm
from mpc_hunt.world.separation import keep_separation
from strategies import FAST, floats

T, SPEED, D_SEP = 0.1, 0.08, 0.2


positions = st.lists(st.tuples(floats(min_value=0.0, max_value=1.5), floats(min_value=0.0, max_value=1.5)),
                     min_size=2, max_size=6).map(np.array)
velocities = st.lists(st.tuples(floats(min_value=-SPEED, max_value=SPEED),
                                floats(min_value=-SPEED, max_value=SPEED)), min_size=6, max_size=6).map(np.array)


@FAST
@given(positions, velocities, st.integers(min_value=0, max_value=63))
def test_after_the_step_no_pair_is_closer_than_before_or_than_d_sep(p, v, mask):
    n = len(p)
    unplanned = np.array([(mask >> i) & 1 == 1 for i in range(n)])
    planned_next = p + T * v[:n]           # planned defenders go where their plan says
    out = keep_separation(p, v[:n], unplanned, planned_next, T, np.full(n, SPEED), D_SEP)
    after = np.where(unplanned[:, None], p + T * out, planned_next)
    for i in np.flatnonzero(unplanned):
        for j in range(n):
            if j != i:
                now = norm(p[i] - (p[j] if unplanned[j] else planned_next[j]))   # never worse than now
                assert norm(after[i] - after[j]) >= min(D_SEP, now) - 1e-9, (i, j)
    assert np.all(norm(out[unplanned]) <= SPEED + 1e-12)
    np.testing.assert_array_equal(out[~unplanned], v[:n][~unplanned])


def test_head_on_defenders_slide_instead_of_meeting():
    p = np.array([[0.0, 0.0], [0.21, 0.0]])
    v = np.array([[SPEED * 0.8, SPEED * 0.6], [-SPEED, 0.0]])   # closing: 0.21 → 0.194 without the filter
    out = keep_separation(p, v, np.array([True, True]), p, T, np.full(2, SPEED), D_SEP)
    assert norm((p[0] + T * out[0]) - (p[1] + T * out[1])) >= D_SEP - 1e-12
    assert out[0][1] > 0.0                                       # the sideways part survives


def test_far_apart_commands_are_untouched():
    p = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    v = np.array([[SPEED, 0.0], [0.0, SPEED], [-SPEED, 0.0]])
    out = keep_separation(p, v, np.array([True, True, False]), p + T * v, T, np.full(3, SPEED), D_SEP)
    np.testing.assert_array_equal(out, v)


# Hunt 190 of the committed sweep (studies/sweep, seed 1), paper:rti:hpipm:5 at t = 133.3 s: defender 1 is
# in the approaching stage (held in the capture problem) and has moved towards the shifted previous plan of
# defender 2, which therefore already violates d_sep at steps 3 and 4 (0.1991 m).
HUNT_190_ATTACKER = [9.963121924043332, 10.957212340637437]
HUNT_190_DEFENDERS = [[11.156712429257793, 11.661204913432838], [8.994519641717632, 9.69907404834632],
                      [9.116256277388585, 9.860361236182216], [12.398924459250647, 8.272746930656709],
                      [10.38976315113019, 12.275636003366563]]
HUNT_190_REFERENCE = {  # the shifted previous plan of the controlled defenders 0, 2 and 4, steps 1..5
    0: [[11.157969972353532, 11.659575422436035], [11.158991040885356, 11.658347714374727],
        [11.159764951673496, 11.65753848586528], [11.160273841544424, 11.657168279013986],
        [11.160273841544424, 11.657168279013986]],
    2: [[9.11721624934217, 9.8586814798355], [9.117872145372143, 9.857237766748565],
        [9.118207135180578, 9.856044530337773], [9.118200739274958, 9.855123966641042],
        [9.118200739274958, 9.855123966641042]],
    4: [[10.390298266487024, 12.27382360225656], [10.390583819159056, 12.272091605623164],
        [10.390600288605931, 12.270445821142594], [10.390320454403048, 12.268891116756441],
        [10.390320454403048, 12.268891116756441]],
}


@pytest.mark.parametrize("formulation,backend", [("qp", "daqp"), ("rti", "hpipm")])
def test_a_linearised_plan_keeps_d_sep_from_a_held_defender_its_reference_crossed(formulation, backend):
    from mpc_hunt import CaptureProblem, CaptureSolver
    from mpc_hunt.sweep.random_scenario import ScenarioRanges, sweep_scenario

    scenario = sweep_scenario(1, 190, ScenarioRanges())
    defenders = np.array(HUNT_190_DEFENDERS)
    problem = CaptureProblem.at_state(scenario, HUNT_190_ATTACKER, defenders, 5)
    reference = np.repeat(defenders[None], 5, axis=0)
    for i, path in HUNT_190_REFERENCE.items():
        reference[:, i] = path
    now = float(norm(defenders[1] - defenders[2]))
    assert now > D_SEP     # holding still keeps the pair apart
    plan = CaptureSolver(formulation, backend).solve(problem, reference).plan
    assert norm(plan[:, 1] - plan[:, 2]).min() >= D_SEP - 1e-6

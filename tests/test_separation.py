"""The separation filter keeps every pair of defenders apart in every stage (mpc_hunt/separation.py)."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from mpc_hunt.geometry import norm
from mpc_hunt.separation import keep_separation
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

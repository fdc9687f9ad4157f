"""Hypothesis strategies shared by the property tests."""

from __future__ import annotations

import functools
import math

import numpy as np
from hypothesis import settings
from hypothesis import strategies as st

FAST = settings(deadline=None, max_examples=150)
# Finite floats without subnormals (whose products underflow and defeat relative tolerances).
floats = functools.partial(st.floats, allow_nan=False, allow_infinity=False, allow_subnormal=False)

# Rounded so that no subnormal coordinates (underflowing norms) are generated.
coords = floats(min_value=-50.0, max_value=50.0).map(lambda x: round(x, 9))
points = st.tuples(coords, coords).map(np.array)
angles = floats(min_value=-math.pi, max_value=math.pi).map(lambda x: round(x, 12))


def polar(length: float, angle: float) -> np.ndarray:
    return np.array([length * math.cos(angle), length * math.sin(angle)])

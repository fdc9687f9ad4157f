"""Plans: every defender's positions over the horizon, shape (N, n, 2)."""

from __future__ import annotations

import numpy as np


def shift_plan(plan: np.ndarray) -> np.ndarray:
    """A previous plan moved one step on, its last step repeated: the receding-horizon warm start."""
    return np.concatenate([plan[1:], plan[-1:]], axis=0)

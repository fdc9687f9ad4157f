"""The one check of an agent's action, shared by every environment: the boundary between a learner and the world.

An action is legal when it is real numbers of exactly its space's shape (nothing is
broadcast: a ``(1, 2)`` or a flat ``(6,)`` is not a team of three's ``(3, 2)``), every one
finite. Its size is not bounded: the world caps a velocity at its robot's speed in its
direction, however large (:func:`mpc_hunt.world.geometry.saturate` measures a huge vector
scaled, so 1e200 m/s is the top speed, not 0). An illegal action is an
:class:`~mpc_hunt.errors.ActionError` (a ``ValueError``) naming the agent, raised before
anything of the hunt moves: the environment is as it was.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from mpc_hunt.errors import ActionError


def checked_action(action, space: spaces.Box, agent: str, what: str | None = None) -> np.ndarray:
    """``action`` as a new float64 array of ``space``'s shape, or an ActionError naming ``agent`` and saying
    ``what`` an action is (default: a velocity, or one per defender)."""
    if what is None:
        what = "a velocity (vx, vy) in m/s" + ("" if space.shape == (2,) else " per defender, one row each")
    try:
        raw = np.asarray(action)
        if raw.dtype.kind not in "biufO":  # bool, integers, floats; objects that may hold numbers
            raise TypeError(raw.dtype)
        value = np.array(raw, dtype=np.float64)
    except (TypeError, ValueError):  # text, complex numbers, ragged rows, a dict...
        raise ActionError(f"{agent}: {what}, not {type(action).__name__} {str(action)[:60]!r}") from None
    if value.shape != space.shape:
        raise ActionError(f"{agent}: shape {value.shape}, not its space's {space.shape} ({what}; nothing is broadcast)")
    if not np.all(np.isfinite(value)):
        raise ActionError(f"{agent}: not finite ({value.tolist()}); give finite numbers, {what}")
    return value

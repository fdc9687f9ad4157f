"""The compiled behaviours, by code, moving a batch of hunts' attackers in one call.

A behaviour whose rule is compiled (:mod:`mpc_hunt.compiled`) has a code here and a line in
:func:`attacker_velocities`; the others (``learned``, ``ppo``: a network's view) move one hunt at a time from
Python (:data:`PYTHON`). A batch holds each hunt's arrays padded to the batch's largest team and obstacle set, with
the counts ``n`` and ``m`` that say how much of each row is the hunt's own.
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.world.behaviours.apf import apf_velocity
from mpc_hunt.world.behaviours.flee import flee_velocity
from mpc_hunt.world.behaviours.gap import gap_velocity
from mpc_hunt.world.behaviours.minimax import minimax_velocity
from mpc_hunt.world.behaviours.noisy import noisy_velocity
from mpc_hunt.world.behaviours.voronoi import voronoi_velocity

PYTHON = -1  # the code of a behaviour moved from Python, one hunt at a time
CODES = {"apf": 0, "flee": 1, "gap": 2, "voronoi": 3, "noisy": 4, "minimax": 5}


@kernel
def attacker_velocities(
    codes: np.ndarray,
    running: np.ndarray,
    p_a: np.ndarray,
    p_d: np.ndarray,
    n: np.ndarray,
    speeds: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    m: np.ndarray,
    prm: np.ndarray,
    draws: np.ndarray,
    rays: np.ndarray,
    out: np.ndarray,
) -> None:
    """``out[b]``: the velocity of hunt b's attacker, for every running hunt of a compiled behaviour (``speeds[b]``:
    its defenders' top speeds; ``draws[b]``: the noisy attacker's two draws of this step,
    :func:`~mpc_hunt.world.behaviours.noisy.draw`; ``rays``: the minimax attacker's,
    :data:`~mpc_hunt.world.behaviours.minimax.DIRECTIONS`)."""
    for b in range(codes.shape[0]):
        if not running[b] or codes[b] == PYTHON:
            continue
        a, d, c, r, q = p_a[b], p_d[b, : n[b]], centres[b, : m[b]], radii[b, : m[b]], prm[b]
        if codes[b] == 0:
            x, y = apf_velocity(a, d, c, r, q)
        elif codes[b] == 1:
            x, y = flee_velocity(a, d, c, r, q)
        elif codes[b] == 2:
            x, y = gap_velocity(a, d, c, r, q)
        elif codes[b] == 3:
            x, y = voronoi_velocity(a, d, c, r, q)
        elif codes[b] == 4:
            x, y = noisy_velocity(a, d, c, r, q, draws[b, 0], draws[b, 1])
        else:
            x, y = minimax_velocity(a, d, c, r, q, speeds[b, : n[b]], rays)
        out[b, 0], out[b, 1] = x, y

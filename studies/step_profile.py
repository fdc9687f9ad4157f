"""Where the recommended step's time goes: ``rti``/``hpipm``'s one CasADi call taken apart.

The step (state in → plan out) is one call of a CasADi Function that
linearises the stage-structured problem, solves the QP with HPIPM and reads
the plan back (mpc_hunt/solving/backends/conic_step.py), plus the Python that poses
the problem and hands the call its arguments. On the same states, warm-started
as the controller does, this times the linearisation alone and HPIPM alone on
the same numeric QP (same options), and counts HPIPM's iterations; the rest of the
call is the read-back and CasADi's own overhead.
"""

from __future__ import annotations

import time

import numpy as np

from mpc_hunt.formulations.capture_model import parameter_vector
from mpc_hunt.formulations.rti import RTIFormulation
from mpc_hunt.formulations.stage_model import SMOOTHING
from mpc_hunt import CaptureMPC, CaptureProblem
from mpc_hunt.solving.backends.conic_step import QP_KEYS
from mpc_hunt.solving.backends.hpipm import HpipmBackend

REPEATS = 5     # each piece is timed this many times per state; the fastest counts (the least disturbed)


def _fastest(call) -> tuple[float, object]:
    best, out = np.inf, None
    for _ in range(REPEATS):
        start = time.perf_counter()
        out = call()
        best = min(best, time.perf_counter() - start)
    return best, out


def rti_profile(problems: list) -> dict:
    """Median ms of the linearisation and of HPIPM alone, and HPIPM's median iterations, over the warm-started
    states ``problems`` (callables that pose each state), the first (set-up) excluded."""
    mpc = CaptureMPC("rti", "hpipm")
    linearise = hpipm = None
    pieces = {"linearise_ms": [], "hpipm_ms": [], "hpipm_iterations": []}
    for make in problems:
        problem: CaptureProblem = make()
        start = mpc.step(problem).start          # the controller's step; its start is the one taken apart
        if linearise is not None:
            theta = np.append(parameter_vector(problem), SMOOTHING)
            reference = problem.x_from_plan(problem.held_plan() if start is None else start)
            seconds, qp = _fastest(lambda: linearise(theta, reference))
            pieces["linearise_ms"].append(1e3 * seconds)
            data = dict(zip(QP_KEYS, qp))
            seconds, _ = _fastest(lambda: hpipm(**data))
            pieces["hpipm_ms"].append(1e3 * seconds)
            pieces["hpipm_iterations"].append(hpipm.stats()["iter_count"])
        else:
            linearise, hpipm = HpipmBackend().linearised(RTIFormulation().built(problem.structure))
    return {"repeats": REPEATS, **{k: float(np.median(v)) for k, v in pieces.items()}}

"""The capture QP's floor: what one QP costs at best on this machine, whichever solver and whatever it starts from.

Most of a compiled step is its QP (``step_profile.py``), so the QP bounds how
fast any step can be. Two bounds, on the warm-started states of the latency
table (each QP linearised at the plan the controller warm-starts from):

* **A perfect warm start.** ``qp``'s QP (the same linearisation, condensed:
  the defenders' moves and Eq. 14's slacks) on DAQP, a dense dual active-set
  solver, through the ``daqp`` backend: solved cold, then solved again by a
  fresh model started from the working set of that solution. No warm-started
  active-set method starts better. Times are DAQP's own clock (its C solve,
  no Python).
* **Fewer rows.** HPIPM alone on ``rti``'s stage QP (``step_profile.py``),
  for the states as posed and for the same states with every obstacle
  removed (its rows and its pull on the attacker): the most that keeping only
  the obstacle rows within reach could save, in iterations and in time.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mpc_hunt import markdown
from mpc_hunt.formulations.capture_model import parameter_vector
from mpc_hunt.formulations.qp import QPFormulation
from mpc_hunt import CaptureMPC, CaptureProblem
from mpc_hunt.solving import registry
from mpc_hunt.capture.solution import WarmStart

from studies.step_profile import rti_profile


def perfect_warm_start(problems: list) -> dict | None:
    """DAQP on ``qp``'s QP at each warm-started state of ``problems`` (callables posing each), the first (cold,
    set-up) excluded: median solve ms and iterations cold and from the solution's own working set, the sizes, and
    the largest difference between the two solutions; None if no state was solved both ways."""
    mpc, backend = CaptureMPC("rti", "hpipm"), registry.backend_class("daqp")()
    rows = []
    for k, make in enumerate(problems):
        problem: CaptureProblem = make()
        start = mpc.step(problem).start
        if k:
            reference = problem.held_plan() if start is None else start
            data = QPFormulation().built(problem.structure).data(("qp", problem.structure), parameter_vector(problem),
                                                              problem.x_from_plan(reference))
            cold = backend.run(backend.setup(data), data, WarmStart(None, None))
            again = backend.run(backend.setup(data), data, cold.duals)
            if cold.status.usable and again.status.usable:
                rows.append((cold.extras["reported_solve_time_s"], cold.iterations,
                             again.extras["reported_solve_time_s"], again.iterations,
                             int(np.count_nonzero(cold.duals.y)), float(np.max(np.abs(cold.x - again.x)))))
    if not rows:
        return None
    r = np.array(rows)
    return {"variables": int(data.A.shape[1]), "rows": int(data.A.shape[0]), "solved": len(rows),
            "states": len(problems) - 1, "median_active_rows": float(np.median(r[:, 4])),
            "cold_ms": 1e3 * float(np.median(r[:, 0])), "cold_iterations": float(np.median(r[:, 1])),
            "warm_ms": 1e3 * float(np.median(r[:, 2])), "warm_iterations": float(np.median(r[:, 3])),
            "max_difference": float(np.max(r[:, 5]))}


def without_obstacles(problems: list) -> list:
    """``problems`` (callables) with every obstacle removed from the scenario."""
    def bare(make):
        problem = make()
        return replace(problem, scenario=replace(problem.scenario, obstacles=()))
    return [lambda make=make: bare(make) for make in problems]


def qp_floor(problems: list) -> dict | None:
    """Both bounds of the module docstring on ``problems`` (callables posing each warm-started state); None when
    DAQP solved none of them."""
    daqp = perfect_warm_start(problems)
    return None if daqp is None else {"daqp": daqp, "hpipm_without_obstacles": rti_profile(without_obstacles(problems))}


def floor_lines(floor: dict, profile: dict, interpreted_ms: float, obstacles: int,
                exported: list[dict] | None) -> list[str]:
    """The README's section: the bounds beside the step times the compiled and exported targets ask for, and
    the fastest exported ``rti`` step in C (any mode and BLASFEO; ``exported`` as ``step_exported.exported_c``)."""
    d, bare = floor["daqp"], floor["hpipm_without_obstacles"]
    lines = ["## The QP's floor", "",
             "What one capture QP costs at best here, on the same states, each linearised at the plan the controller "
             "warm-starts from ([`step_floor.py`](../step_floor.py)). DAQP: `qp`'s QP (the same linearisation, "
             f"condensed: {d['variables']} variables, {d['rows']} rows, a median {d['median_active_rows']:.0f} active "
             f"at the optimum), on its own clock, solved cold and then again from the working set of its own solution "
             f"(no warm-started active-set method starts better; the two solutions agree to {d['max_difference']:.0e}"
             f", {d['solved']} of {d['states']} states solved). HPIPM alone: `rti`'s stage QP (fastest of "
             f"{profile['repeats']} per state, then the median), as posed and with the scenario's {obstacles} "
             "obstacles removed (their rows and their pull on the attacker: the most that dropping the obstacle rows "
             "out of reach could save).", "",
             *markdown.table(["QP", "solver", "start", "median solve (ms)", "median iterations"], "lllrr", [
                 ["`qp`, condensed", "DAQP", "cold", f"{d['cold_ms']:.3f}", f"{d['cold_iterations']:.0f}"],
                 ["`qp`, condensed", "DAQP", "its own optimal working set", f"{d['warm_ms']:.3f}",
                  f"{d['warm_iterations']:.0f}"],
                 ["`rti`, stage form", "HPIPM", "as posed", f"{profile['hpipm_ms']:.3f}",
                  f"{profile['hpipm_iterations']:.0f}"],
                 ["`rti`, stage form", "HPIPM", "obstacles removed", f"{bare['hpipm_ms']:.3f}",
                  f"{bare['hpipm_iterations']:.0f}"]]), ""]
    best = min(d["warm_ms"], profile["hpipm_ms"], bare["hpipm_ms"])
    lines.append(f"The compiled step's target (10× the interpreted `rti` step's {interpreted_ms:.3f} ms) leaves "
                 f"{interpreted_ms / 10:.3f} ms for the whole step and the exported C target (20×) "
                 f"{interpreted_ms / 20:.3f} ms; the lowest QP time above is {best:.3f} ms, "
                 f"{best / (interpreted_ms / 10):.1f}× and {best / (interpreted_ms / 20):.1f}× those.")
    c = min((e for e in exported or [] if e["formulation"] == "rti" and e["exit"] == 0),
            key=lambda e: e["median_step_ms"], default=None)
    if c is not None:
        lines[-1] += (f" The fastest exported `rti` step in C ({c['variant']}, plans within "
                      f"{c['max_plan_difference_m']:.0e} m of Python's) takes {c['median_step_ms']:.3f} ms, "
                      f"{c['median_step_ms'] / (interpreted_ms / 20):.1f}× the exported target.")
    return lines + [""]

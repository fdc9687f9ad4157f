"""Solve one capture problem and read its certificate.

One capture-stage problem (Eqs. 12-15) at one state, solved by a formulation on a backend, scored by the one
evaluator of the true nonlinear problem. Three things come back, each answering another question:

* ``status``: what the solver believes (``optimal``, ``optimal_inaccurate``, ``infeasible``, ``iteration_limit``,
  ``time_limit``, ``error``; the first two are usable);
* ``certificate``: how well the returned point solves the problem the solver was handed, computed from that
  problem's data (the primal and dual residuals and the duality gap; for IPOPT its own measures);
* ``violation``: by how much the plan breaks the true constraints (for a linearised formulation, the
  linearisation's error shows here, not in the certificate).

The state is the shipped one of ``paper-open`` at which the hunting circle has formed (what ``mpc-hunt solve``
uses by default); the solve is then repeated warm from the first plan and its duals, and the next state's
problem is solved from the plan shifted one step, as a receding horizon restarts it.

    python examples/solve_one_problem.py [--formulation qp] [--backend daqp] [--horizon 8]
"""

from __future__ import annotations

import argparse

from mpc_hunt import CaptureProblem, CaptureSolver, builtin_scenario, pairs, shift_plan
from mpc_hunt.bench import builtin_problem_set


def report(label: str, solution) -> None:
    print(
        f"{label}: {solution.formulation} on {solution.backend}: {solution.status.value} "
        f"in {solution.solve_time * 1e3:.2f} ms, {solution.iterations} iterations"
        + (f" (set-up {solution.setup_time * 1e3:.0f} ms apart)" if solution.setup_time else "")
    )
    c = solution.certificate
    if c is None:
        print("  certificate: none (the backend returns no multipliers)")
    else:
        print(
            f"  certificate ({c.kind}): primal residual {c.primal_residual:.2e}, dual residual "
            f"{c.dual_residual:.2e}, duality gap {c.duality_gap:.2e}; within 1e-6: {c.within(1e-6)}"
        )
    print(
        f"  objective (the evaluator's) {solution.objective:.6g}, the formulation's own "
        f"{solution.formulation_objective:.6g}"
    )
    print("  true violations (m): " + ", ".join(f"{k} {v:.1e}" for k, v in solution.violation.items()))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="paper-open")
    parser.add_argument("--formulation", default="qp")
    parser.add_argument("--backend", default="daqp")
    parser.add_argument("--horizon", type=int, default=5)
    args = parser.parse_args()

    print(f"{len(pairs())} formulation x backend pairs work; this one: {args.formulation} on {args.backend}")
    scenario = builtin_scenario(args.scenario)
    state = builtin_problem_set("default").default_state(args.scenario)
    problem = CaptureProblem.at_state(scenario, state.attacker, state.defenders, horizon=args.horizon)
    print(
        f"state at t = {state.time} s: attacker {state.attacker.tolist()}, "
        f"{int(problem.controlled.sum())} of {len(state.defenders)} defenders in the capture stage"
    )

    solver = CaptureSolver(args.formulation, args.backend, score=True)  # set up once; each solve one-shot
    first = solver.solve(problem)  # cold: every defender held
    report("cold", first)
    report("warm", solver.solve(problem, first.plan, first.duals))  # the same problem from its own answer

    # One step on: the defenders at the plan's first positions, the attacker moved by its law (Eq. 2); the plan
    # shifted one step is this problem's warm start (the duals carry over while the same defenders are controlled).
    following = CaptureProblem.at_state(
        scenario, problem.attacker_step(state.attacker, state.defenders), first.plan[0], horizon=args.horizon
    )
    duals = first.duals if following.signature == problem.signature else None
    report("next state, warm", solver.solve(following, shift_plan(first.plan), duals))
    print("first step of the plan (m):", first.plan[0].round(4).tolist())


if __name__ == "__main__":
    main()

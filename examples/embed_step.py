"""Embed the capture step in a control loop of your own, under a deadline, and stop it at capture.

The loop below is the whole closed loop, written out: at every control step it poses the capture problem at
the current state (the enclose objective, tracking places on a hunting circle that ``Enclosure`` builds),
hands it to ``CaptureMPC`` (the receding horizon: a warm start from the plan applied last step, shifted, and a
fallback when a solve fails), times the step against the deadline, applies the plan's first positions, moves
the attacker by the paper's law (Eq. 2, as the problem models it) and runs the paper's success test (Eqs. 4-5),
which must hold for the scenario's ``hold_time`` in a row. Every step prints its time, its certificate (the
residuals of the QP the solver was handed) and the deadline misses so far.

It starts from the shipped state of ``paper-open`` at which the hunting circle has formed (the problem set
``default``); ``--from-start`` starts from the scenario's own starts instead, a longer hunt.

    python examples/embed_step.py [--formulation rti] [--backend hpipm] [--horizon 10] [--deadline 0.02]
"""

from __future__ import annotations

import argparse
import time

from mpc_hunt import CaptureMPC, CaptureProblem, Enclosure, Observation, builtin_scenario, success_test
from mpc_hunt.bench import builtin_problem_set


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="paper-open")
    parser.add_argument("--formulation", default="rti")
    parser.add_argument("--backend", default="hpipm")
    parser.add_argument("--horizon", type=int, default=10)
    parser.add_argument("--deadline", type=float, default=0.02, help="the step's budget in seconds (50 Hz)")
    parser.add_argument("--from-start", action="store_true", help="from the scenario's starts")
    args = parser.parse_args()

    scenario = builtin_scenario(args.scenario)
    hunt = scenario.hunt
    T = hunt.time_step
    if args.from_start:
        attacker, defenders = scenario.attacker.start, scenario.defender_starts
    else:
        state = builtin_problem_set("default").default_state(args.scenario)
        attacker, defenders = state.attacker, state.defenders

    places = Enclosure(scenario, args.horizon)  # where the defenders should stand, step by step
    # set up once, then updated and warm-started every step; score=False: no evaluator in the loop (a controller's
    # setting: scoring every plan costs about 60 % of an rti step), so a failed solve falls back to the shifted plan
    mpc = CaptureMPC(args.formulation, args.backend, score=False)
    hold_steps = round(hunt.hold_time / T)  # the success test must hold this many steps in a row
    held = misses = 0
    previous = None
    print(
        f"{scenario.name}: {args.formulation} on {args.backend}, N = {args.horizon}, T = {T} s, "
        f"deadline {args.deadline * 1e3:.0f} ms"
    )
    print(" step      t   step ms  status      primal    dual      gap        misses  radius m")
    for k in range(round(hunt.time_limit / T)):
        observation = Observation(k * T, attacker, previous, defenders)
        started = time.perf_counter()
        problem = CaptureProblem.at_state(
            scenario,
            attacker,
            defenders,
            args.horizon,
            reference=places.reference(observation),
            enclose_weights=places.weights,
        )
        step = mpc.step(problem)
        elapsed = time.perf_counter() - started  # what the loop waited: posing the problem and the solve
        misses += elapsed > args.deadline

        previous = attacker
        attacker = problem.attacker_step(attacker, defenders)  # the world: the attacker reacts to where they were
        defenders = step.plan[0]  # the plan's first positions: where the defenders are one step on
        status = success_test(
            attacker,
            defenders,
            scenario.obstacle_centres,
            scenario.obstacle_radii,
            hunt.hunt_radius,
            hunt.centre_tolerance,
        )
        held = held + 1 if status.holds else 0

        c = step.solution.certificate
        residuals = (
            "   no certificate           "
            if c is None
            else (f"{c.primal_residual:9.1e} {c.dual_residual:9.1e} {c.duality_gap:9.1e}")
        )
        label = step.solution.status.value if step.fallback is None else f"fallback: {step.fallback}"
        print(
            f"{k:5d} {(k + 1) * T:6.1f} {elapsed * 1e3:9.2f}  {label:10s} {residuals}  {misses:6d}"
            f"  {status.radius:7.3f}"
        )
        if held >= hold_steps:
            print(
                f"captured at t = {(k + 1) * T:.1f} s after {k + 1} steps; "
                f"steps over the {args.deadline * 1e3:.0f} ms deadline: {misses} (the first builds the step); "
                f"fallbacks: {sum(mpc.fallbacks.values())}"
            )
            return
    raise SystemExit(f"not captured within the scenario's time limit of {hunt.time_limit} s")


if __name__ == "__main__":
    main()

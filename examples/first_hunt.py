"""The first hunt: a built-in scenario, a controller by name, one closed-loop run, and what it reports.

``mpc-hunt simulate`` does the same from the command line; here the hunt is ``paper-open`` (the paper's
simulation 1, no obstacles) and the controller the recommended one, ``ControllerSpec()`` with every field left
at its default (``trap``, its capture stage ``rti`` on HPIPM over 10 steps).

    python examples/first_hunt.py [--scenario paper-obstacles] [--plot hunt.png]
"""

from __future__ import annotations

import argparse

from mpc_hunt import ControllerSpec, builtin_names, builtin_scenario, simulate
from mpc_hunt.plots import plot_hunt


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="paper-open", choices=builtin_names())
    parser.add_argument("--plot", help="write the hunt's figure to this PNG file")
    args = parser.parse_args()

    scenario = builtin_scenario(args.scenario)
    spec = ControllerSpec()  # the recommended controller; ControllerSpec("paper") is the paper's strategy
    controller = spec.build(scenario)  # built on the defenders' belief about the attacker, never on the world
    result = simulate(scenario, controller)

    print(f"scenario {result.scenario}: {len(scenario.defenders)} defenders, {len(scenario.obstacles)} obstacles")
    print(f"controller {spec.label}: {controller.describe()}")
    print(f"termination: {result.termination}; captured: {result.captured}; capture time: {result.capture_time} s")
    print("path lengths (m):", ", ".join(f"{x:.2f}" for x in result.path_lengths))
    print(f"final hunting radius: {result.final_hunting_radius:.3f} m (R_hunt {scenario.hunt.hunt_radius} m)")
    print(
        f"least defender separation: {result.min_defender_separation:.3f} m; "
        f"least distance to the attacker: {result.min_attacker_distance:.3f} m; steps: {result.steps}"
    )
    stats = result.solve_time_stats()
    print(
        f"capture-stage solves: {stats['count']}, median {stats['median_s'] * 1e3:.2f} ms, "
        f"max {stats['max_s'] * 1e3:.2f} ms; failed {result.failed_solves}, fallbacks {result.fallbacks}"
    )
    if args.plot:
        plot_hunt(result, scenario, args.plot)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()

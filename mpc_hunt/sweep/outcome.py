"""What one hunt of a sweep counts as: captured, a failure with its cause, or not capturable by definition.

Causes, the first that applies (docs/robustness.md):
``non_finite_state``; ``obstacle_collision`` (a defender inside an obstacle);
``defender_contact`` (two defenders closer than ``min_separation``, less
``CONTACT_TOLERANCE``); ``attacker_escaped`` (it left the arena);
``solver_failure_streak`` (``FAILURE_STREAK`` capture-stage solves in a row
failed, 5 s at T = 0.1 s); ``time_limit``. A captured hunt that broke a safety
distance is a failure with that cause: safety comes before capture.
"""

from __future__ import annotations

from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.world.scenario import Scenario

CAUSES = ("non_finite_state", "obstacle_collision", "defender_contact", "attacker_escaped",
          "solver_failure_streak", "time_limit", "error")
CONTACT_TOLERANCE = 1e-6    # m
FAILURE_STREAK = 50


def failure_cause(result: HuntResult, scenario: Scenario) -> str | None:
    """The cause of a failed hunt, or None if it was captured safely."""
    if result.termination == "non_finite_state":
        return "non_finite_state"
    if result.min_obstacle_clearance is not None and result.min_obstacle_clearance < 0:
        return "obstacle_collision"
    if result.min_defender_separation is not None \
            and result.min_defender_separation < scenario.hunt.min_separation - CONTACT_TOLERANCE:
        return "defender_contact"
    if result.captured:
        return None
    if result.termination == "attacker_escaped":
        return "attacker_escaped"
    if result.longest_failure_streak >= FAILURE_STREAK:
        return "solver_failure_streak"
    return "time_limit"

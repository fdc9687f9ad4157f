"""What one hunt of a sweep counts as: captured, a failure with its cause, or not capturable by definition.

Causes, the first that applies (docs/robustness.md):
``non_finite_state``; ``obstacle_collision`` (a defender inside an obstacle);
``defender_contact`` (two defenders closer than ``min_separation``, less
``CONTACT_TOLERANCE``); ``outside_arena`` (a defender beyond an edge of the
arena, by more than ``CONTACT_TOLERANCE``); ``attacker_escaped`` (it left the
arena); ``solver_failure_streak`` (``FAILURE_STREAK`` capture-stage solves in a
row failed, 5 s at T = 0.1 s); ``time_limit``. A captured hunt that broke a
safety distance or left the arena is a failure with that cause: safety comes
before capture.

Coming inside an obstacle's safety distance R_safe (Eq. 15) without touching
the obstacle is no failure, but a sweep records it per stage
(:func:`safety_breaches`).
"""

from __future__ import annotations

from mpc_hunt.sim.hunt_result import HuntResult
from mpc_hunt.world.scenario import Scenario

CAUSES = (
    "non_finite_state",
    "obstacle_collision",
    "defender_contact",
    "outside_arena",
    "attacker_escaped",
    "solver_failure_streak",
    "time_limit",
    "error",
)
CONTACT_TOLERANCE = 1e-6  # m
FAILURE_STREAK = 50


def failure_cause(result: HuntResult, scenario: Scenario) -> str | None:
    """The cause of a failed hunt, or None if it was captured safely."""
    if result.termination == "non_finite_state":
        return "non_finite_state"
    if result.min_obstacle_clearance is not None and result.min_obstacle_clearance < 0:
        return "obstacle_collision"
    if (
        result.min_defender_separation is not None
        and result.min_defender_separation < scenario.hunt.min_separation - CONTACT_TOLERANCE
    ):
        return "defender_contact"
    if result.min_arena_margin is not None and result.min_arena_margin < -CONTACT_TOLERANCE:
        return "outside_arena"
    if result.captured:
        return None
    if result.termination == "attacker_escaped":
        return "attacker_escaped"
    if result.longest_failure_streak >= FAILURE_STREAK:
        return "solver_failure_streak"
    return "time_limit"


def safety_breaches(result: HuntResult, scenario: Scenario) -> tuple[bool, bool]:
    """Did a defender come inside an obstacle's safety distance R_safe (Eq. 15), less ``CONTACT_TOLERANCE``,
    at a position an approaching-stage command led it to, and at one a capture-stage command led it to?"""
    limit = scenario.hunt.safety_distance - CONTACT_TOLERANCE
    approach, capture = (
        clearance is not None and clearance < limit
        for clearance in (result.approach_min_obstacle_clearance, result.capture_min_obstacle_clearance)
    )
    return approach, capture

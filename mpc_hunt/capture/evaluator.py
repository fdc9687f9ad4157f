"""The referee: scores any plan on the true nonlinear capture problem.

Every formulation and backend is scored here, in plain NumPy, independently of
the CasADi expressions the formulations are built from, by the objective the
plan was made for (:data:`OBJECTIVE`, the paper's; :data:`ENCLOSE_OBJECTIVE`)
and one violation per constraint family, in metres.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.solution import Status
from mpc_hunt.world.geometry import norm, saturate

VIOLATION_NAMES = ("motion_limit", "equal_distance", "obstacle_safety", "separation", "attacker_distance")
# The families a plan must keep to be applied: Eq. 14 is elastic in every formulation (an L1 penalty, not a bound).
HARD_CONSTRAINTS = tuple(name for name in VIOLATION_NAMES if name != "equal_distance")
# The families of the robots' own geometry (Eqs. 13 and 15, the separations), free of the attacker's prediction.
GEOMETRY_CONSTRAINTS = ("motion_limit", "obstacle_safety", "separation")
TERM_NAMES = ("force", "ring", "move", "equal_distance")
ENCLOSE_TERM_NAMES = ("slot", "attacker", "edge", "move")

OBJECTIVE = """\
J(X) = sum over steps k = 1..N of
         w_f |u'_a - u_a,k|^2 / v_a^2                           (force, Eq. 12)
       + w_r sum_i (|r_ai,k| - R_hunt/2)^2 / R_hunt^2           (ring: closes the circle)
       + w_m sum_i |p_di,k - p_di,k-1|^2 / r_d,i^2              (move: smoothness)
       + w_eq sum_i | |r_ai,k|^2 - q_k | / R_hunt^2             (equal_distance: Eq. 14's L1 penalty)
over the controlled defenders i, with q_k the median of |r_ai,k|^2 over i (the q_k that
minimises the last term, as the NLP's elastic Eq. 14 does), the attacker p_a,k propagated
through its APF dynamics (Eq. 2) under the plan, and w_f = 1, w_r = 0.1, w_m = 1e-3,
w_eq = 1e3. Reported beside it, never inside it: each constraint family's largest
violation in metres: motion_limit (Eq. 13, |p_di,k - p_di,k-1| - r_d), equal_distance
(Eq. 14, max_i |r_ai,k| - min_i |r_ai,k|), obstacle_safety (Eq. 15, r_o + R_safe -
|p_di,k - c_o|), separation (d_sep - |p_di,k - p_dj,k|) and attacker_distance
(d_min - |r_ai,k|)."""

ENCLOSE_OBJECTIVE = """\
J(X) = sum over steps k = 1..N of
         w_k sum_i |p_di,k - s_i,k|^2 / r_d^2                    (slot: each defender to its place)
       + w_a |p_a,k - a_k|^2 / r_d^2                             (attacker: to where the circle holds it)
       + w_e sum_sides max(0, margin - distance to the side)^2 / r_d^2     (edge: the arena)
       + w_m sum_i |p_di,k - p_di,k-1|^2 / r_d,i^2               (move: smoothness)
with the places s_i,k, the attacker's a_k and the weights w_k from the reference the controller
builds (mpc_hunt.control.enclosure), r_d the controlled defenders' mean step (v_d T), the
attacker propagated through its APF dynamics (Eq. 2),
w_a = 10, w_e = 10, margin = 1 m, w_m = 1e-3. The paper's constraints but Eq. 14 (the places
decide the distances), with every defender inside the arena."""


def hard_violation(violation: dict[str, float]) -> float:
    """The largest violation of the families a plan must keep (:data:`HARD_CONSTRAINTS`), in metres."""
    return max(violation[name] for name in HARD_CONSTRAINTS)


@dataclass(frozen=True)
class Evaluation:
    """The true objective of a plan, its terms, the attacker's predicted path and each constraint's violation."""

    objective: float
    violation: dict[str, float]
    attacker_path: np.ndarray  # (N, 2): the attacker at steps 1..N
    terms: dict[str, float]  # the objective's terms (TERM_NAMES), summed over the horizon
    margin: dict[str, float]  # each family's smallest distance to its bound, in metres (< 0: violated;
    # inf: no such constraint; Eq. 14's is −(max − min) distance, ≤ 0)

    @property
    def max_violation(self) -> float:
        return max(self.violation.values())


def equal_distance_penalty(squared_distances: np.ndarray) -> float:
    """Σ_i | |r_ai|² − q | at its minimiser q, the median of the squared distances (Eq. 14's L1 form).

    For an array of steps (one row per step), the sum over every step, each with its own median.
    """
    sq = np.asarray(squared_distances, dtype=float)
    return float(np.sum(np.abs(sq - np.median(sq, axis=-1, keepdims=True))))


def _largest(values: np.ndarray) -> float:
    return float(np.max(values)) if values.size else -np.inf


def score_plan(problem: CaptureProblem, plan: np.ndarray) -> dict:
    """What a solver adds to its :class:`~mpc_hunt.capture.solution.Solution` for ``plan``: the evaluator's
    ``objective``, ``violation``, ``attacker_path`` and the time it took, ``score_time``."""
    t0 = time.perf_counter()
    evaluation = evaluate(problem, plan)
    return dict(
        objective=evaluation.objective,
        violation=evaluation.violation,
        attacker_path=evaluation.attacker_path,
        score_time=time.perf_counter() - t0,
    )


def solve_scores(problem: CaptureProblem, plan: np.ndarray | None, status: Status, score: bool) -> dict:
    """What a solver scores of its answer: with ``score`` every finite plan, else only a failed solve's (the plan a
    controller's fallback reads, :class:`mpc_hunt.solving.mpc.CaptureMPC`); ``{}`` for none."""
    if plan is None or not np.all(np.isfinite(plan)) or (status.usable and not score):
        return {}
    return score_plan(problem, plan)


def evaluate(problem: CaptureProblem, plan: np.ndarray) -> Evaluation:
    """Score ``plan`` (shape (N, n, 2): every defender at steps 1..N) on ``problem`` (see :data:`OBJECTIVE`).

    The attacker is propagated step by step (Eq. 2 depends on the step before);
    everything else is computed for the whole horizon at once.
    """
    plan = np.asarray(plan, dtype=float)
    N, n = problem.horizon, len(problem.controlled)
    if plan.shape != (N, n, 2):
        raise ValueError(f"plan: expected shape {(N, n, 2)}, got {plan.shape}")
    w, hunt, a = problem.weights, problem.scenario.hunt, problem.scenario.attacker
    c = problem.controlled
    r_d = np.where(c, problem.step_limits, 0.0)
    centres, radii = problem.scenario.obstacle_centres, problem.scenario.obstacle_radii

    path, forces = np.empty((N, 2)), np.empty((N, 2))
    p_a = problem.attacker_step(problem.attacker_position, problem.defender_positions)
    for k in range(N):
        path[k] = p_a
        forces[k] = problem.resultant(p_a, plan[k])
        p_a = p_a + problem.time_step * saturate(forces[k], a.max_speed)  # Eq. 2, as attacker_step
    dist = norm(path[:, None, :] - plan)  # (N, n)
    steps = plan - np.concatenate([problem.defender_positions[None], plan[:-1]])
    mine = dist[:, c]
    if problem.objective == "enclose":
        terms = _enclose_terms(problem, plan, path, steps, r_d)
    else:
        force_error = problem.desired_velocity - forces
        terms = {
            "force": w.force * float(np.sum(force_error**2)) / a.max_speed**2,
            "ring": w.ring * float(np.sum(((mine - problem.ring_radius) / hunt.hunt_radius) ** 2)),
            "move": w.move * float(np.sum(np.sum(steps[:, c] ** 2, axis=2) / r_d[c] ** 2)),
            "equal_distance": w.equal_distance * equal_distance_penalty(mine**2) / hunt.hunt_radius**2,
        }
    apart = norm(plan[:, c][:, :, None, :] - plan[:, None, :, :])  # (N, controlled, n)
    others = np.arange(n)[None, :] != np.flatnonzero(c)[:, None]
    worst = {
        "motion_limit": _largest(norm(steps) - r_d),
        "equal_distance": _largest(mine.max(axis=1) - mine.min(axis=1)),
        "obstacle_safety": _largest(
            radii + hunt.safety_distance - norm(plan[:, c][:, :, None, :] - centres[None, None])
        ),
        "separation": _largest(hunt.min_separation - apart[:, others]),
        "attacker_distance": _largest(hunt.min_attacker_distance - mine),
    }
    violation = {k: max(v, 0.0) for k, v in worst.items()}
    if problem.objective == "enclose":  # Eq. 14 is no constraint of this objective (only a regulariser)
        violation["equal_distance"] = 0.0
    return Evaluation(sum(terms.values()), violation, path, terms, {k: -v for k, v in worst.items()})


def _enclose_terms(problem: CaptureProblem, plan, path, steps, r_d) -> dict[str, float]:
    """The terms of :data:`ENCLOSE_OBJECTIVE`."""
    e, ref, c = problem.enclose_weights, problem.enclose_reference, problem.controlled
    arena = problem.scenario.arena
    if arena is None:
        beyond = np.zeros((len(path), 4))
    else:
        m = e.edge_margin
        beyond = np.maximum(
            np.stack(
                [
                    arena[0] + m - path[:, 0],
                    arena[1] + m - path[:, 1],
                    path[:, 0] - arena[2] + m,
                    path[:, 1] - arena[3] + m,
                ],
                axis=1,
            ),
            0.0,
        )
    length = float(np.mean(problem.step_limits[c]))
    slot = np.sum((plan[:, c] - ref.defenders[:, c]) ** 2, axis=(1, 2)) / length**2
    return {
        "slot": float(np.sum(ref.slot_weight * slot)),
        "attacker": e.attacker * float(np.sum((path - ref.attacker) ** 2)) / length**2,
        "edge": e.edge * float(np.sum(beyond**2)) / length**2,
        "move": e.move * float(np.sum(np.sum(steps[:, c] ** 2, axis=2) / r_d[c] ** 2)),
    }

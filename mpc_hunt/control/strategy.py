"""The paper's hunting strategy as a controller (it never sees how the world is simulated).

Each defender is in the approaching stage (|r_ai| ≥ R_agg: Eq. 6 towards the
predicted intercept) or the capture stage (|r_ai| < R_agg: its next positions
come from the capture-stage problem, Eqs. 12–15, solved over a receding
horizon). The receding-horizon memory is one
:class:`~mpc_hunt.solving.mpc.CaptureMPC`'s (``mpc``; ``mpc.solver`` is its
:class:`~mpc_hunt.solving.solver.CaptureSolver`): the plan applied, shifted one
step, as the next warm start while the same defenders are controlled, and the
fallback when a solve fails (counted; the order is in :mod:`mpc_hunt.solving.mpc`).
The evaluator scores a successful plan only with ``score=True``, a failed one
always. The approaching defenders' commands pass the safety-distance filter
(:mod:`mpc_hunt.world.safety`), then the
separation filter (:mod:`mpc_hunt.world.separation`) against the capture-stage
defenders' next positions and each other.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mpc_hunt.world import attacker
from mpc_hunt.world.approach import approach_target, approach_velocity
from mpc_hunt.capture.problem import OBJECTIVES, CaptureProblem, EncloseWeights, checked_horizon
from mpc_hunt.control.containment import CONTAIN_WEIGHTS, Containment
from mpc_hunt.control.enclosure import Enclosure
from mpc_hunt.control.trap import Trap
from mpc_hunt.control.estimation import AttackerEstimator, Estimate
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.control.controller import Command, Observation, attacker_velocity_estimate
from mpc_hunt.world.safety import keep_safety_distance
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.separation import keep_separation
from mpc_hunt.solving.mpc import CaptureMPC


def approach_commands(scenario: Scenario, obs: Observation, approaching: np.ndarray,
                      prediction: bool) -> tuple[np.ndarray, np.ndarray]:
    """Velocities (Eq. 6, kept out of R_safe: :mod:`mpc_hunt.world.safety`) and intercepts (Eqs. 7–8) of the
    ``approaching`` defenders; zero elsewhere."""
    speeds = scenario.defender_max_speeds
    hunt = scenario.hunt
    velocities = np.zeros_like(obs.defenders)
    intercepts = np.full_like(obs.defenders, np.nan)
    v_a = attacker_velocity_estimate(obs, hunt.time_step)
    for i in np.flatnonzero(approaching):
        target = approach_target(obs.attacker, v_a, obs.defenders[i], speeds[i], prediction)
        intercepts[i] = target
        others = np.delete(obs.defenders, i, axis=0)
        velocities[i] = keep_safety_distance(
            obs.defenders[i], approach_velocity(scenario, obs.defenders[i], target, speeds[i], others),
            scenario.obstacle_centres, scenario.obstacle_radii, hunt.safety_distance, hunt.time_step, speeds[i])
    return velocities, intercepts


class HuntingStrategy:
    """The paper's strategy; the capture stage solved by any formulation and backend, for either objective.

    ``objective="paper"``: Eqs. 12–15 for the defenders within R_agg, Eq. 6 for the others.
    ``objective="enclose"``: every active defender planned at every step by the capture
    problem, tracking the places :class:`~mpc_hunt.control.enclosure.Enclosure` builds.
    ``score``: the evaluator scores every plan, not only a failed solve's (the module's docstring).
    """

    enclose_weights = EncloseWeights()     # the enclose objective's weights
    OBJECTIVE = "paper"                    # the capture objective the controller poses unless told otherwise

    def __init__(self, scenario: Scenario, *, prediction: bool = True, formulation: str = "nlp",
                 backend: str | None = None, horizon: int = 1, time_limit: float | None = None,
                 objective: str | None = None, score: bool = False, **solver_options):
        objective = objective or self.OBJECTIVE
        if objective not in OBJECTIVES:
            raise MpcHuntError(f"objective: unknown {objective!r} (available: {', '.join(OBJECTIVES)})")
        self.scenario = scenario
        self.prediction = prediction
        self.horizon = checked_horizon(horizon)
        self.objective = objective
        self.mpc = CaptureMPC(formulation, backend, time_limit=time_limit, score=score, **solver_options)
        posed = self.mpc.solver.formulation.objectives
        if objective not in posed:      # every solve would fail: refuse at once
            raise MpcHuntError(f"formulation: {formulation} poses the {' or '.join(posed)}"
                               f" objective, not this controller's {objective!r} (use a controller with that "
                               f"objective, or another formulation)")
        self.enclosure = Enclosure(scenario, horizon) if objective == "enclose" else None

    def describe(self) -> dict:
        return {"controller": "enclose" if self.enclosure else "paper", "prediction": self.prediction,
                "formulation": self.mpc.solver.formulation.name, "backend": self.mpc.solver.backend.name,
                "horizon": self.horizon, "objective": self.objective}

    def command(self, obs: Observation) -> Command:
        if self.enclosure is not None:
            return self._enclose(obs)
        s = self.scenario
        capture = attacker.perceives(s, obs.attacker, obs.defenders) & obs.active
        velocities, intercepts = approach_commands(s, obs, ~capture & obs.active, self.prediction)
        solution, fallback, planned_next = None, False, obs.defenders
        if capture.any():
            problem = CaptureProblem.at_state(s, obs.attacker, obs.defenders, self.horizon, active=obs.active)
            solution, plan, fallback = self._capture(problem)
            velocities[capture] = (plan[0][capture] - obs.defenders[capture]) / s.hunt.time_step
            planned_next = plan[0]
        else:
            self.mpc.reset()
        velocities = keep_separation(obs.defenders, velocities, ~capture & obs.active, planned_next, s.hunt.time_step,
                                     s.defender_max_speeds, s.hunt.min_separation)
        return Command(velocities, capture, intercepts, solution, fallback)

    def _enclose(self, obs: Observation) -> Command:
        """Every active defender from the capture problem with the enclose objective."""
        s = self.scenario
        reference = self.enclosure.reference(obs)
        problem = CaptureProblem.at_state(s, obs.attacker, obs.defenders, self.horizon, active=obs.active,
                                          reference=reference)
        if self.enclose_weights != problem.enclose_weights:
            problem = dataclasses.replace(problem, enclose_weights=self.enclose_weights)
        solution, plan, fallback = self._capture(problem)
        velocities = np.where(problem.controlled[:, None], (plan[0] - obs.defenders) / s.hunt.time_step, 0.0)
        intercepts = np.full_like(obs.defenders, np.nan)
        return Command(velocities, problem.controlled.copy(), intercepts, solution, fallback)

    def _capture(self, problem: CaptureProblem):
        """Solve the capture problem; returns (solution, the plan applied, whether it is a fallback)."""
        step = self.mpc.step(problem)
        return step.solution, step.plan, step.fallback is not None


class EnclosingStrategy(HuntingStrategy):
    """The strategy with the enclose objective (CLI ``--controller enclose``)."""

    OBJECTIVE = "enclose"


class ModelFreeStrategy(HuntingStrategy):
    """The capture problem with the enclose objective and no term on a predicted attacker (``CONTAIN_WEIGHTS``),
    tracking the places its ``REFERENCE`` builds from what the defenders observe; ``NAME`` is its controller's."""

    enclose_weights = CONTAIN_WEIGHTS
    OBJECTIVE = "enclose"
    REFERENCE: type
    NAME: str

    def __init__(self, scenario: Scenario, **options):
        super().__init__(scenario, **options)
        self.enclosure = self.REFERENCE(scenario, self.horizon)

    def describe(self) -> dict:
        return super().describe() | {"controller": self.NAME}


class ContainingStrategy(ModelFreeStrategy):
    """Tracking the Voronoi rule's places moved with the attacker's observed velocity,
    :class:`~mpc_hunt.control.containment.Containment` (CLI ``--controller contain``)."""

    REFERENCE, NAME = Containment, "contain"


class TrappingStrategy(ModelFreeStrategy):
    """Tracking the minimum-time shrink of the attacker's dominance region that :class:`~mpc_hunt.control.trap.Trap`
    builds (CLI ``--controller trap``)."""

    REFERENCE, NAME = Trap, "trap"


class AdaptiveStrategy(EnclosingStrategy):
    """The enclose controller whose model of the attacker is re-estimated every step from the observed track
    (:class:`~mpc_hunt.control.estimation.AttackerEstimator`; CLI ``--controller adapt``): the capture problem
    and the enclose reference predict the attacker with the estimated intent, gain and perception radius in
    place of the belief's, which is the estimator's prior."""

    def __init__(self, scenario: Scenario, **options):
        super().__init__(scenario, **options)
        self.prior = scenario
        self.estimator = AttackerEstimator(scenario)
        self.estimate: Estimate | None = None

    def describe(self) -> dict:
        return super().describe() | {"controller": "adapt"}

    def command(self, obs: Observation) -> Command:
        self.estimate = self.estimator.update(obs)
        self.scenario = self.enclosure.scenario = self.estimate.scenario(self.prior)
        return super().command(obs)

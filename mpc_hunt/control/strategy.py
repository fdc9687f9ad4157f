"""The paper's hunting strategy as a controller (it never sees how the world is simulated).

A solving controller is a reference (:mod:`mpc_hunt.control.reference`) × the capture stage solved over a
receding horizon. With the paper's reference, each defender is in the approaching stage (|r_ai| ≥ R_agg: Eq. 6
towards the predicted intercept) or the capture stage (|r_ai| < R_agg: its next positions come from the
capture-stage problem, Eqs. 12–15); with a reference of places, every active defender is in the capture stage.
The receding-horizon memory is one :class:`~mpc_hunt.solving.mpc.CaptureMPC`'s (``mpc``; ``mpc.solver`` is its
:class:`~mpc_hunt.solving.solver.CaptureSolver`): the plan applied, shifted one step, as the next warm start
while the same defenders are controlled, and the fallback when a solve fails (counted; the order is in
:mod:`mpc_hunt.solving.mpc`). The evaluator scores a successful plan only with ``score=True``, a failed one
always. The approaching defenders' commands pass the safety-distance filter (:mod:`mpc_hunt.world.safety`),
then the separation filter (:mod:`mpc_hunt.world.separation`) against the capture-stage defenders' next
positions and each other.
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.capture.problem import CaptureProblem, checked_horizon
from mpc_hunt.control.controller import Command, Observation, attacker_velocity_estimate
from mpc_hunt.control.enclosure import Enclosure
from mpc_hunt.control.estimation import AttackerEstimator, Estimate
from mpc_hunt.control.reference import CaptureReference, PaperObjective
from mpc_hunt.solving import registry
from mpc_hunt.solving.mpc import CaptureMPC
from mpc_hunt.world.approach import approach_target, approach_velocity
from mpc_hunt.world.belief import AttackerModel
from mpc_hunt.world.safety import keep_safety_distance
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.separation import keep_separation


def approach_commands(
    scenario: Scenario, obs: Observation, approaching: np.ndarray, prediction: bool
) -> tuple[np.ndarray, np.ndarray]:
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
            obs.defenders[i],
            approach_velocity(scenario, obs.defenders[i], target, speeds[i], others),
            scenario.obstacle_centres,
            scenario.obstacle_radii,
            hunt.safety_distance,
            hunt.time_step,
            speeds[i],
        )
    return velocities, intercepts


class HuntingStrategy:
    """A solving controller: a reference (:mod:`mpc_hunt.control.reference`) × the capture stage, solved over a
    receding horizon by any formulation and backend.

    ``reference``: :class:`~mpc_hunt.control.reference.PaperObjective` (the default, the paper's strategy: Eqs.
    12–15 for the defenders within R_agg, Eq. 6 for the others), or a class building places that the enclose
    objective tracks with every active defender (``Enclosure``, ``Containment``, ``Trap``).
    ``formulation``, ``backend`` and ``horizon``: the capture stage as given, never defaulted here (a controller
    by name, :class:`~mpc_hunt.control.spec.ControllerSpec`, takes the defaults; ``backend`` None is the
    formulation's own). ``score``: the evaluator scores every plan, not only a failed solve's (the module's
    docstring).
    """

    def __init__(
        self,
        scenario: Scenario,
        reference: type[CaptureReference] = PaperObjective,
        *,
        formulation: str,
        backend: str | None = None,
        horizon: int,
        prediction: bool = True,
        time_limit: float | None = None,
        score: bool = False,
        **solver_options,
    ):
        self.scenario = scenario
        self.prediction = prediction
        self.horizon = checked_horizon(horizon)
        self.reference = reference(scenario, self.horizon)
        self.objective = reference.OBJECTIVE
        self.mpc = CaptureMPC(formulation, backend, time_limit=time_limit, score=score, **solver_options)
        refusal = registry.objective_refusal(formulation, self.mpc.solver.backend.name, self.objective)
        if refusal is not None:  # every solve would fail: refuse at once
            raise refusal

    def describe(self) -> dict:
        return {
            "controller": self.reference.NAME,
            "prediction": self.prediction,
            "formulation": self.mpc.solver.formulation.name,
            "backend": self.mpc.solver.backend.name,
            "horizon": self.horizon,
            "objective": self.objective,
        }

    def posed(self) -> Scenario:
        """The believed scenario this step is posed on: the one the controller was built on."""
        return self.scenario

    def command(self, obs: Observation) -> Command:
        """The capture stage's plan for the defenders it holds (the reference's places tracked, or Eq. 12 within
        R_agg); Eq. 6 for the other active ones, filtered against the plan's next positions."""
        s = self.posed()
        capture = self.reference.capture_stage(obs)
        velocities, intercepts = approach_commands(s, obs, ~capture & obs.active, self.prediction)
        solution, fallback, planned_next = None, False, obs.defenders
        if capture.any():
            problem = CaptureProblem.at_state(
                s,
                obs.attacker,
                obs.defenders,
                self.horizon,
                active=obs.active,
                reference=self.reference.reference(obs),
                enclose_weights=self.reference.weights,
            )
            solution, plan, fallback = self._capture(problem)
            velocities[capture] = (plan[0][capture] - obs.defenders[capture]) / s.hunt.time_step
            planned_next = plan[0]
        else:
            self.mpc.reset()
        velocities = keep_separation(
            obs.defenders,
            velocities,
            ~capture & obs.active,
            planned_next,
            s.hunt.time_step,
            s.defender_max_speeds,
            s.hunt.min_separation,
        )
        return Command(velocities, capture, intercepts, solution, fallback)

    def _capture(self, problem: CaptureProblem):
        """Solve the capture problem; returns (solution, the plan applied, whether it is a fallback)."""
        step = self.mpc.step(problem)
        return step.solution, step.plan, step.fallback is not None


class AdaptiveStrategy(HuntingStrategy):
    """The enclose controller whose model of the attacker is re-estimated every step from the observed track
    (CLI ``--controller adapt``): a prior :class:`~mpc_hunt.world.belief.AttackerModel`, the belief's, and an
    :class:`~mpc_hunt.control.estimation.AttackerEstimator` beside the controller that updates it; the capture
    problem and the enclose reference predict the attacker with the current model (its intent, gain and
    perception radius). ``scenario`` is the hunt it was built on (arena, defenders, obstacles, parameters);
    :meth:`posed` is that hunt with the current model's attacker
    (:meth:`AttackerModel.scenario <mpc_hunt.world.belief.AttackerModel.scenario>`)."""

    OBJECTIVE = "enclose"
    SUMMARY = "enclose with the attacker's model re-estimated online from its observed track"

    def __init__(self, scenario: Scenario, **options):
        super().__init__(scenario, Enclosure, **options)
        self.prior = AttackerModel.of(scenario)
        self.estimate: Estimate | None = None
        self.estimator = AttackerEstimator(scenario, self.prior)
        self.reference = Enclosure(scenario, self.horizon, posed=self.posed)
        self._posed = (self.prior, scenario)  # the last model and the hunt posed with it

    @property
    def model(self) -> AttackerModel:
        """The model the step predicts with: the last estimate's, the prior before the first update."""
        return self.prior if self.estimate is None else self.estimate.model

    def posed(self) -> Scenario:
        """The hunt with the current model's attacker, made once per model."""
        if self._posed[0] is not self.model:
            self._posed = (self.model, self.model.scenario(self.scenario))
        return self._posed[1]

    def describe(self) -> dict:
        return super().describe() | {"controller": "adapt"}

    def command(self, obs: Observation) -> Command:
        self.estimate = self.estimator.update(obs)
        return super().command(obs)

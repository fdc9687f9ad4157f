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
from mpc_hunt.compiled import kernel
from mpc_hunt.control.controller import Command, Observation, estimated_velocity, previous_of
from mpc_hunt.control.enclosure import Enclosure
from mpc_hunt.control.estimation import AttackerEstimator, Estimate
from mpc_hunt.control.reference import CaptureReference, PaperObjective
from mpc_hunt.solving import registry
from mpc_hunt.solving.mpc import CaptureMPC
from mpc_hunt.world.approach import approach_of
from mpc_hunt.world.belief import AttackerModel
from mpc_hunt.world.packed import SAFETY, T
from mpc_hunt.world.prediction import meeting_point
from mpc_hunt.world.safety import kept_safe
from mpc_hunt.world.scenario import Scenario
from mpc_hunt.world.separation import keep_separation


@kernel
def approach_stage(p_a, previous, P, approaching, speeds, centres, radii, prm, prediction, velocities, intercepts):
    """Into ``velocities`` and ``intercepts``: the ``approaching`` defenders' Eq. 6 towards their intercepts
    (Eqs. 7–8, the attacker's velocity estimated from ``previous``, NaN before the first step; its position without
    prediction or intercept), kept out of R_safe (:mod:`mpc_hunt.world.safety`)."""
    v_a = estimated_velocity(p_a, previous, prm[T])
    for i in range(P.shape[0]):
        if approaching[i]:
            found, tx, ty = meeting_point(p_a, v_a, P[i], speeds[i]) if prediction else (False, 0.0, 0.0)
            if not found:
                tx, ty = p_a[0], p_a[1]
            intercepts[i, 0], intercepts[i, 1] = tx, ty
            vx, vy = approach_of(P, i, tx, ty, speeds[i], centres, radii, prm)
            velocities[i, 0], velocities[i, 1] = kept_safe(P[i], vx, vy, centres, radii, prm[SAFETY], prm[T], speeds[i])


def approach_commands(
    scenario: Scenario, obs: Observation, approaching: np.ndarray, prediction: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Velocities (Eq. 6, kept out of R_safe: :mod:`mpc_hunt.world.safety`) and intercepts (Eqs. 7–8) of the
    ``approaching`` defenders; zero elsewhere (:func:`approach_stage`)."""
    s, P = scenario, np.asarray(obs.defenders, dtype=float)
    velocities, intercepts = np.zeros_like(P), np.full_like(P, np.nan)
    previous = previous_of(obs)
    approach_stage(np.asarray(obs.attacker, float), previous, P, np.asarray(approaching, dtype=bool),
                   s.defender_max_speeds, s.obstacle_centres, s.obstacle_radii, s.packed, prediction, velocities,
                   intercepts)  # fmt: skip
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

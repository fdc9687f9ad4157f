"""The online estimator of the attacker (mpc_hunt/control/estimation.py) on synthetic APF attackers.

Each truth is the paper's attacker (``mpc_hunt.world.attacker.velocity``) with parameters set here, driven by
three defenders that circle it at distances sweeping in and out of its perception radius. The estimator starts
from the believed scenario ``paper-open`` (intent 0.03 m/s along (1, −1)/√2, gain k_d η = 1, R_agg = 1 m) with
the world's obstacles, which the defenders know. The achieved errors quoted in comments were measured on these
hunts (`python tests/control/test_estimation.py` prints most of them); the tolerances leave a margin.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from mpc_hunt import CaptureProblem, Obstacle, Scenario, builtin_scenario
from mpc_hunt.control import estimation
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.estimation import AttackerEstimator, Estimate
from mpc_hunt.world.belief import AttackerModel
from mpc_hunt.world.attacker import nominal_velocity, perceives, velocity
from mpc_hunt.world.geometry import norm

PRIOR = builtin_scenario("paper-open")
TOP = PRIOR.attacker.max_speed                     # 0.03 m/s, known to the defenders
MODERATE = dict(intent=(0.012, -0.008), gain=0.004, radius=1.2)
HEAVY_PRIOR = dataclasses.replace(PRIOR, attacker=dataclasses.replace(PRIOR.attacker, nominal_velocity=(0.0, 0.03),
                                                                     perception_radius=1.5),
                                  hunt=dataclasses.replace(PRIOR.hunt, k_d=0.05))   # wrong about the paper's attacker


def world(intent, gain, radius, obstacles=()) -> Scenario:
    """The truth: ``paper-open`` with the attacker's intent, gain k_d η (η kept) and R_agg set, and obstacles."""
    attacker = dataclasses.replace(PRIOR.attacker, start=(5.0, 10.0), nominal_velocity=intent,
                                   perception_radius=radius)
    hunt = dataclasses.replace(PRIOR.hunt, k_d=gain / PRIOR.hunt.eta)
    return dataclasses.replace(PRIOR, attacker=attacker, hunt=hunt,
                               obstacles=tuple(Obstacle(c, r) for c, r in obstacles))


def believed(truth: Scenario, prior: Scenario = PRIOR) -> Scenario:
    """What the defenders believe: the truth's obstacles, the prior's attacker and gains."""
    return dataclasses.replace(truth, attacker=prior.attacker, hunt=prior.hunt)


def estimator(believed: Scenario) -> AttackerEstimator:
    """The estimator the adapt controller composes on ``believed``: its attacker the prior model."""
    return AttackerEstimator(believed, AttackerModel.of(believed))


def observations(truth: Scenario, steps=150, reach=(0.3, 2.5), noise=0.0, seed=0):
    """The observations of a hunt: three defenders circle the attacker, their distances sweeping ``reach``
    (periods 6–14 s) as they turn (0.1–0.4 rad/s); the attacker's observed position has white noise."""
    rng = np.random.default_rng(seed)
    T = truth.hunt.time_step
    phase, period = rng.uniform(0, 2 * np.pi, 3), rng.uniform(6, 14, 3)
    spin = rng.uniform(0.1, 0.4, 3) * rng.choice([-1, 1], 3)
    p_a, previous = np.array(truth.attacker.start, dtype=float), None
    for k in range(steps):
        t = k * T
        distance = reach[0] + (reach[1] - reach[0]) * 0.5 * (1 + np.sin(2 * np.pi * t / period + phase))
        angle = 2 * np.pi * np.arange(3) / 3 + spin * t
        p_d = p_a + distance[:, None] * np.c_[np.cos(angle), np.sin(angle)]
        seen = p_a + noise * rng.standard_normal(2)
        yield Observation(t, seen, previous, p_d)
        previous = seen
        p_a = p_a + T * velocity(truth, p_a, p_d)


def estimate(truth: Scenario, prior: Scenario = PRIOR, **hunt) -> Estimate:
    """The estimate after the hunt's last observation."""
    updated = estimator(believed(truth, prior))
    for obs in observations(truth, **hunt):
        result = updated.update(obs)
    return result


def errors(result: Estimate, truth: Scenario) -> tuple[float, float, float]:
    """|intent error| (m/s), relative gain error, relative radius error."""
    gain = truth.hunt.k_d * truth.hunt.eta
    model = result.model
    return (float(norm(np.array(model.intent) - nominal_velocity(truth))), abs(model.gain / gain - 1),
            abs(model.perception_radius / truth.attacker.perception_radius - 1))


@pytest.mark.parametrize("truth", [
    world(**MODERATE),
    world(intent=(-0.02, 0.005), gain=0.02, radius=0.8),
    world(**MODERATE, obstacles=[((5.8, 9.2), 0.3)]),        # the obstacle's field acts on the attacker
], ids=["moderate", "short-range", "obstacle"])
def test_recovers_intent_gain_and_perception_radius(truth):
    result = estimate(truth)
    assert result.identified and result.speed_identified and result.samples == estimation.WINDOW
    # Achieved: intent within 1.9e-15 m/s, gain within 3.5e-13 and radius within 1.1e-13 (relative), residual
    # 5.9e-15 m/s.
    intent, gain, radius = errors(result, truth)
    assert intent < 1e-10 and gain < 1e-9 and radius < 1e-9
    assert result.residual < 1e-10


@pytest.mark.slow
@settings(deadline=None, max_examples=15)
@example(speed=0.001953125, heading=0.0, log_gain=0.0, radius=1.5625, seed=0)   # corners hypothesis found, where a
@example(speed=0.001953125, heading=0.0, log_gain=0.0, radius=1.625, seed=0)    # 12-step search stopped short
@example(speed=0.001, heading=0.0, log_gain=0.0, radius=1.5, seed=17)  # one sample below v_a: 3 grids too coarse
@given(speed=st.floats(1e-3, TOP), heading=st.floats(0.0, 2 * np.pi), log_gain=st.floats(-3.0, 0.0),
       radius=st.floats(0.6, 1.8), seed=st.integers(0, 1000))
def test_recovers_any_attacker_the_defenders_excite(speed, heading, log_gain, radius, seed):
    truth = world(intent=(speed * np.cos(heading), speed * np.sin(heading)), gain=10**log_gain, radius=radius)
    result = estimate(truth, seed=seed)
    # On 300 random truths of these ranges (a tenth at their ends, some with no intent): radius within 6.2e-12,
    # residual under 1.2e-14 m/s; where the scale of (v_nom, g) is seen (139), intent within 4e-13 m/s and gain
    # within 3.5e-10. Hypothesis seeks out harder corners (a few mm/s of intent against g = 1, where an uncapped
    # sample arriving last leaves a search short of converged), hence the wide margin.
    intent, gain, radius_error = errors(result, truth)
    assert result.identified and radius_error < 1e-4 and result.residual < 1e-5
    if result.speed_identified:
        assert intent < 1e-5 and gain < 1e-3


@pytest.mark.parametrize("log_gain, radius, seed", [(0.0, 0.6, 841), (0.0, 1.218, 630), (-1.562, 1.75, 553)])
def test_an_attacker_with_no_intent_is_told_by_its_pushes_alone(log_gain, radius, seed):
    """Pushed, it moves along Φ at top speed and otherwise stands: R is pinned only between the distances at
    which it did and did not react, and g only by the rare push below top speed."""
    truth = world(intent=(0.0, 0.0), gain=10**log_gain, radius=radius)
    result = estimate(truth, seed=seed)
    # On 40 such truths (the first the worst): radius within 0.41 %, residual under 1e-14 m/s.
    assert result.identified and errors(result, truth)[2] < 1e-2 and result.residual < 1e-5
    if result.speed_identified:
        assert norm(np.array(result.model.intent)) < 1e-9


def test_heavy_saturation_is_recovered_from_directions():
    """The paper's attacker (gain 1, intent at top speed): any defender in range caps its speed."""
    truth = world(intent=(0.2, -0.2), gain=1.0, radius=1.0)
    capped = [norm(o.attacker - o.previous_attacker) / PRIOR.hunt.time_step >= TOP * (1 - 1e-9)
              for o in observations(truth) if o.previous_attacker is not None]
    assert np.mean(capped) == 1.0                     # every sample at top speed: only directions are seen
    result = estimate(truth, HEAVY_PRIOR)
    # Achieved: intent within 8e-16 m/s, gain within 9.2e-13 and radius within 1.8e-14 (relative).
    intent, gain, radius = errors(result, truth)
    assert result.identified and result.speed_identified
    assert intent < 1e-9 and gain < 1e-6 and radius < 1e-6


def test_when_every_sample_is_capped_only_the_ratio_of_gain_to_intent_is_seen():
    truth = world(intent=(0.0, 0.007), gain=0.25, radius=1.7)
    result = estimate(truth, reach=(0.3, 1.5))                        # every defender always within 1.7 m
    assert result.identified and not result.speed_identified
    # The fastest intent that fits: |v_nom| = v_a, with the gain scaled alike; the radius is exact.
    np.testing.assert_allclose(result.model.intent, [0.0, TOP], atol=1e-9)
    assert result.model.gain == pytest.approx(0.25 * TOP / 0.007, rel=1e-6)
    assert result.model.perception_radius == pytest.approx(1.7, rel=1e-6)
    assert result.residual < 1e-8


@pytest.mark.parametrize("reach", [(3.2, 4.5), (1.5, 2.9)], ids=["beyond-every-candidate", "beyond-true-radius"])
def test_with_no_defender_in_range_the_intent_is_recovered_and_the_field_is_the_prior(reach):
    truth = world(**MODERATE)
    result = estimate(truth, reach=reach)
    assert not result.identified
    assert result.model.gain == PRIOR.hunt.k_d * PRIOR.hunt.eta
    assert result.model.perception_radius == PRIOR.attacker.perception_radius
    # Achieved: intent within 1.6e-15 m/s.
    assert errors(result, truth)[0] < 1e-9 and result.residual < 1e-9


def test_noisy_positions():
    """White noise of 2 mm on the observed positions (the attacker moves at most 3 mm a step)."""
    truth = world(**MODERATE)
    results = [estimate(truth, noise=0.002, seed=seed) for seed in range(8)]
    assert all(result.identified for result in results)
    found = np.array([errors(result, truth) for result in results])
    # Achieved over these 8 hunts: intent within 1.6e-3 m/s (of 0.0144 m/s), gain within 67 % and radius within
    # 42 % (medians 7.5e-4 m/s, 36 % and 12 %).
    assert np.all(found < [3e-3, 1.0, 0.6])
    assert np.all(np.median(found, axis=0) < [1.5e-3, 0.6, 0.25])


def test_noise_with_no_defender_in_range_is_not_taken_for_a_field():
    result = estimate(world(**MODERATE), reach=(1.5, 2.9), noise=0.002)
    assert not result.identified
    assert errors(result, world(**MODERATE))[0] < 2e-3          # achieved: 1.5e-4 m/s


def test_the_estimate_corrects_the_capture_problems_prediction():
    truth = world(**MODERATE)
    prior, result = believed(truth), estimate(truth)
    fitted = result.model.scenario(prior)
    assert fitted.hunt.eta == prior.hunt.eta and fitted.hunt.k_d * fitted.hunt.eta == result.model.gain
    assert fitted.obstacles == prior.obstacles and fitted.attacker.max_speed == prior.attacker.max_speed
    later = list(observations(truth, steps=300))[150:]               # states after the window
    missed, planned = {"prior": [], "fitted": []}, {"prior": [], "fitted": []}
    for obs, following in zip(later, later[1:]):
        if not perceives(prior, obs.attacker, obs.defenders).any():   # no capture problem without a defender in R
            continue
        for name, scenario in (("prior", prior), ("fitted", fitted)):
            problem = CaptureProblem.at_state(scenario, obs.attacker, obs.defenders)
            missed[name].append(norm(problem.attacker_step(obs.attacker, obs.defenders) - following.attacker))
            planned[name].append(np.array_equal(problem.controlled, perceives(truth, obs.attacker, obs.defenders)))
    assert len(missed["fitted"]) > 50
    # The capture problem's next attacker position, on 114 states: achieved within 2e-15 m of the world's,
    # against up to 3.7 mm (mean 1.7 mm) with the prior.
    assert max(missed["fitted"]) < 1e-9 and max(missed["prior"]) > 1e-3
    # The same defenders enter the capture stage as the world's attacker perceives (the prior's R: 18 states off).
    assert all(planned["fitted"]) and not all(planned["prior"])


def test_the_gain_goes_into_k_d_keeping_eta_which_also_scales_the_obstacles_field():
    believed_ = dataclasses.replace(PRIOR, hunt=dataclasses.replace(PRIOR.hunt, eta=2.0, k_d=0.5))
    fitted = AttackerModel.of(believed_).fitted(np.array([0.01, 0.0]), 0.3, 1.4).scenario(believed_)
    assert fitted.hunt.eta == 2.0 and fitted.hunt.k_d == pytest.approx(0.15)
    assert fitted.attacker.nominal_velocity == (0.01, 0.0) and fitted.attacker.perception_radius == 1.4
    assert dataclasses.replace(fitted, attacker=believed_.attacker, hunt=believed_.hunt) == believed_


def test_the_prior_stands_until_there_are_enough_samples():
    updated = estimator(PRIOR)
    for k, obs in enumerate(observations(world(**MODERATE), steps=estimation.MIN_SAMPLES)):
        result = updated.update(obs)
        assert result.samples == k and not result.identified
        model = result.model
        np.testing.assert_array_equal(model.intent, nominal_velocity(PRIOR))
        assert model.gain == 1.0 and model.perception_radius == 1.0 and np.isfinite(result.residual)


def test_an_attacker_standing_still_is_estimated_standing_still():
    result = estimate(world(intent=(0.0, 0.0), gain=0.004, radius=1.2), reach=(3.2, 4.5))
    assert not result.identified and norm(np.array(result.model.intent)) < 1e-12 and result.residual < 1e-12


def test_non_finite_observations_and_a_new_team_are_skipped():
    truth = world(**MODERATE)
    updated = estimator(PRIOR)
    hunt = list(observations(truth, steps=150))
    for k, obs in enumerate(hunt):
        if k == 60:
            obs = dataclasses.replace(obs, attacker=np.array([np.nan, 0.0]))
        if k == 120:
            obs = dataclasses.replace(obs, defenders=obs.defenders[:2])
        result = updated.update(obs)
        model = result.model
        assert np.all(np.isfinite(model.intent)) and np.isfinite(model.gain) and np.isfinite(result.residual)
    assert result.samples == 28                 # the window restarted when the team changed at k = 120
    assert result.identified and max(errors(result, truth)) < 1e-6


@settings(deadline=None, max_examples=40)
@given(data=st.data(), steps=st.integers(0, 40), defenders=st.integers(1, 4))
def test_any_track_gives_a_finite_estimate_within_the_bounds(data, steps, defenders):
    """Arbitrary positions, jumps and coincidences: never NaN, never outside the searched ranges."""
    coordinate = st.floats(-5.0, 5.0)
    updated, previous = estimator(PRIOR), None
    for k in range(steps):
        p_a = np.array(data.draw(st.tuples(coordinate, coordinate)))
        p_d = p_a + np.array(data.draw(st.lists(st.tuples(coordinate, coordinate), min_size=defenders,
                                                max_size=defenders))) * data.draw(st.sampled_from([0.0, 0.1, 1.0]))
        result = updated.update(Observation(0.1 * k, p_a, previous, p_d))
        previous = p_a
        model = result.model
        values = np.r_[model.intent, model.gain, model.perception_radius, result.residual, result.solve_time]
        assert np.all(np.isfinite(values)) and norm(np.array(model.intent)) <= TOP * (1 + 1e-12)
        assert 1e-3 <= model.gain <= 1e3 and 1 / 3 <= model.perception_radius <= 3


def test_an_update_is_cheap():
    updated = estimator(believed(world(**MODERATE)))
    times = [updated.update(obs).solve_time for obs in observations(world(**MODERATE), steps=300)]
    # Measured (docs/estimation.md): median 0.8 ms, mean 1.3 ms, a search (one update in ten) 4.3 ms. A loose
    # bound, to catch an order of magnitude, not to time the machine.
    assert np.median(times[estimation.MIN_SAMPLES:]) < 0.02


if __name__ == "__main__":      # the measurements quoted in docs/estimation.md
    cases = {"moderate": (world(**MODERATE), PRIOR, {}),
             "short range": (world(intent=(-0.02, 0.005), gain=0.02, radius=0.8), PRIOR, {}),
             "obstacle": (world(**MODERATE, obstacles=[((5.8, 9.2), 0.3)]), PRIOR, {}),
             "heavy (the paper's attacker)": (world(intent=(0.2, -0.2), gain=1.0, radius=1.0), HEAVY_PRIOR, {}),
             "no defender within 3 m": (world(**MODERATE), PRIOR, dict(reach=(3.2, 4.5))),
             **{f"noise 2 mm, seed {seed}": (world(**MODERATE), PRIOR, dict(noise=0.002, seed=seed))
                for seed in range(8)}}
    print("case: |intent error| m/s, gain error, radius error, identified")
    for name, (truth, prior, hunt) in cases.items():
        result = estimate(truth, prior, **hunt)
        intent, gain, radius = errors(result, truth)
        print(f"{name}: {intent:.1e}, {gain:.1e}, {radius:.1e}, {result.identified}")
    updated, times, searched = estimator(believed(world(**MODERATE))), [], []
    search = updated._search
    for obs in observations(world(**MODERATE), steps=600):
        ran = []
        updated._search = lambda: ran.append(True) or search()       # an update that searched, told apart
        times.append(1e3 * updated.update(obs).solve_time)
        searched.append(bool(ran))
    times, searched = np.array(times[estimation.MIN_SAMPLES:]), np.array(searched[estimation.MIN_SAMPLES:])
    for name, chosen in (("tracking", times[~searched]), ("search", times[searched]), ("all", times)):
        print(f"{name} per update (ms): median {np.median(chosen):.2f}, mean {chosen.mean():.2f}, "
              f"p90 {np.percentile(chosen, 90):.2f}, max {chosen.max():.2f}")

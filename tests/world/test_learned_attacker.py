"""The ``learned`` attacker's policy: features in the intent's frame, its heading W·φ, the world's rules kept."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mpc_hunt.errors import ScenarioError
from mpc_hunt.world.behaviours.base import undisturbed
from mpc_hunt.world.behaviours.flee import flee_direction
from mpc_hunt.world.behaviours.learned import FEATURES, LearnedAttacker, features, intent_frame
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Scenario

V_A = 0.03
CENTRE = np.array([10.0, 10.0])


def _scenario(intent=(V_A, 0.0)) -> Scenario:
    team = tuple(Defender(start=(1.0 + i, 1.0), max_speed=0.08) for i in range(3))
    return Scenario(name="learned", defenders=team,
                    attacker=Attacker(start=tuple(CENTRE), nominal_velocity=intent, max_speed=V_A,
                                      perception_radius=1.0),
                    hunt=HuntParameters(), arena=(0.0, 0.0, 20.0, 20.0))


def _picking(column: int) -> np.ndarray:
    """W that heads along the unit vector in features ``column`` and ``column + 1``."""
    w = np.zeros((2, FEATURES))
    w[0, column], w[1, column + 1] = 1.0, 1.0
    return w


def _rotation(angle: float) -> np.ndarray:
    return np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])


def test_a_policy_that_picks_the_flee_feature_flees_and_one_that_picks_the_gap_takes_the_gap():
    near = np.array([[11.0, 10.0], [10.0, 12.0]])
    flee = LearnedAttacker(_scenario(), None, _picking(0)).velocity(CENTRE, near)
    assert norm(flee) == pytest.approx(V_A, rel=1e-12)
    np.testing.assert_allclose(flee / V_A, flee_direction(CENTRE, near) / norm(flee_direction(CENTRE, near)),
                               atol=1e-12)
    three = np.array([[11.0, 10.0], [10.0, 11.0], [9.0, 10.0]])          # the widest gap is the south half
    gap = LearnedAttacker(_scenario(), None, _picking(2)).velocity(CENTRE, three)
    np.testing.assert_allclose(gap, [0.0, -V_A], atol=1e-12)


@pytest.mark.parametrize("turn", [0.7, 2.0, -2.9])
def test_the_policy_is_the_same_whatever_the_intents_direction(turn):
    """The scene and the intent turned together turn the heading with them: features in the intent's frame."""
    w = np.random.default_rng(1).normal(size=(2, FEATURES))
    near = np.array([[11.0, 10.5], [9.2, 11.0], [10.3, 8.4]])
    here = LearnedAttacker(_scenario(), None, w).velocity(CENTRE, near)
    R = _rotation(turn)
    turned = LearnedAttacker(_scenario(tuple(R @ [V_A, 0.0])), None, w).velocity(CENTRE,
                                                                               CENTRE + (near - CENTRE) @ R.T)
    np.testing.assert_allclose(turned, R @ here, atol=1e-12)
    phi = features(CENTRE, near, 3, 3.0, intent_frame(np.array([V_A, 0.0]))[0])
    assert phi.shape == (FEATURES,) and phi[-1] == 1.0 and phi[-2] == pytest.approx(1.0)


def test_with_nobody_sensed_it_is_the_papers_undisturbed_attacker_and_bad_weights_are_refused():
    far = np.array([[16.0, 10.0]])
    scenario = _scenario()
    np.testing.assert_array_equal(LearnedAttacker(scenario, None, np.ones((2, FEATURES))).velocity(CENTRE, far),
                                  undisturbed(scenario, CENTRE))
    with pytest.raises(ScenarioError, match="weights"):
        LearnedAttacker(scenario, None, np.ones((2, 3)))
    with pytest.raises(ScenarioError, match="weights"):
        LearnedAttacker(scenario, None, np.full((2, FEATURES), np.nan))

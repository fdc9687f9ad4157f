"""The environments' boundary (docs/envs.md, "At the boundary"): every action, legal or not, and every argument.

The property tests drive each environment with random legal actions (inside the Box, at the speed limit in any
direction or along an axis, zero, finite but astronomically large) and illegal ones (a NaN or an infinity
anywhere, a wrong shape, text, complex numbers, ragged rows; for the parallel environment missing and unknown
agents), over random seeds and hunts (random ones of 2-4 defenders; a given one that ends in a capture, one that
ends in an escape, one cut by its time limit), through several hunts each. Beside each environment runs a twin
with the same seed and only the legal actions. Invariants: every observation finite and in its space, every
reward finite, an illegal action a ValueError that changes nothing (the twin stays in step to the bit), a hunt's
end paid once (one terminal-sized reward, on its last step, then every step refused until a reset), a huge
action the top speed. The examples after them pin each defect the boundary had.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from conftest import small_scenario
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.envs import AttackerEnv, ControllerPolicy, DefenderEnv, HuntParallelEnv
from mpc_hunt.envs.observation import velocity_bound
from mpc_hunt.errors import ActionError, MpcHuntError, OptionError
from mpc_hunt.sweep.random_scenario import ScenarioRanges
from mpc_hunt.world.behaviours import BEHAVIOURS
from mpc_hunt.world.scenario import Attacker, Defender, HuntParameters, Scenario

BOUNDARY = settings(deadline=None, max_examples=15,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.large_base_example])
STEPS = 40                 # legal steps per example: with 15 examples, 600 per environment
TERMINAL = 0.5             # a step's shaping stays far below this; an end's ±1 far above


def _hunt(**changes) -> HuntParameters:
    return dataclasses.replace(HuntParameters(), **changes)


def _ringed() -> Scenario:
    """Three slow-ish defenders already round a slow attacker: captured within a few steps unless they scatter."""
    ring = [(10.0 + 0.35 * math.cos(a), 10.0 + 0.35 * math.sin(a)) for a in np.radians([90.0, 210.0, 330.0])]
    return Scenario(name="ringed", defenders=tuple(Defender(start=p, max_speed=0.02) for p in ring),
                    attacker=Attacker(start=(10.0, 10.0), nominal_velocity=(0.01, 0.0), max_speed=0.005,
                                      perception_radius=1.0),
                    hunt=_hunt(time_limit=4.0, hold_time=0.3), arena=(0.0, 0.0, 20.0, 20.0))


def _at_the_edge() -> Scenario:
    """An attacker a step from the arena's west edge, heading out: it escapes at once unless held in."""
    return Scenario(name="edge", defenders=tuple(Defender(start=p, max_speed=0.08) for p in
                                                 [(15.0, 5.0), (15.0, 10.0), (15.0, 15.0)]),
                    attacker=Attacker(start=(0.002, 10.0), nominal_velocity=(-0.2, 0.0), max_speed=0.06,
                                      perception_radius=1.0),
                    hunt=_hunt(time_limit=3.0), arena=(0.0, 0.0, 20.0, 20.0))


SHORT = dataclasses.replace(small_scenario(obstacles=((10.6, 10.0, 0.4),)), hunt=_hunt(time_limit=2.5))
GIVEN = {"ringed": _ringed(), "edge": _at_the_edge(), "short": SHORT}
# Where the environment's hunts come from: keyword arguments of its constructor.
sources = st.one_of(
    st.builds(lambda n, limit, obstacles: {"defenders": n, "ranges": ScenarioRanges(
        time_limit=limit, n_obstacles=(0, obstacles), n_defenders=(2, 5))},
        st.integers(2, 4), st.floats(1.0, 6.0), st.integers(0, 5)),
    st.sampled_from(sorted(GIVEN)).map(lambda name: {"scenario": GIVEN[name]}))
seeds = st.integers(0, 2**32 - 1)


def _along(shape: tuple, angles, length: float) -> np.ndarray:
    return np.array([[length * math.cos(a), length * math.sin(a)] for a in angles]).reshape(shape)


def _angles(shape: tuple):
    rows = shape[0] if len(shape) == 2 else 1
    return st.lists(st.floats(-math.pi, math.pi), min_size=rows, max_size=rows)


def legal(shape: tuple, speed: float):
    """A legal action of ``shape`` for robots of ``speed``: inside the Box, at the limit in any direction or
    along an axis, or zero."""
    rows = shape[0] if len(shape) == 2 else 1
    axes = st.lists(st.sampled_from([0.0, 0.5 * math.pi, math.pi, -0.5 * math.pi]), min_size=rows, max_size=rows)
    return st.one_of(
        hnp.arrays(np.float64, shape, elements=st.floats(-speed, speed)),
        _angles(shape).map(lambda a: _along(shape, a, speed)),
        axes.map(lambda a: np.round(_along(shape, a, speed), 15)),
        st.just(np.zeros(shape)))


def huge(shape: tuple):
    """A legal action of ``shape`` whose every velocity is finite but 1e150 m/s or more (its square overflows)."""
    return st.tuples(_angles(shape), st.floats(150.0, 307.0)).map(lambda x: _along(shape, x[0], 10.0 ** x[1]))


def illegal(shape: tuple):
    """An illegal action for a space of ``shape``: a non-finite number somewhere, a wrong shape, not numbers."""
    size = int(np.prod(shape))
    wrong = [(1, 2), (size,), (size + 1,), (), (*shape, 1)] + ([(2,)] if shape != (2,) else [(2, 1)])

    def poisoned(x):
        flat, where, bad = np.zeros(size), x[0], x[1]
        flat[where % size] = bad
        return flat.reshape(shape)

    return st.one_of(
        st.tuples(st.integers(0, 99), st.sampled_from([math.nan, math.inf, -math.inf])).map(poisoned),
        st.sampled_from([s for s in wrong if s != shape]).map(np.zeros),
        st.sampled_from(["fast", None, [1j, 0.0], [[0.0, 0.0], [0.0]], {"vx": 0.0}]))


def snapshot(env) -> tuple:
    """Everything a step could change, but the scripted side's memory (the twin checks that)."""
    e = env.episode
    rng = env.np_random.bit_generator.state if hasattr(env, "np_random") else env.rng.bit_generator.state
    return (e.attacker.tobytes(), e.defenders.tobytes(), e.attacker_velocity.tobytes(),
            e.defender_velocities.tobytes(), e.step_count, e.held, e.termination, e.potential, len(e.trail),
            repr(rng))


def _check_observation(env, observation, space):
    assert np.all(np.isfinite(observation))
    assert observation in space, "outside: " + str(
        [(i, v) for i, v in enumerate(observation) if not space.low[i] <= v <= space.high[i]])


def _check_end(reward: float, termination: str | None, ended: bool, sign: float) -> None:
    """A running step's reward is shaping only; the last one pays the end, with the side's sign."""
    assert math.isfinite(reward)
    if not ended:
        assert abs(reward) < TERMINAL and termination is None
        return
    assert termination in ("captured", "attacker_escaped", "time_limit")
    event(f"a hunt ended: {termination}")            # pytest --hypothesis-show-statistics counts them
    expected = -1.0 if termination == "captured" else 1.0
    assert sign * reward == pytest.approx(expected, abs=TERMINAL)


def _check_huge_was_top_speed(env, action, observation, huge: bool) -> None:
    """A defender told 1e150 m/s or more moves at its top speed, in that direction."""
    if not huge or not isinstance(env, DefenderEnv):
        return
    velocities = observation[7:7 + 4 * env.hunts.defenders].reshape(-1, 4)[:, 2:]
    speeds = env.scenario.defender_max_speeds
    np.testing.assert_allclose(np.hypot(*velocities.T), speeds, rtol=1e-6)
    np.testing.assert_allclose(velocities / speeds[:, None], action / np.hypot(*action.T)[:, None], atol=1e-6)


def _gymnasium(kind: str, source: dict):
    if kind == "attacker":
        return AttackerEnv(controller="voronoi", **source)
    return DefenderEnv(**source)


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["attacker", "defenders"])
@BOUNDARY
@given(data=st.data(), source=sources, seed=seeds, attacker=st.sampled_from([None, *BEHAVIOURS]))
def test_a_gymnasium_environment_holds_its_invariants_under_random_actions(kind, data, source, seed, attacker):
    env = _gymnasium(kind, source if kind == "attacker" else {**source, "attacker": attacker})
    twin = _gymnasium(kind, source if kind == "attacker" else {**source, "attacker": attacker})
    shape, speed = env.action_space.shape, float(env.action_space.high.max())
    sign = 1.0 if kind == "attacker" else -1.0
    observation, _ = env.reset(seed=seed)
    np.testing.assert_array_equal(observation, twin.reset(seed=seed)[0])
    _check_observation(env, observation, env.observation_space)
    steps, hunt_rewards = 0, []
    while steps < STEPS:
        if data.draw(st.integers(0, 3)) == 0:                   # one draw in four is illegal
            before = snapshot(env)
            with pytest.raises(ValueError, match="^action: "):
                env.step(data.draw(illegal(shape)))
            assert snapshot(env) == before
            continue
        large = data.draw(st.integers(0, 4)) == 0
        action = data.draw(huge(shape) if large else legal(shape, speed))
        observation, reward, terminated, truncated, info = env.step(action)
        twin_step = twin.step(action)
        np.testing.assert_array_equal(observation, twin_step[0])
        assert (reward, terminated, truncated, info) == twin_step[1:]
        steps += 1
        hunt_rewards.append(reward)
        _check_observation(env, observation, env.observation_space)
        _check_end(reward, info["termination"], terminated or truncated, sign)
        _check_huge_was_top_speed(env, action, observation, large and not (terminated or truncated))
        if terminated or truncated:
            assert sum(abs(r) >= TERMINAL for r in hunt_rewards) == 1
            before = snapshot(env)
            for late in (action, np.zeros(shape), data.draw(illegal(shape))):
                with pytest.raises(MpcHuntError, match="has ended"):
                    env.step(late)
            assert snapshot(env) == before
            seed = (seed + 1) % 2**32
            observation, _ = env.reset(seed=seed)
            np.testing.assert_array_equal(observation, twin.reset(seed=seed)[0])
            hunt_rewards = []


def _parallel_illegal(env, data):
    """An illegal dict of actions: one agent's action illegal, an agent missing, an unknown one, not a dict."""
    legal_ones = {a: np.zeros(env.action_space(a).shape) for a in env.agents}
    agent = data.draw(st.sampled_from(env.agents))
    kind = data.draw(st.integers(0, 3))
    if kind == 0:
        return {**legal_ones, agent: data.draw(illegal(env.action_space(agent).shape))}, f"actions\\['{agent}'\\]"
    if kind == 1:
        return {a: v for a, v in legal_ones.items() if a != agent}, f"no action for {agent}"
    if kind == 2:
        return {**legal_ones, "defender_99": np.zeros(2)}, "unknown agent 'defender_99'"
    return list(legal_ones.values()), "a dict of one action per agent"


@pytest.mark.slow
@BOUNDARY
@given(data=st.data(), source=sources, seed=seeds)
def test_the_parallel_environment_holds_its_invariants_under_random_actions(data, source, seed):
    env, twin = HuntParallelEnv(**source), HuntParallelEnv(**source)
    observations, _ = env.reset(seed=seed)
    twin.reset(seed=seed)
    steps, hunt_rewards = 0, []
    while steps < STEPS:
        if data.draw(st.integers(0, 3)) == 0:
            before = snapshot(env)
            actions, message = _parallel_illegal(env, data)
            with pytest.raises(ValueError, match=message):
                env.step(actions)
            assert snapshot(env) == before and env.agents == env.possible_agents
            continue
        actions = {a: data.draw(st.one_of(legal(env.action_space(a).shape, float(env.action_space(a).high.max())),
                                          huge(env.action_space(a).shape))) for a in env.agents}
        observations, rewards, terminations, truncations, infos = env.step(actions)
        twin_step = twin.step(actions)
        for a in env.possible_agents:
            np.testing.assert_array_equal(observations[a], twin_step[0][a])
            _check_observation(env, observations[a], env.observation_space(a))
            assert rewards[a] == -rewards["attacker"] if a != "attacker" else math.isfinite(rewards[a])
        assert (rewards, terminations, truncations, infos) == twin_step[1:]
        steps += 1
        hunt_rewards.append(rewards["attacker"])
        ended = terminations["attacker"] or truncations["attacker"]
        _check_end(rewards["attacker"], infos["attacker"]["termination"], ended, 1.0)
        if ended:
            assert env.agents == [] and sum(abs(r) >= TERMINAL for r in hunt_rewards) == 1
            before = snapshot(env)
            for late in (actions, {}):
                with pytest.raises(MpcHuntError, match="has ended"):
                    env.step(late)
            assert snapshot(env) == before
            seed = (seed + 1) % 2**32
            env.reset(seed=seed)
            twin.reset(seed=seed)
            hunt_rewards = []


# --- each defect the boundary had, pinned ---------------------------------------------------------------------

def _defenders_at_their_limit(env, steps: int = 200) -> list[np.ndarray]:
    """Every defender at its top speed along an axis (east, then south, in turn): its velocity component is then
    the speed itself, where the world's rounding shows."""
    env.reset(seed=1)
    speed = env.hunts.defender_speed
    observations = []
    for k in range(steps):
        observation, _, terminated, truncated, _ = env.step(np.tile([speed, 0.0] if k % 2 else [0.0, -speed], (3, 1)))
        observations.append(observation)
        if terminated or truncated:
            break
    return observations


def test_a_legal_action_at_the_speed_limit_is_observed_inside_the_space():
    env = DefenderEnv(small_scenario())
    observations = _defenders_at_their_limit(env)
    velocities = np.array([o[7:19].reshape(3, 4)[:, 2:] for o in observations])
    assert len(observations) == 200 and np.abs(velocities).max() > 0.08       # the rounding the bound must hold
    assert all(o in env.observation_space for o in observations)
    assert env.observation_space.high[3] == velocity_bound(0.08, 0.1) < 0.08 + 1e-8


@pytest.mark.parametrize("make", [lambda: DefenderEnv(SHORT), lambda: AttackerEnv(SHORT, controller="voronoi")])
def test_a_huge_finite_action_is_the_top_speed_in_its_direction(make):
    env = make()
    env.reset(seed=0)
    shape = env.action_space.shape
    action = np.tile([1e200, -1e200], (3, 1)) if shape == (3, 2) else np.array([1e200, -1e200])
    observation, *_ = env.step(action)
    if shape == (3, 2):
        velocities = observation[7:19].reshape(3, 4)[:, 2:]
        np.testing.assert_allclose(velocities, np.tile([0.08, -0.08], (3, 1)) / math.sqrt(2), rtol=1e-9)
    else:
        np.testing.assert_allclose(observation[3:5], np.array([0.03, -0.03]) / math.sqrt(2), rtol=1e-9)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_non_finite_action_is_a_value_error_naming_the_agent_and_nothing_moves(bad):
    for env, action, name in [(DefenderEnv(SHORT), np.array([[0.0, 0.0], [0.0, bad], [0.0, 0.0]]), "action"),
                              (AttackerEnv(SHORT, controller="voronoi"), np.array([bad, 0.0]), "action")]:
        env.reset(seed=0)
        before = snapshot(env)
        with pytest.raises(ActionError, match=f"^{name}: not finite"):
            env.step(action)
        assert snapshot(env) == before
    env = HuntParallelEnv(SHORT)
    env.reset(seed=0)
    actions = {a: np.zeros(2) for a in env.agents} | {"defender_1": np.array([bad, 0.0])}
    with pytest.raises(ValueError, match="^actions\\['defender_1'\\]: not finite"):
        env.step(actions)


@pytest.mark.parametrize("make", [lambda: AttackerEnv(SHORT),                    # enclose keeps its last plan
                                  lambda: DefenderEnv(SHORT, attacker="noisy")])   # draws at every step
def test_an_illegal_action_leaves_the_other_sides_memory_as_it_was(make):
    """The check comes before the scripted side moves: the refused step changes nothing the next steps see."""
    env, twin = make(), make()
    env.reset(seed=3)
    twin.reset(seed=3)
    action = np.full(env.action_space.shape, 0.01)
    for k in range(8):
        if k == 3:
            with pytest.raises(ActionError):
                env.step(np.full(env.action_space.shape, np.nan))
        np.testing.assert_array_equal(env.step(action)[0], twin.step(action)[0])


@pytest.mark.parametrize("shape", [(1, 2), (6,), (2,), (3, 2, 1)])
def test_a_team_action_of_another_shape_is_refused_not_broadcast(shape):
    env = DefenderEnv(SHORT)
    env.reset(seed=0)
    with pytest.raises(ActionError, match=f"^action: shape \\({shape[0]},"):
        env.step(np.full(shape, 0.01))
    attacker = AttackerEnv(SHORT, controller="voronoi")
    attacker.reset(seed=0)
    with pytest.raises(ActionError, match="not its space's \\(2,\\)"):
        attacker.step(np.zeros((1, 2)))


@pytest.mark.parametrize("make", [lambda: AttackerEnv(SHORT, controller="voronoi"), lambda: DefenderEnv(SHORT)])
def test_after_the_end_a_step_is_refused_until_reset_so_the_end_is_paid_once(make):
    env = make()
    env.reset(seed=0)
    done, rewards = False, []
    while not done:
        _, reward, terminated, truncated, _ = env.step(np.zeros(env.action_space.shape))
        rewards.append(reward)
        done = terminated or truncated
    assert abs(rewards[-1]) > TERMINAL and all(abs(r) < TERMINAL for r in rewards[:-1])
    with pytest.raises(MpcHuntError, match="the hunt has ended \\(time_limit\\); call reset"):
        env.step(np.zeros(env.action_space.shape))
    env.reset(seed=0)
    assert env.step(np.zeros(env.action_space.shape))[1] == rewards[0]


def test_the_parallel_step_names_missing_and_unknown_agents():
    env = HuntParallelEnv(SHORT)
    env.reset(seed=0)
    with pytest.raises(ActionError, match="no action for attacker, defender_0, defender_1, defender_2"):
        env.step({})
    with pytest.raises(ActionError, match="no action for defender_2; unknown agent 'defender_3'"):
        env.step({"attacker": np.zeros(2), "defender_0": np.zeros(2), "defender_1": np.zeros(2),
                  "defender_3": np.zeros(2)})


@pytest.mark.parametrize("build, argument", [
    (lambda: AttackerEnv(scenario=SHORT, defenders=5), "^defenders: 5, but the scenario has 3"),
    (lambda: DefenderEnv(scenario=SHORT, ranges=ScenarioRanges()), "^ranges: "),
    (lambda: HuntParallelEnv(ranges=ScenarioRanges(n_defenders=(4, 5)), defenders=3), "^defenders: 3, outside"),
    (lambda: HuntParallelEnv(defenders=0), "^defenders: "),
    (lambda: DefenderEnv(scenario="paper-open"), "^scenario: "),
    (lambda: AttackerEnv(controller_options={"horizon": 0}), "^controller_options: horizon: must be"),
    (lambda: AttackerEnv(controller_options={"formulation": "qp", "backend": "osqp", "time_limit": -1}),
     "^controller_options: time_limit: "),
    (lambda: AttackerEnv(controller="voronoi", controller_options={"horizon": 5}),
     "^controller_options: horizon: controller 'voronoi' solves no capture problem"),
    (lambda: AttackerEnv(controller_options={"formulation": "rti", "backend": "hpipm", "horizn": 10}),
     "^controller_options: horizn: not an option of HPIPM"),
    (lambda: AttackerEnv(controller="enclos"), "^controller: unknown controller 'enclos'"),
    (lambda: AttackerEnv(controller="voronoi", belief="honest"), "^belief: a Belief"),
    (lambda: ControllerPolicy(DefenderEnv(SHORT), "voronoi", {"horizon": 3}), "^options: horizon: controller 'voronoi'"),
    (lambda: ControllerPolicy(DefenderEnv(SHORT), ControllerSpec("apf"), {}), "^options: the spec 'apf' holds its"),
    (lambda: AttackerEnv(render_mode="human"), "^render_mode: "),
])
def test_a_bad_argument_is_refused_when_the_environment_is_built_naming_it(build, argument):
    with pytest.raises(OptionError, match=argument):
        build()


def test_the_team_is_the_scenarios_or_the_ranges_and_a_reset_scenario_must_fit_the_spaces():
    assert AttackerEnv(scenario=small_scenario(defenders=4), controller="voronoi").hunts.defenders == 4
    assert DefenderEnv(ranges=ScenarioRanges(n_defenders=(4, 4))).action_space.shape == (4, 2)
    env = DefenderEnv(SHORT)
    faster = dataclasses.replace(SHORT, attacker=dataclasses.replace(SHORT.attacker, max_speed=0.05))
    with pytest.raises(OptionError, match="options\\['scenario'\\]: a Scenario that fits the spaces"):
        env.reset(seed=0, options={"scenario": faster})
    assert env.episode is None
    far = dataclasses.replace(SHORT, attacker=dataclasses.replace(SHORT.attacker, start=(999_990.0, 10.0)),
                              hunt=_hunt(time_limit=600.0))
    with pytest.raises(OptionError, match="^scenario: a robot could reach 1.00004e\\+06 m"):
        DefenderEnv(far)

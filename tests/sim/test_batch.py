"""A batch of hunts is each hunt alone: the same trajectories, bit for bit, whatever else the batch holds."""

import dataclasses

import numpy as np
import pytest

from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.sim.batch import simulate_batch
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.sweep.random_scenario import ScenarioRanges, sweep_scenario
from mpc_hunt.world.behaviours import with_behaviour
from mpc_hunt.world.scenario import HuntParameters

# Teams of 2 to 5 and 0 to 3 obstacles, mixed in one batch; attackers compiled and not (learned moves from Python);
# controllers of two batched rules (voronoi, apf) and one commanded hunt by hunt (the paper's strategy, a QP a step).
RANGES = ScenarioRanges(n_defenders=(2, 5), n_obstacles=(0, 3))
PAIRS = [("voronoi", "gap"), ("apf", "flee"), ("voronoi", "noisy"), ("voronoi", "voronoi"), ("apf", "learned"),
         ("voronoi", "minimax"), ("paper:rti:hpipm:5", "flee"), ("voronoi", "apf")]


def _hunts(seed: int, time_limit: float = 60.0):
    scenarios, controllers = [], []
    for index, (controller, attacker) in enumerate(PAIRS):
        s = with_behaviour(sweep_scenario(seed, index, RANGES), attacker)
        s = dataclasses.replace(s, hunt=dataclasses.replace(s.hunt, time_limit=time_limit))
        scenarios.append(s)
        controllers.append(ControllerSpec.parse(controller))
    return scenarios, controllers


def _same(a, b):
    assert a.termination == b.termination and a.capture_time == b.capture_time
    np.testing.assert_array_equal(a.attacker, b.attacker)
    np.testing.assert_array_equal(a.defenders, b.defenders)
    np.testing.assert_array_equal(a.capture_stage, b.capture_stage)
    np.testing.assert_array_equal(a.intercepts, b.intercepts)


@pytest.mark.parametrize("seed", [3, 8])
def test_a_batch_of_mixed_teams_obstacles_attackers_and_controllers_is_each_hunt_alone(seed):
    scenarios, specs = _hunts(seed)
    assert len({len(s.defenders) for s in scenarios}) > 1 and len({len(s.obstacles) for s in scenarios}) > 1
    alone = [simulate(s, spec.build(s), rng=np.random.default_rng(i)) for i, (s, spec) in
             enumerate(zip(scenarios, specs))]
    together = simulate_batch(scenarios, [spec.build(s) for s, spec in zip(scenarios, specs)],
                              [np.random.default_rng(i) for i in range(len(scenarios))])
    assert len({len(r.times) for r in together}) > 1          # hunts ended at different steps, others went on
    for a, b in zip(alone, together):
        _same(a, b)
    # ... and in another order, beside other hunts
    order = list(reversed(range(len(scenarios))))
    shuffled = simulate_batch([scenarios[i] for i in order], [specs[i].build(scenarios[i]) for i in order],
                              [np.random.default_rng(i) for i in order])
    for i, b in zip(order, shuffled):
        _same(alone[i], b)


def test_a_hunt_whose_defender_fails_stops_it_in_the_batch_as_alone():
    s = sweep_scenario(4, 0, RANGES)
    d = s.defenders
    failing = dataclasses.replace(s, defenders=(dataclasses.replace(d[0], fails_at=5.0), *d[1:]),
                                  hunt=HuntParameters(**{**dataclasses.asdict(s.hunt), "time_limit": 40.0}))
    spec = ControllerSpec.parse("voronoi")
    alone = simulate(failing, spec.build(failing))
    (together, _) = simulate_batch([failing, s], [spec.build(failing), spec.build(s)],
                                   [np.random.default_rng(0), np.random.default_rng(1)])
    _same(alone, together)
    k = int(5.0 / s.hunt.time_step)
    assert np.all(together.defenders[k:, 0] == together.defenders[k, 0])   # stood still from fails_at on


def test_a_batch_of_none_or_of_mismatched_lists_is_one_line_naming_the_field():
    from mpc_hunt.errors import OptionError

    scenarios, specs = _hunts(3)
    with pytest.raises(OptionError, match="^scenarios: a batch of 0 hunts"):
        simulate_batch([], [], [])
    with pytest.raises(OptionError, match="^scenarios: a batch of 2 hunts with 1 controllers"):
        simulate_batch(scenarios[:2], [specs[0].build(scenarios[0])], [np.random.default_rng(0)] * 2)


class _NotANumber:
    """A controller that commands NaN: its hunt ends (the state is no longer finite), no other is touched."""

    def describe(self):
        return {"controller": "nan"}

    def command(self, obs):
        from mpc_hunt.control.controller import Command

        n = len(obs.defenders)
        return Command(np.full((n, 2), np.nan), np.zeros(n, dtype=bool), np.full((n, 2), np.nan))


def test_a_hunt_commanded_nan_ends_alone_and_disturbs_no_other():
    scenarios, specs = _hunts(8)
    controllers = [spec.build(s) for s, spec in zip(scenarios, specs)]
    controllers[1] = _NotANumber()
    rngs = [np.random.default_rng(i) for i in range(len(scenarios))]
    results = simulate_batch(scenarios, controllers, rngs)
    assert results[1].termination == "non_finite_state" and results[1].steps == 1
    for i in (0, 2, 3):
        _same(simulate(scenarios[i], specs[i].build(scenarios[i]), rng=np.random.default_rng(i)), results[i])


def test_the_recorded_paths_grow_as_the_hunts_go_on_and_keep_every_step():
    from mpc_hunt.sim.batch import Commands, Paths

    p_a, p_d = np.zeros((2, 2)), np.zeros((2, 3, 2))
    paths = Paths(p_a, p_d, room=2)
    out = Commands(2, 3)
    for k in range(9):                                  # past the room twice: 2 → 4 → 8 → 16 steps
        out.intercepts[:] = k
        running = np.array([True, k < 5])               # the second hunt ends after step 4
        paths.record(k, running, p_a + k + 1, p_d + k + 1, out)
    np.testing.assert_array_equal(paths.attacker[0, :10, 0], np.arange(10))
    np.testing.assert_array_equal(paths.intercepts[0, :9, 0, 0], np.arange(9))
    np.testing.assert_array_equal(paths.attacker[1, :6, 0], np.arange(6))
    assert np.isnan(paths.attacker[1, 6:]).all() and paths.stages.shape[1] == 16

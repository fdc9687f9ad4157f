"""The defenders' belief apart from the world (mpc_hunt/world/belief.py): a controller never sees the behaviour."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from mpc_hunt.control.controller import Observation
from mpc_hunt.control.controllers import CONTROLLERS, SOLVING
from mpc_hunt.control.spec import make_controller
from mpc_hunt.errors import ScenarioError
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.world.belief import AttackerModel, Belief, belief_rng, believed, parse_belief
from mpc_hunt.world.scenario_io import builtin_scenario

OPTIONS = {"formulation": "rti", "backend": "hpipm", "horizon": 5}


def _with(scenario, behaviour, **attacker):
    return dataclasses.replace(scenario, attacker=dataclasses.replace(scenario.attacker, behaviour=behaviour,
                                                                      **attacker))


def test_the_believed_scenario_is_the_papers_attacker_with_the_believed_parameters():
    world = _with(builtin_scenario("paper-obstacles"), "gap", sensing_radius=3.0)
    model = believed(world, Belief(perception_radius=1.3, eta=3.0))
    assert (model.attacker.behaviour, model.attacker.sensing_radius) == ("apf", None)
    assert model.attacker.perception_radius == pytest.approx(world.attacker.perception_radius / 1.3, rel=1e-15)
    assert model.hunt.eta == pytest.approx(world.hunt.eta / 3.0, rel=1e-15)
    assert model.attacker.nominal_velocity == world.attacker.nominal_velocity
    assert (model.defenders, model.obstacles, model.arena) == (world.defenders, world.obstacles, world.arena)


def test_the_model_built_from_a_belief_carries_the_believed_parameters_not_the_worlds():
    world = _with(builtin_scenario("paper-obstacles"), "gap", sensing_radius=3.0)
    world = dataclasses.replace(world, hunt=dataclasses.replace(world.hunt, eta=2.0, k_d=0.5))
    model = AttackerModel.believed(world, Belief(perception_radius=1.3, eta=4.0, intent_heading=60.0),
                                   np.random.default_rng(2))
    assert model.perception_radius == world.attacker.perception_radius / 1.3
    assert (model.eta, model.k_d, model.gain) == (0.5, 0.5, 0.25)
    assert model.max_speed == world.attacker.max_speed and model.LAW == "apf"
    assert model.intent != pytest.approx(world.attacker.nominal_velocity, abs=1e-3)
    assert math.hypot(*model.intent) == pytest.approx(math.hypot(*world.attacker.nominal_velocity), rel=1e-12)
    # The one place a believed scenario is made: the world's hunt with the model's attacker.
    posed = model.scenario(world)
    assert AttackerModel.of(posed) == model and (posed.attacker.behaviour, posed.attacker.sensing_radius) == \
        ("apf", None)
    assert dataclasses.replace(posed, attacker=world.attacker, hunt=world.hunt) == world
    assert believed(world, Belief(perception_radius=1.3, eta=4.0, intent_heading=60.0),
                    np.random.default_rng(2)) == posed
    assert AttackerModel.of(world) == AttackerModel.believed(world)


def test_the_intent_heading_error_is_drawn_within_its_bound_by_the_passed_in_generator():
    world = builtin_scenario("paper-open")
    vx, vy = world.attacker.nominal_velocity
    turns = []
    for k in range(200):
        wx, wy = believed(world, Belief(intent_heading=60.0), np.random.default_rng(k)).attacker.nominal_velocity
        assert math.hypot(wx, wy) == pytest.approx(math.hypot(vx, vy), rel=1e-12)
        turns.append(math.degrees(math.atan2(vx * wy - vy * wx, vx * wx + vy * wy)))
    assert max(map(abs, turns)) <= 60.0 and max(turns) > 50.0 and min(turns) < -50.0
    with pytest.raises(ScenarioError, match="a random generator is needed"):
        believed(world, Belief(intent_heading=60.0))


@pytest.mark.parametrize("text, belief", [
    ("exact", Belief()), ("perception_radius=1.3x", Belief(perception_radius=1.3)),
    ("eta=3x,intent_heading=60", Belief(eta=3.0, intent_heading=60.0)),
])
def test_a_belief_is_written_as_its_errors(text, belief):
    assert parse_belief(text) == belief and parse_belief(belief.label()) == belief


@pytest.mark.parametrize("text, message", [
    ("radius=2x", "expected NAME=VALUE"), ("eta=fast", "eta's value 'fast' is not a number"),
    ("eta=0x", "belief.eta: must be positive"), ("intent_heading=400", "beyond the limit"),
])
def test_a_bad_belief_is_a_one_line_error(text, message):
    with pytest.raises(ScenarioError, match=message):
        parse_belief(text)


class Recorder:
    """Wraps a controller and keeps every observation it was given and every velocity it returned."""

    def __init__(self, controller):
        self.controller, self.seen, self.said = controller, [], []

    def command(self, obs):
        self.seen.append(obs)
        cmd = self.controller.command(obs)
        self.said.append(cmd.velocities.copy())
        return cmd

    def describe(self):
        return self.controller.describe()


@pytest.mark.parametrize("name", sorted(CONTROLLERS))
def test_a_controllers_commands_do_not_depend_on_the_worlds_behaviour_given_the_same_observations(name):
    """Run the gap-seeker's world for 40 s (two defenders sensed from the start, where the two laws differ), then replay its observations to the same controller built for a
    fleeing attacker's world: the commands are the same to the last bit."""
    base = dataclasses.replace(builtin_scenario("paper-open"),
                               hunt=dataclasses.replace(builtin_scenario("paper-open").hunt, time_limit=40.0))
    base = dataclasses.replace(base, attacker=dataclasses.replace(base.attacker, start=(14.0, 10.0)))
    options = OPTIONS if name in SOLVING else {}
    gap, flee = _with(base, "gap", sensing_radius=6.0), _with(base, "flee", sensing_radius=6.0)
    recorded = Recorder(make_controller(name, gap, **options))
    simulate(gap, recorded)
    replayed = make_controller(name, flee, **options)
    assert len(recorded.seen) == 400
    for obs, velocities in zip(recorded.seen, recorded.said):
        np.testing.assert_array_equal(replayed.command(obs).velocities, velocities)


def test_the_worlds_behaviour_changes_the_hunt():
    """The same controller in two worlds sees different observations: the behaviour is the world's."""
    base = builtin_scenario("paper-open")
    base = dataclasses.replace(base, attacker=dataclasses.replace(base.attacker, start=(14.0, 10.0)),
                               hunt=dataclasses.replace(base.hunt, time_limit=40.0))
    worlds = [_with(base, b, sensing_radius=6.0) for b in ("gap", "flee")]
    paths = [simulate(w, make_controller("voronoi", w)).attacker for w in worlds]
    assert not np.array_equal(paths[0], paths[1])


def test_an_observation_carries_no_behaviour():
    assert {f.name for f in dataclasses.fields(Observation)} == {"time", "attacker", "previous_attacker",
                                                                  "defenders", "failed"}


def test_the_cli_and_the_sweep_draw_the_belief_from_the_one_function_with_todays_streams(monkeypatch):
    """``mpc-hunt simulate --seed S``: child 0 of SeedSequence(S); sweep hunt (seed, index, member): child 1 of
    its node (index, member), beside the world's child 0. Both from :func:`belief_rng`."""
    import argparse

    from mpc_hunt.cli import commands
    from mpc_hunt.sweep import runner

    assert belief_rng(5).bit_generator.state == \
        np.random.default_rng(np.random.SeedSequence(5).spawn(1)[0]).bit_generator.state
    node = np.random.SeedSequence(7).spawn(4)[3].spawn(3)[2]
    assert belief_rng(7, 3, 2).bit_generator.state == np.random.default_rng(node.spawn(2)[1]).bit_generator.state
    asked = []

    def spy(*args):
        asked.append(args)
        return belief_rng(*args)

    monkeypatch.setattr(commands, "belief_rng", spy)
    monkeypatch.setattr(runner, "belief_rng", spy)
    _, world, drawn = commands._world(argparse.Namespace(attacker=None, seed=5), builtin_scenario("paper-open"))
    assert drawn.bit_generator.state == belief_rng(5).bit_generator.state
    assert world.bit_generator.state == np.random.default_rng(5).bit_generator.state
    assert runner.hunt_rngs(7, 3, 2)[1].bit_generator.state == belief_rng(7, 3, 2).bit_generator.state
    assert asked == [(5,), (7, 3, 2)]

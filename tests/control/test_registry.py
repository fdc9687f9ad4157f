"""A controller is one registry line: a solving one its reference × the capture stage, found by the CLI."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from conftest import ATTACKER, DEFENDERS, small_scenario
from mpc_hunt.capture.problem import EncloseWeights, Reference
from mpc_hunt.cli.commands import build_parser
from mpc_hunt.control import controllers
from mpc_hunt.control.controller import Observation
from mpc_hunt.control.reference import Places
from mpc_hunt.control.spec import make_controller


class Stay(Places):
    """A throwaway reference: every defender's place is where it stands."""

    NAME = "stay"
    SUMMARY = "a throwaway controller that holds every defender where it stands"
    weights = EncloseWeights(attacker=0.0)

    def __init__(self, scenario, horizon):
        self.horizon = horizon

    def reference(self, obs):
        places = np.repeat(obs.defenders[None], self.horizon, axis=0)
        return Reference(places, np.repeat(obs.attacker[None], self.horizon, axis=0), np.ones(self.horizon))


@pytest.fixture
def stay(monkeypatch):
    monkeypatch.setitem(controllers.CONTROLLERS, "stay", controllers.Solving(Stay))
    monkeypatch.setattr(controllers, "SOLVING", controllers.SOLVING + ("stay",))     # as one more line would make it


def _controller_action(parser):
    simulate = next(a for a in parser._subparsers._group_actions[0].choices["simulate"]._actions
                    if a.dest == "controller")
    return simulate


def test_a_registered_controller_is_in_the_clis_choices_and_help_and_runs(stay):
    action = _controller_action(build_parser())
    assert "stay" in action.choices and Stay.SUMMARY in action.help
    controller = make_controller("stay", small_scenario(), horizon=3)
    command = controller.command(Observation(0.0, ATTACKER, None, DEFENDERS))
    assert controller.describe()["controller"] == "stay"
    assert command.solution.success and np.allclose(command.velocities, 0.0, atol=1e-6)


def test_every_controller_is_described_in_the_help_not_only_listed():
    action = _controller_action(build_parser())
    for name, entry in controllers.CONTROLLERS.items():
        assert f"{name}: {entry.SUMMARY}" in action.help


def test_the_solving_controllers_are_those_that_pose_an_objective():
    assert set(controllers.SOLVING) == {"paper", "enclose", "contain", "adapt", "trap"}
    for name in controllers.SOLVING:
        assert controllers.controller_objective(name) in ("paper", "enclose")


def test_the_docs_table_of_controllers_is_the_registrys():
    docs = (Path(__file__).resolve().parents[2] / "docs" / "architecture.md").read_text(encoding="utf-8")
    block = docs.split("<!-- controllers:start -->\n", 1)[1].split("<!-- controllers:end -->", 1)[0]
    assert block == controllers.table(), "docs/architecture.md: replace the controllers block with:\n" + \
        controllers.table()

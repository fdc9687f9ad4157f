"""A sweep builds each strategy's controller and each attacker's behaviour once before any hunt: one that cannot be
built (a damaged shipped network) is one line on stderr with exit status 2, as simulate says it, never a sweep of
hunts that all end in the same error and exit 0. The shipped files are only read here: the damaged ones are
copies in a temporary folder, put in their place by monkeypatching the name the loader reads."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from mpc_hunt.cli.commands import main
from mpc_hunt.control import ppo_team
from mpc_hunt.errors import SettingError
from mpc_hunt.sweep.random_scenario import ScenarioRanges
from mpc_hunt.sweep.runner import DEFAULT_STRATEGIES, check_buildable
from mpc_hunt.world import mlp
from mpc_hunt.world.behaviours import BEHAVIOURS
from mpc_hunt.world.behaviours import ppo as ppo_attacker

NETWORKS = {"team": (ppo_team, "TEAM_POLICY"), "attacker": (ppo_attacker, "ATTACKER_POLICY")}  # module, its network
FLAGS = {  # the sweep's flags that play each network, the field its refusal names, simulate's flags
    "team": (["--strategy", "ppo"], "--strategy: ppo", ["--controller", "ppo"]),
    "attacker": (["--strategy", "apf", "--attacker", "ppo"], "--attacker: ppo", ["--attacker", "ppo"]),
}


def _damaged(side: str) -> dict[str, bytes]:
    module, name = NETWORKS[side]
    good = Path(str(getattr(module, name).file())).read_bytes()
    return {"text": b"not a network\n", "empty": b"", "truncated": good[: len(good) // 2]}


@pytest.fixture
def no_hunt(monkeypatch):
    """Nothing of the sweep may start (no results file, no hunt) before the refusal."""
    for where in ("mpc_hunt.sweep.store.SweepStore", "mpc_hunt.sweep.stored_run.run_into"):
        monkeypatch.setattr(where, lambda *a, **k: pytest.fail("the sweep started"))


@pytest.mark.parametrize("damage", ["text", "empty", "truncated"])
@pytest.mark.parametrize("side", list(NETWORKS))
def test_a_damaged_network_stops_the_sweep_in_one_line_before_any_hunt(capsys, monkeypatch, tmp_path, no_hunt,
                                                                       side, damage):
    module, name = NETWORKS[side]
    shipped = getattr(module, name)
    bad = tmp_path / shipped.name
    bad.write_bytes(_damaged(side)[damage])
    monkeypatch.setattr(module, name, replace(shipped, name=str(bad)))   # as if the shipped file were damaged
    loads = []
    load = mlp.load_mlp
    monkeypatch.setattr(mlp, "load_mlp", lambda *a: loads.append(a) or load(*a))
    flags, named, simulate = FLAGS[side]
    output = tmp_path / "sweep.db"
    code = main(["sweep", *flags, "--hunts", "50", "--output", str(output)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(f"mpc-hunt sweep: error: {named} cannot be built: {bad}: "), err
    assert len(loads) == 1                                           # once, not once per hunt
    assert not output.exists()
    assert main(["simulate", *simulate, "--json"]) == 2                 # as simulate refuses it
    assert f"{bad}: " in capsys.readouterr().err


def test_the_shipped_strategies_and_attackers_can_be_built():
    check_buildable([*DEFAULT_STRATEGIES, "ppo"], list(BEHAVIOURS), 0, ScenarioRanges())


def test_a_strategy_that_cannot_be_built_is_refused_naming_strategies(monkeypatch, tmp_path):
    bad = tmp_path / "team.npz"
    bad.write_text("not a network\n")
    monkeypatch.setattr(ppo_team, "TEAM_POLICY", replace(ppo_team.TEAM_POLICY, name=str(bad)))
    with pytest.raises(SettingError) as exc:
        check_buildable(["apf", "ppo"], ["gap"], 0, ScenarioRanges())
    assert exc.value.fields == ("strategies",) and str(exc.value).startswith(f"strategies: ppo cannot be built: {bad}")

"""Committed numbers stay true: the studies' --check (run by studies/check_all.py, CI's step after the tests) and what
the checks themselves must catch."""

from __future__ import annotations

import dataclasses
import importlib
import json
import subprocess
import sys
from pathlib import Path

import pytest

from mpc_hunt import builtin_scenario, simulate

ROOT = Path(__file__).resolve().parents[1]


def test_the_checks_run_every_study_that_takes_one_and_fail_when_one_fails(monkeypatch, capsys):
    """``studies/check_all.py`` (CI's step after the tests): every study with a --check, its status 1 on a failure."""
    check_all = _study("check_all")
    assert {"reproduce_paper", "compare", "realtime", "attackers", "team_size", "sweep"} <= set(check_all.checked())
    assert "check_all" not in check_all.checked() and "study_check" not in check_all.checked()
    with pytest.raises(SystemExit) as exc:
        check_all.main(["no_such_study"])
    assert exc.value.code == 2 and "no study 'no_such_study' takes --check" in capsys.readouterr().err
    monkeypatch.setattr(check_all, "check", lambda name: (name, subprocess.CompletedProcess(
        [], 1 if name == "compare" else 0, "", "differs"), 0.0))
    assert check_all.main(["compare", "sweep"]) == 1
    out = capsys.readouterr().out
    assert "FAILED compare" in out and "ok sweep" in out and "1 of 2 studies' checks pass" in out


def _study(name: str):
    sys.path.insert(0, str(ROOT))
    try:
        return importlib.import_module(f"studies.{name}")
    finally:
        sys.path.remove(str(ROOT))


def test_the_reproduction_check_fails_for_a_one_percent_change_of_the_field_gain():
    """The band must not be so wide that a real change of the model passes: η × 1.01 on one robust run."""
    reproduce = _study("reproduce_paper")
    committed = json.loads((ROOT / "studies" / "reproduction" / "results.json").read_text(encoding="utf-8"))
    scenario = builtin_scenario("paper-open")
    nominal = reproduce.report(simulate(scenario, prediction=False))
    assert reproduce.differing(committed, {"paper-open-no-prediction": nominal}) == []
    changed = dataclasses.replace(scenario, hunt=dataclasses.replace(scenario.hunt, eta=1.01 * scenario.hunt.eta))
    errors = reproduce.differing(committed, {"paper-open-no-prediction": reproduce.report(
        simulate(changed, prediction=False))})
    assert any("path_lengths_m" in e for e in errors), errors


def test_the_sweep_check_reruns_robust_hunts_and_holds_them_to_their_bands():
    sweep = _study("sweep")
    steps = {"median": 100.0, "min": 98.0, "max": 104.0}
    entry = {"robust": True, "outcome": "captured", "cause": None, "termination": "captured", "wall_time_s": 1.0,
             "band": {k: steps if k in ("steps", "solves") else None for k in sweep.BANDED}}
    hunts = {"0": {**entry, "robust": False}, "1": entry, "2": {**entry, "wall_time_s": 0.5},
             "3": {**entry, "outcome": "failed", "cause": "attacker_escaped", "termination": "escaped"}}
    assert sweep.rerun_choice(hunts) == ["2", "3"]
    row = {k: None for k in sweep.BANDED} | {"outcome": "captured", "cause": None, "termination": "captured",
                                              "steps": 101, "solves": 101}
    assert sweep._off_band("h", entry, row) == []
    assert [e.split(":")[1].split()[0] for e in sweep._off_band("h", entry, row | {"steps": 108})] == ["steps"]
    assert sweep._off_band("h", entry, row | {"outcome": "failed"})

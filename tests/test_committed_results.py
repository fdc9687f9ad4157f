"""Committed numbers stay true: the studies' --check reruns them and compares with what is committed."""

from __future__ import annotations

import dataclasses
import importlib
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from mpc_hunt import builtin_scenario, simulate

ROOT = Path(__file__).resolve().parents[1]


STUDIES = ["studies/attackers.py", "studies/team_sweep.py", "studies/team_size.py", "studies/step_latency.py",
           "studies/reproduce_paper.py", "studies/default_problems.py", "studies/sweep.py", "studies/compare.py",
           "studies/realtime.py", "studies/train_attacker.py", "studies/train_ppo.py", "studies/env_throughput.py"]
CHECKS_AT_ONCE = 2        # the studies' checks run side by side (none times anything), the slowest first


def _check(study: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    # The study imports this tree's code, not whichever copy of mpc_hunt is installed.
    return subprocess.run([sys.executable, study, "--check"], cwd=ROOT, capture_output=True, text=True, env=env)


@pytest.fixture(scope="module")
def checks(request):
    """The ``--check`` of every study the session selected, started at once on ``CHECKS_AT_ONCE`` workers."""
    chosen = [item.callspec.params["study"] for item in request.session.items
              if getattr(item, "originalname", None) == "test_committed_results_match_the_code"]
    with ThreadPoolExecutor(max_workers=CHECKS_AT_ONCE) as pool:
        yield {study: pool.submit(_check, study) for study in chosen}


@pytest.mark.parametrize("study", STUDIES)
def test_committed_results_match_the_code(study, checks):
    run = checks[study].result()
    assert run.returncode == 0, run.stderr[-2000:]


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

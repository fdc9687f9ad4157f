"""Committed numbers stay true: the studies' --check reruns them and compares with what is committed."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("study", ["studies/reproduce_paper.py", "studies/default_problems.py", "studies/compare.py",
                                   "studies/realtime.py", "studies/sweep.py",
                                   "studies/step_latency.py"])
def test_committed_results_match_the_code(study):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    # The study imports this tree's code, not whichever copy of mpc_hunt is installed.
    run = subprocess.run([sys.executable, study, "--check"], cwd=ROOT, capture_output=True, text=True, env=env)
    assert run.returncode == 0, run.stderr[-2000:]

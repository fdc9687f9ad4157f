"""Without Numba's compiler (``NUMBA_DISABLE_JIT=1``, as where Numba is absent) the rules run as plain Python: the
same hunts, to the bit."""

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HUNTS = """
import dataclasses, json, numpy as np
from mpc_hunt.control.spec import ControllerSpec
from mpc_hunt.sim.simulator import simulate
from mpc_hunt.sweep.random_scenario import ScenarioRanges, sweep_scenario
from mpc_hunt.world.behaviours import with_behaviour
out = []
hunts = [("voronoi", "gap"), ("apf", "minimax"), ("voronoi", "noisy"), ("apf", "flee"), ("trap", "gap")]
for i, (c, a) in enumerate(hunts):
    s = with_behaviour(sweep_scenario(3, i, ScenarioRanges(n_obstacles=(1, 3))), a)
    s = dataclasses.replace(s, hunt=dataclasses.replace(s.hunt, time_limit=15.0 if c != "trap" else 4.0))
    r = simulate(s, ControllerSpec.parse(c).build(s), rng=np.random.default_rng(i))
    out.append([r.attacker.tolist(), r.defenders.tolist(), r.termination])
print(json.dumps(out))
"""


def _hunts(**env) -> list:
    run = subprocess.run([sys.executable, "-c", HUNTS], capture_output=True, text=True, timeout=600, cwd=ROOT,
                         env={**os.environ, "PYTHONPATH": str(ROOT), **env})
    assert run.returncode == 0, run.stderr[-2000:]
    return json.loads(run.stdout)


def test_the_plain_python_rules_give_the_compiled_ones_hunts():
    assert _hunts(NUMBA_DISABLE_JIT="1") == _hunts()

"""The team sweep's headline (studies/team_sweep.py) pairs the distributed stage with the centralised one hunt by
hunt, on the hunts each rate counts."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from studies import team_sweep  # noqa: E402


def _row(strategy, index, captured, *, comfortable=1, capturable=1):
    return {"strategy": strategy, "attacker": "gap", "belief": "exact", "seed": 4, "index": index,
            "outcome": "captured" if captured else "failed", "comfortable": comfortable,
            "capturable_by_definition": capturable}


def test_the_paired_column_counts_the_hunts_its_rate_counts_and_tells_apart_what_its_interval_does():
    central, distributed = team_sweep.CENTRAL, team_sweep.DISTRIBUTED
    rows = [_row(central, i, i < 20, comfortable=int(i < 30)) for i in range(60)]
    rows += [_row(distributed, i, i < 35, comfortable=int(i < 30)) for i in range(60)]
    rows += [_row(s, 60 + i, False, comfortable=0, capturable=0) for s in (central, distributed) for i in range(4)]
    assert team_sweep.paired_cell(rows, "gap", "all") == "+25 (+13 to +35), 60: ahead"      # 15 of 60 more
    assert team_sweep.paired_cell(rows, "gap", "comfortable").endswith(", 30: ahead")      # 10 of 30 more
    assert team_sweep.paired_cell(rows, "flee", "all") == "–"

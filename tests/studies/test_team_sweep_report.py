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


def test_what_a_hunt_costs_is_each_cells_mean_and_each_strategys_core_hours():
    """``costs`` (both sweep studies' section): a cell's mean seconds a hunt, exact belief only; an attacker no
    strategy met is no row; every row of the file, whatever its belief, in the last sentence."""
    from studies.sweep_study import costs

    rows = [{**_row("b", i, True), "wall_time_s": t} for i, t in enumerate((1.0, 3.0))]
    rows += [{**_row("a", 0, True), "attacker": "apf", "wall_time_s": 7200.0},
             {**_row("a", 1, True), "belief": "eta=3x", "wall_time_s": 3600.0}]
    lines = costs(rows, "`x.db`")
    assert "| apf | 7200.00 | |" in lines and "| gap | | 2.00 |" in lines
    assert not any(line.startswith("| flee") for line in lines)
    assert lines[-2] == "Each strategy's hunts, exact belief, in core-hours: `a` 2.00, `b` 0.00; every row of `x.db`: 3.00."

"""A sweep study's last run kept beside its rerun (studies/previous_rows.py, the attackers study's section): rows
kept and read back, the hunts both runs ran counted alike, moved or changed, damaged files refused in one line."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from mpc_hunt.errors import DataFileError  # noqa: E402
from mpc_hunt.sweep.store import SweepStore  # noqa: E402
from studies import attackers, previous_rows, team_sweep  # noqa: E402
from studies.study_check import run_study  # noqa: E402


def _row(strategy, index, captured, *, attacker="gap", time=100.0, path=50.0):
    return {"strategy": strategy, "attacker": attacker, "belief": "exact", "seed": 1, "index": index,
            "comfortable": 1, "outcome": "captured" if captured else "failed",
            "cause": None if captured else "time_limit", "capture_time_s": time if captured else None,
            "path_length_m": path, "min_obstacle_clearance_m": 0.2, "min_defender_separation_m": 0.3, "steps": 900}


def test_rows_kept_from_a_results_file_read_back_as_they_were(tmp_path):
    rows = [_row("voronoi", i, i % 2 == 0, path=50.0 + i / 3) for i in range(5)]
    store = SweepStore(tmp_path / "sweep.db", attackers.arguments(5, 1))
    for row in rows:
        store.add(row)
    store.close()
    assert previous_rows.keep([tmp_path / "sweep.db"]) == [5]
    kept = previous_rows.read(tmp_path / "sweep.db")
    assert sorted(kept, key=lambda r: r["index"]) == rows          # every field, floats to the last bit
    table = "\n".join(previous_rows.again(rows, kept))
    assert "| `voronoi` | 5 | 5 | 5 | 0.00 s | 0 | 0 |" in table and "Outcomes changed" not in table


def test_the_rerun_counts_what_moved_and_names_what_changed():
    before = [_row("trap", i, i < 6) for i in range(20)]
    now = [_row("trap", i, i < 6, path=50.0 + (i == 3) * 1e-12) for i in range(6)]          # 3: the last bit
    now += [_row("trap", 6, True, time=130.0), _row("trap", 7, True, time=140.0)]          # now captured
    now += [_row("trap", i, False) for i in range(8, 20)]
    now[1] = _row("trap", 1, True, time=102.5)                                              # moved, captured
    now[0] = _row("trap", 0, False)                                                         # no longer captured
    now += [_row("trap", 40, True)]                                                         # not in the last run
    table = "\n".join(previous_rows.again(now, before))
    assert "| `trap` | 20 | 15 | 17 | 2.50 s | 2 | 1 |" in table
    assert "draw 0: captured at 100.0 s then, failed (time_limit) now" in table
    assert "draw 6: failed (time_limit) then, captured at 130.0 s now" in table
    many = [_row("trap", i, False) for i in range(30)]
    listed = previous_rows.again([_row("trap", i, True) for i in range(30)], many)
    assert sum(line.startswith("- `trap`") for line in listed) == previous_rows.LISTED
    assert f"- and {30 - previous_rows.LISTED} more" in "\n".join(listed)
    assert previous_rows.again(now, [_row("apf", 0, True)]) == ["No hunt of the last run was run again.", ""]


@pytest.mark.parametrize("content", ["{", "[]", '{"fields": ["strategy"], "rows": []}',
                                     json.dumps({"fields": list(previous_rows.FIELDS), "rows": [[1, 2]]}),
                                     json.dumps({"fields": list(previous_rows.FIELDS), "rows": 3})])
def test_a_damaged_kept_file_is_one_line_naming_it(content, tmp_path):
    (tmp_path / "sweep.previous.json").write_text(content, encoding="utf-8")
    with pytest.raises(DataFileError, match="sweep.previous.json") as error:
        previous_rows.read(tmp_path / "sweep.db")
    assert "\n" not in str(error.value)
    assert previous_rows.read(tmp_path / "absent.db") is None


def test_the_attackers_report_tells_apart_on_the_rerun_what_the_last_run_could_not():
    focus, baseline = attackers.FOCUS, attackers.BASELINE
    last = [_row(focus, i, i < 6) for i in range(10)] + [_row(baseline, i, i < 4) for i in range(10)]
    now = [_row(focus, i, i < 180) for i in range(300)] + [_row(baseline, i, i < 120) for i in range(300)]
    lines = attackers.last_run(now, last)
    gap = next(line for line in lines if line.startswith("| gap |"))
    assert "+20 (-10 to +44), 10: not told apart" in gap and "+20 (+15 to +24), 300: ahead" in gap
    assert "| `trap:rti:hpipm:10` | 10 | 6 | 6 | 0.00 s | 4 | 0 |" in "\n".join(lines)
    assert attackers.last_run(now, None) == []


@pytest.mark.parametrize("name, files", [("attackers", ("sweep.db",)), ("team_sweep", ("attackers.db", "teams.db"))])
def test_keeping_the_last_run_never_writes_over_a_kept_one(name, files, tmp_path, capsys):
    study = {"attackers": attackers, "team_sweep": team_sweep}[name]
    out = tmp_path / "study"
    out.mkdir()
    for file in files[:-1]:                                       # the last file missing: nothing kept of any
        SweepStore(out / file, attackers.arguments(5, 1)).close()
    assert run_study(lambda: study.main(["--keep-previous", "--output", str(out)])) == 2
    assert f"{files[-1]} does not exist" in capsys.readouterr().err
    assert not list(out.glob("*.previous.json"))
    SweepStore(out / files[-1], attackers.arguments(5, 1)).close()
    (out / f"{Path(files[0]).stem}.previous.json").write_text("kept", encoding="utf-8")
    assert run_study(lambda: study.main(["--keep-previous", "--output", str(out)])) == 2
    assert "already holds a run's rows" in capsys.readouterr().err
    assert (out / f"{Path(files[0]).stem}.previous.json").read_text(encoding="utf-8") == "kept"
    (out / f"{Path(files[0]).stem}.previous.json").unlink()
    assert study.main(["--keep-previous", "--output", str(out)]) == 0
    assert sorted(p.name for p in out.glob("*.previous.json")) == sorted(f"{Path(f).stem}.previous.json"
                                                                         for f in files)


def test_the_team_sweep_sets_each_file_beside_its_last_run(tmp_path):
    central, distributed = team_sweep.CENTRAL, team_sweep.DISTRIBUTED

    def results(name, rows):
        (tmp_path / name).unlink(missing_ok=True)
        store = SweepStore(tmp_path / name, team_sweep.sweeps(5, 5, 4)[name][0])
        for row in rows:
            store.add(row)
        store.close()

    results("attackers.db", [_row(central, i, i < 5) for i in range(10)] + [_row(distributed, i, i < 3)
                                                                             for i in range(10)])
    results("teams.db", [_row(central, i, True, attacker="apf") for i in range(3)])
    assert team_sweep.last_run(tmp_path) == []                    # nothing kept: no section
    previous_rows.keep([tmp_path / name for name in team_sweep.FILES])
    results("attackers.db", [_row(central, i, i < 150) for i in range(300)] + [_row(distributed, i, i < 90)
                                                                               for i in range(300)])
    text = "\n".join(team_sweep.last_run(tmp_path))
    assert "`attackers.db`: the last run's 20 hunts" in text and "`teams.db`: the last run's 3 hunts" in text
    assert "| `enclose:rti:hpipm:10` | 10 | 5 | 5 | 0.00 s | 5 | 0 |" in text and "| `enclose:rti:hpipm:10` | 3 | 3 | 3 |" in text
    gap = next(line for line in text.splitlines() if line.startswith("| gap |"))
    assert "-20 (-45 to +10), 10: not told apart" in gap and "-20 (-24 to -15), 300: behind" in gap

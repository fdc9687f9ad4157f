"""A study's --check on a missing or damaged committed results file: one line (exit 2), never a traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
STUDIES = [  # (study, its results file under studies/, the docs page its table lives in)
    ("engine", "engine/results.json", "engine.md"),
    ("env_throughput", "env_throughput/results.json", "envs.md"),
    ("compare", "compare/results.json", "benchmarks.md"),
]


@pytest.mark.parametrize("study, results, docs", STUDIES)
@pytest.mark.parametrize("content, said", [(None, "no such file"), ('{"rows": [', "not valid JSON")])
def test_a_missing_or_damaged_committed_result_is_one_line(tmp_path, study, results, docs, content, said):
    copy = tmp_path / "repo"
    (copy / "studies" / Path(results).parent).mkdir(parents=True)
    (copy / "docs").mkdir()
    for name in (f"{study}.py", "study_check.py", "docs_block.py", "__init__.py"):
        (copy / "studies" / name).write_text((ROOT / "studies" / name).read_text(encoding="utf-8"), encoding="utf-8")
    (copy / "docs" / docs).write_text((ROOT / "docs" / docs).read_text(encoding="utf-8"), encoding="utf-8")
    if content is not None:
        (copy / "studies" / results).write_text(content, encoding="utf-8")
    run = subprocess.run([sys.executable, f"studies/{study}.py", "--check"], cwd=copy, capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 2 and said in run.stderr and "Traceback" not in run.stderr, run.stderr[-500:]

"""studies/cpu_noise.py --check on a missing or damaged results.json: one line (exit 2) or a difference (exit 1),
never a traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("content, status, said", [
    (None, 2, "no such file"),
    ('{"rows": [', 2, "not valid JSON"),
    ("[1, 2]", 1, "not this study's results"),
    ('{"rows": [], "settings": {}}', 1, "not the processes and workload"),
])
def test_a_damaged_committed_result_is_one_line(tmp_path, content, status, said):
    copy = tmp_path / "repo"
    (copy / "studies" / "cpu_noise").mkdir(parents=True)
    (copy / "docs").mkdir()
    for name in ("cpu_noise.py", "study_check.py", "docs_block.py", "__init__.py"):
        source = ROOT / "studies" / name
        if source.exists():
            (copy / "studies" / name).write_text(source.read_text(encoding="utf-8"), encoding="utf-8")
    (copy / "docs" / "benchmarks.md").write_text((ROOT / "docs" / "benchmarks.md").read_text(encoding="utf-8"))
    if content is not None:
        (copy / "studies" / "cpu_noise" / "results.json").write_text(content)
    run = subprocess.run([sys.executable, "studies/cpu_noise.py", "--check"], cwd=copy, capture_output=True,
                         text=True, timeout=60)
    assert run.returncode == status and said in run.stderr and "Traceback" not in run.stderr

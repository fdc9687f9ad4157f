"""The README's Python example runs as written."""

from __future__ import annotations

from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_the_python_api_example_runs(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("MPC_HUNT_CACHE", str(tmp_path))
    block = README.read_text(encoding="utf-8").split("## Python API", 1)[1].split("```python", 1)[1].split("```", 1)[0]
    namespace: dict = {}
    exec(compile(block, str(README), "exec"), namespace)
    assert namespace["result"].captured
    assert namespace["solution"].success and namespace["status"].usable

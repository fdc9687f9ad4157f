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


def test_the_environment_examples_run(capsys):
    """Each of the README's environment examples, as written."""
    section = README.read_text(encoding="utf-8").split("## Environments", 1)[1].split("\n## ", 1)[0]
    blocks = [b.split("```", 1)[0] for b in section.split("```python")[1:]]
    assert len(blocks) == 3
    for block in blocks:
        namespace: dict = {}
        exec(compile(block, str(README), "exec"), namespace)
        assert namespace["observation" if "observation" in namespace else "observations"] is not None

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


def test_the_readme_the_docs_and_the_cli_name_the_same_recommended_controller():
    import re

    from mpc_hunt.cli.commands import build_parser
    from mpc_hunt.control.recommended import RECOMMENDED_CONTROLLER

    readme = README.read_text(encoding="utf-8")
    assert re.search(r"recommended\s+controller\s+\(`(\w+)`", readme).group(1) == RECOMMENDED_CONTROLLER
    envs = (README.parent / "docs" / "envs.md").read_text(encoding="utf-8")
    assert re.search(r"the recommended one, `(\w+)`", envs).group(1) == RECOMMENDED_CONTROLLER
    assert build_parser().parse_args(["simulate"]).controller == RECOMMENDED_CONTROLLER

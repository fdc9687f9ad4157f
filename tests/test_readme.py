"""The README and the manual's Python examples run as written, and name the same recommended controller as the CLI."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
GETTING_STARTED = ROOT / "docs" / "getting-started.md"  # the README's Python API block moved here
AGENTS = ROOT / "docs" / "guides" / "agents.md"  # and its environment examples here


def test_the_python_api_example_runs(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("MPC_HUNT_CACHE", str(tmp_path))
    page = GETTING_STARTED.read_text(encoding="utf-8")
    block = page.split("## Python API", 1)[1].split("```python", 1)[1].split("```", 1)[0]
    namespace: dict = {}
    exec(compile(block, str(GETTING_STARTED), "exec"), namespace)
    assert namespace["result"].captured
    assert namespace["solution"].success and namespace["status"].usable


def test_the_environment_examples_run(capsys):
    """Each of the environment examples of the agents' guide, as written."""
    section = AGENTS.read_text(encoding="utf-8").split("## Environments", 1)[1].split("\n## ", 1)[0]
    blocks = [b.split("```", 1)[0] for b in section.split("```python")[1:]]
    assert len(blocks) == 3
    for block in blocks:
        namespace: dict = {}
        exec(compile(block, str(AGENTS), "exec"), namespace)
        assert namespace["observation" if "observation" in namespace else "observations"] is not None


def test_the_readme_the_docs_and_the_cli_name_the_same_recommended_controller():
    import re

    from mpc_hunt.cli.commands import build_parser
    from mpc_hunt.control.recommended import RECOMMENDED_CONTROLLER

    for page in (README, GETTING_STARTED):
        text = page.read_text(encoding="utf-8")
        assert re.search(r"recommended\s+controller\s+\(`(\w+)`", text).group(1) == RECOMMENDED_CONTROLLER, page
    envs = (ROOT / "docs" / "envs.md").read_text(encoding="utf-8")
    assert re.search(r"the recommended one, `(\w+)`", envs).group(1) == RECOMMENDED_CONTROLLER
    assert build_parser().parse_args(["simulate"]).controller == RECOMMENDED_CONTROLLER


def test_the_readme_is_a_front_door_with_the_two_quick_start_commands():
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 120
    start = text.split("## Quick start", 1)[1].split("```sh\n", 1)[1].split("```", 1)[0]
    assert start == ('python3 -m pip install . && mpc-hunt simulate\n'
                     'python3 -m pip install ".[test]" && python3 -m pytest\n')
    assert GETTING_STARTED.read_text(encoding="utf-8").count(start) == 1  # the same two, in the manual

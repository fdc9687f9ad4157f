"""A study's headline figures in the docs: a block between markers, written by the study, compared by its --check.

    <!-- name:start -->  ...generated...  <!-- name:end -->
"""

from __future__ import annotations

from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs" / "benchmarks.md"


def _markers(name: str) -> tuple[str, str]:
    return f"<!-- {name}:start -->\n", f"<!-- {name}:end -->"


def read_block(name: str, path: Path = DOCS) -> str:
    """The text between the markers of ``name`` (an error if they are missing)."""
    start, end = _markers(name)
    text = path.read_text(encoding="utf-8")
    if start not in text or end not in text:
        raise SystemExit(f"{path}: the markers {start.strip()} ... {end} are missing")
    return text.split(start, 1)[1].split(end, 1)[0]


def write_block(name: str, block: str, path: Path = DOCS) -> None:
    """Replace the text between the markers of ``name`` with ``block``."""
    start, end = _markers(name)
    old = read_block(name, path)
    text = path.read_text(encoding="utf-8")
    path.write_text(text.replace(start + old + end, start + block + end), encoding="utf-8")

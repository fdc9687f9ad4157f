"""A compare run's report folder (``mpc-hunt compare --report``): the Markdown report, the JSON and the figures."""

from __future__ import annotations

from pathlib import Path

from mpc_hunt.bench.compare import CompareRun
from mpc_hunt.bench.compare_report import document, dumps, readme
from mpc_hunt.bench.compare_rows import rows as score_rows
from mpc_hunt.plots.compare import plot_compare


def write_report(run: CompareRun, machine: dict, folder: Path, command: str, extra: dict) -> list[Path]:
    """``README.md``, ``results.json`` (every solve included) and the figures, in ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    rows = score_rows(run)
    (folder / "results.json").write_text(
        dumps(document(run, machine, rows, extra, solves=True)) + "\n", encoding="utf-8"
    )
    figures = plot_compare(run, rows, folder)
    (folder / "README.md").write_text(readme(run, machine, rows, command, figures), encoding="utf-8")
    return [folder / "README.md", folder / "results.json", *figures]

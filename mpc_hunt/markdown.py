"""Markdown tables, written one way for every report (compare's, the sweep summary, the studies' READMEs), and the
same tables as plain text for the terminal (:func:`plain`).

A table is its header, the rule under it (a column's alignment: ``l``, left, ``---``; ``r``, right, ``---:``)
and a line per row; a cell is any value, written with ``str``, an empty one as ``| |``. Nothing is padded:
the lines are as short as their cells, so that a committed report stays the text its code renders.

    lines = table(["pair", "N", "ms"], "lrr", [["rti/hpipm", 10, "2.389"]])
    # ['| pair | N | ms |', '| --- | ---: | ---: |', '| rti/hpipm | 10 | 2.389 |']
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

RULES = {"l": "---", "r": "---:"}  # a column's alignment, as the rule under the header writes it


def row(cells: Iterable[object]) -> str:
    """One line of a table: ``| a | b |``."""
    return "|" + "".join(f" {text} |" if text else " |" for text in map(str, cells))


def rule(align: str) -> str:
    """The line under the header, a column a letter of ``align`` (``l`` or ``r``)."""
    unknown = set(align) - set(RULES)
    if unknown:
        raise ValueError(f"align: unknown {sorted(unknown)[0]!r} (known: {', '.join(RULES)})")
    return row(RULES[a] for a in align)


def table(header: Sequence[object], align: str, rows: Iterable[Iterable[object]] = ()) -> list[str]:
    """The table's lines: ``header``, the rule of ``align`` (a letter a column), a line a row."""
    if len(align) != len(header):
        raise ValueError(f"align: {len(align)} columns, the header has {len(header)}")
    return [row(header), rule(align), *map(row, rows)]


def plain(header: Sequence[object], align: str, rows: Iterable[Iterable[object]] = ()) -> str:
    """The table as plain text for the terminal: each column padded to its widest cell as ``align`` says (a letter a
    column, as :func:`table`'s), two spaces apart, no rule."""
    rule(align)  # (the letters checked)
    body = [list(map(str, header)), *(list(map(str, cells)) for cells in rows)]
    if len(align) != len(body[0]):
        raise ValueError(f"align: {len(align)} columns, the header has {len(body[0])}")
    widths = [max(len(line[i]) for line in body) for i in range(len(align))]
    return "\n".join(
        "  ".join(c.ljust(w) if a == "l" else c.rjust(w) for c, w, a in zip(line, widths, align)) for line in body
    )

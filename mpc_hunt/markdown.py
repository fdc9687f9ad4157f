"""Markdown tables, written one way for every report (compare's, the sweep summary, the studies' READMEs), and the
same tables as plain text for the terminal (:func:`plain`).

A table is its header, the rule under it (a column's alignment: ``l``, left, ``---``; ``r``, right, ``---:``)
and a line per row; a cell is any value, written with ``str``, an empty one as ``| |``. Nothing is padded:
the lines are as short as their cells, so that a committed report stays the text its code renders.

    lines = table(["pair", "N", "ms"], "lrr", [["rti/hpipm", 10, "2.389"]])
    # ['| pair | N | ms |', '| --- | ---: | ---: |', '| rti/hpipm | 10 | 2.389 |']

A report whose rows are dicts declares its columns once, each its header, its cell of a row and its alignment
(:class:`Column`; :func:`figure` writes a number), and renders them with :func:`columns_table` or
:func:`columns_plain`: a column's header and cell cannot drift apart.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

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


@dataclass(frozen=True)
class Column:
    """A column of a table of dict rows: its ``header``, its ``cell`` of a row, its alignment (``l`` or ``r``)."""

    header: str
    cell: Callable[[dict], object]
    align: str = "r"


def figure(key: str, fmt: str = "", scale: float = 1.0) -> Callable[[dict], str]:
    """The cell of ``row[key]`` times ``scale``, written with ``fmt``; "–" where the row has none (None)."""
    return lambda row: "–" if row.get(key) is None else format(row[key] * scale if scale != 1.0 else row[key], fmt)


def columns_table(columns: Sequence[Column], rows: Iterable[dict]) -> list[str]:
    """:func:`table` of ``rows``, a cell a column."""
    return table([c.header for c in columns], "".join(c.align for c in columns), _cells(columns, rows))


def columns_plain(columns: Sequence[Column], rows: Iterable[dict]) -> str:
    """:func:`plain` of ``rows``, a cell a column."""
    return plain([c.header for c in columns], "".join(c.align for c in columns), _cells(columns, rows))


def _cells(columns: Sequence[Column], rows: Iterable[dict]) -> Iterable[list[object]]:
    return ([c.cell(r) for c in columns] for r in rows)

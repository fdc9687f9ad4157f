"""The Markdown tables of every report: the lines as the committed reports hold them, nothing padded."""

from __future__ import annotations

import pytest

from mpc_hunt import markdown


def test_a_table_is_its_header_its_rule_and_a_line_a_row():
    assert markdown.table(["pair", "N", "ms"], "lrr", [["rti/hpipm", 10, "2.389"], ["qp/daqp", 5, "–"]]) == [
        "| pair | N | ms |", "| --- | ---: | ---: |", "| rti/hpipm | 10 | 2.389 |", "| qp/daqp | 5 | – |"]


def test_an_empty_cell_is_one_space_and_no_rows_leave_the_header():
    assert markdown.table(["bar", "measured", ""], "lll") == ["| bar | measured | |", "| --- | --- | --- |"]
    assert markdown.row(["met", ""]) == "| met | |"


def test_an_alignment_that_is_not_the_headers_is_refused():
    with pytest.raises(ValueError, match="2 columns, the header has 3"):
        markdown.table(["a", "b", "c"], "lr")
    with pytest.raises(ValueError, match="unknown 'c'"):
        markdown.rule("lc")


def test_a_plain_table_pads_each_column_to_its_widest_cell_as_aligned():
    text = markdown.plain(["pair", "N", "ms"], "llr", [["rti/hpipm", 10, "2.4"], ["qp/osqp", 1, "12.35"]])
    assert text.splitlines() == [
        "pair       N      ms",
        "rti/hpipm  10    2.4",
        "qp/osqp    1   12.35",
    ]
    with pytest.raises(ValueError, match="align: 2 columns"):
        markdown.plain(["a", "b", "c"], "lr")

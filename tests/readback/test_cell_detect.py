"""A robot cell's program told apart in a whole text (winder.readback.cells.detect_cell):
in time linear in the text, whatever blank lines it holds."""

from __future__ import annotations

import time

import pytest

from winder.readback.cells import detect_cell

BLANK_LINES = 200_000
LINEAR_S = 5.0  # a search of a few megabytes; one quadratic in the blank lines takes hours here


@pytest.mark.parametrize(("last", "cell"), [("DEF p( )", "krl"), ("def p():", "urscript"), ("MODULE p", "rapid"),
                                            ("G93", None)])
def test_blank_lines_are_searched_in_linear_time(last: str, cell: str | None) -> None:
    text = " \n\t\n" * (BLANK_LINES // 2) + f"  {last}\n"
    started = time.perf_counter()
    assert detect_cell(text) == cell
    assert time.perf_counter() - started < LINEAR_S

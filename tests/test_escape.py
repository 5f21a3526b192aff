"""winder.escape: text from a file name or a config, written into each output format, reads back as the
one comment, string or field it was written as (issue 45: a `.wind` named "j\\nanalysis: {...}\\n#.wind"
gave `convert` a YAML with an extra top-level key). Read back by each format's own reader where Python
has one (PyYAML, csv, ast for URScript's Python-like strings, html)."""

from __future__ import annotations

import ast
import csv
import html
import io

import pytest
import yaml

from winder import escape

HOSTILE = ["j\nanalysis: {pressure: 5}\n#.wind", "k\ranalysis: {pressure: 5}\r#", "m\u2028analysis: 5\u2028#",
           "n\x85analysis: 5", 'quote " and \\ backslash', "paren ) G0 X999 ( again", "tab\tand\x00nul",
           "=HYPERLINK(\"x\")", "*HEADING", "**", "<script>alert(1)</script> & 'x'", "ünïcödé 角度", ""]


@pytest.mark.parametrize("text", HOSTILE)
def test_yaml_string_and_comment_read_back(text: str) -> None:
    assert yaml.safe_load(f"k: {escape.yaml_string(text)}\n") == {"k": text}
    assert yaml.safe_load(f"a: 1  # {escape.yaml_comment(text)}\nb: 2\n") == {"a": 1, "b": 2}


@pytest.mark.parametrize("text", HOSTILE)
def test_comments_stay_on_their_line(text: str) -> None:
    for helper in (escape.gcode_comment, escape.krl_comment, escape.rapid_comment, escape.urscript_comment,
                   escape.abaqus_text, escape.yaml_comment):
        out = helper(text)
        assert len(out.splitlines()) <= 1 and out.isprintable(), (helper.__name__, out)
    assert "(" not in escape.gcode_comment(text) and ")" not in escape.gcode_comment(text)
    assert not escape.abaqus_text(text).startswith("*")


@pytest.mark.parametrize("text", HOSTILE)
def test_strings_read_back_as_one_literal(text: str) -> None:
    line = escape.one_line(text)
    assert ast.literal_eval(escape.urscript_string(text)) == line  # URScript strings are Python's
    rapid = escape.rapid_string(text)
    assert rapid[0] == rapid[-1] == '"' and '"' not in rapid[1:-1].replace('""', "")
    assert rapid[1:-1].replace('""', '"').replace("\\\\", "\\") == line[:escape.RAPID_STRING_MAX]
    krl = escape.krl_string(text)
    assert krl[0] == krl[-1] == '"' and '"' not in krl[1:-1]


@pytest.mark.parametrize("text", HOSTILE)
def test_csv_field_is_one_field(text: str) -> None:
    row = next(csv.reader(io.StringIO(f"1,{escape.csv_field(text)},2\r\n")))
    assert len(row) == 3 and row[0] == "1" and row[2] == "2"
    assert row[1].removeprefix("'") == escape.one_line(text)
    assert not row[1][:1] in ("=", "+", "@") and not (row[1][:1] == "-" and row[1] != "-")


@pytest.mark.parametrize("text", HOSTILE)
def test_html_text_is_text(text: str) -> None:
    out = escape.html_text(text)
    assert "<" not in out and ">" not in out and html.unescape(out) == text


def test_numbers_are_not_formulas() -> None:
    assert escape.csv_field("-12.5") == "-12.5" and escape.csv_field("-x") == "'-x"

"""Text from a file name or a config written into another file format: one helper per format.

A config's path, a `.wind` file's name, a job's name reach YAML (`convert`), G-code and robot-program
comments, an Abaqus deck's heading, CSV and HTML. Whatever their bytes, each helper gives text that the
format reads as the one comment, string or field it is written as: no line break (a newline, a carriage
return, U+2028, NEL: every character that is not printable becomes a space), no closing quote or
parenthesis, no keyword. docs/guide/output-files.md lists them.
"""

from __future__ import annotations

import json

__all__ = ["abaqus_text", "csv_field", "gcode_comment", "html_text", "krl_comment", "krl_string", "one_line",
           "rapid_comment", "rapid_string", "urscript_comment", "urscript_string", "yaml_comment", "yaml_string"]

RAPID_STRING_MAX = 80  # characters of a RAPID string (ABB's limit)


def one_line(text: object) -> str:
    """text on one line: every character that is not printable (line and paragraph separators, tabs,
    controls) a space, runs of spaces one."""
    return " ".join("".join(c if c.isprintable() else " " for c in str(text)).split())


def yaml_comment(text: object) -> str:
    """Text for after `# ` on a YAML line: one line, so nothing after it is read as YAML."""
    return one_line(text)


def yaml_string(text: object) -> str:
    """A YAML double-quoted scalar reading back as text exactly (JSON's string syntax, ASCII escapes: a
    YAML 1.1 reader folds a raw U+2028 or NEL as a line break)."""
    return json.dumps(str(text), ensure_ascii=True)


def gcode_comment(text: object) -> str:
    """Text for a G-code comment, `; text` or `(text)`: one line, parentheses made brackets (a `)` ends
    a parenthesized comment, and the rest of the line would be read as words)."""
    return one_line(text).replace("(", "[").replace(")", "]")


def krl_comment(text: object) -> str:
    """Text after `;` in KRL (to the end of the line)."""
    return one_line(text)


def rapid_comment(text: object) -> str:
    """Text after `!` in RAPID (to the end of the line)."""
    return one_line(text)


def urscript_comment(text: object) -> str:
    """Text after `#` in URScript (to the end of the line)."""
    return one_line(text)


def krl_string(text: object) -> str:
    """A KRL string literal: KRL has no escape for `"`, so a quote becomes an apostrophe."""
    return '"' + one_line(text).replace('"', "'") + '"'


def rapid_string(text: object) -> str:
    """A RAPID string literal: `"` and `\\` doubled (RAPID's escapes), at most RAPID_STRING_MAX characters."""
    body = one_line(text)[:RAPID_STRING_MAX]
    return '"' + body.replace("\\", "\\\\").replace('"', '""') + '"'


def urscript_string(text: object) -> str:
    """A URScript string literal: `\\` and `"` escaped with a backslash."""
    return '"' + one_line(text).replace("\\", "\\\\").replace('"', '\\"') + '"'


def abaqus_text(text: object) -> str:
    """A data line of an Abaqus / CalculiX deck (the *HEADING's title): one line, not starting with `*`
    (a keyword line, or a `**` comment)."""
    return one_line(text).lstrip("*").lstrip() or "-"


def csv_field(text: object) -> str:
    """A CSV field (RFC 4180): one line, quoted with its quotes doubled where it holds a comma or a
    quote; a field a spreadsheet would run as a formula (= + - @ first) gets a leading `'`."""
    value = one_line(text)
    if value[:1] in ("=", "+", "-", "@") and not _number(value):
        value = "'" + value
    if any(c in value for c in ',"'):
        return '"' + value.replace('"', '""') + '"'
    return value


def _number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def html_text(text: object) -> str:
    """Text for HTML content or a quoted attribute: &, <, >, " and ' escaped (html.escape)."""
    import html  # noqa: PLC0415

    return html.escape(str(text), quote=True)

"""One output file against its reference, compared by the file's kind (winder.app.compare's rules)."""

from __future__ import annotations

from winder.app.compare import MAX_SHOWN, Difference, compare_bytes, compare_csv, compare_lines
from winder.app.compare_ply import compare_ply
from winder.app.compare_summary import compare_json
from winder.export import registry


def compare_file(file_name: str, expected: bytes, got: bytes,
                 limit: int = MAX_SHOWN) -> tuple[list[Difference], int]:
    """Compare one output with its reference by the file's kind (see the module docstring)."""
    if expected == got:
        return [], 0
    fmt = registry.format_of(file_name)
    kind = "gcode" if fmt is None else fmt.name  # an unknown file: as lines of words and numbers
    if kind == "ply":  # float32 vertices: within their last bit
        return compare_ply(expected, got, limit=limit)
    if kind == "summary":
        compare = compare_json
    elif kind in _TEXT_COMPARE:
        compare = _TEXT_COMPARE[kind]
    else:  # another binary output
        return compare_bytes(expected, got)
    try:
        a, b = expected.decode("utf-8"), got.decode("utf-8")
    except UnicodeDecodeError:
        return compare_bytes(expected, got)
    return compare(a, b, limit=limit)


_TEXT_COMPARE = {"csv": compare_csv, "layup": compare_csv, "gcode": compare_lines}

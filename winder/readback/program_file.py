"""A winding program on disk, read line by line (simulate's input; winder.readback.gcode).

Nothing but the line being read is held: its dialect is found by one streaming pass (the same tests
as winder.readback.gcode.detect and cells.detect_cell, line by line), which also counts
the lines, and its moves by a second pass. A line longer than MAX_LINE_BYTES (a winder program's are
under 200 bytes) is refused naming it, so no line is read whole whatever the file holds. A robot
cell's program (KRL, RAPID, URScript) is read whole, within a size its caller bounds by its budget:
those readers resolve names across the file (a KRL move names a point of its .dat).

Lines split as str.splitlines splits a text (\\r\\n, \\r and the other line breaks); bytes that are
not UTF-8 (a Latin-1 accent in a comment) are read as U+FFFD, and a leading byte-order mark dropped.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator

from winder.config.files import checked_size
from winder.errors import ConfigError
from winder.export.dialects import marlin

_MARLIN_FIRST = marlin.HEADER.strip().upper()  # a marlin program's first text

MAX_LINE_BYTES = 1_000_000
# The line only a dialect writes, in the order the dialects are told apart. Multi-line: the same
# pattern matches a line (survey) and searches a whole text (cells.detect_cell).
# The leading blanks never cross a newline ([^\S\n]*, the same matches as \s*: with \s*, a text's
# search runs from every line start over all the blank lines after it, 76 s for 60,000 of them).
# A robot cell's program (URScript's def ends with a colon, KRL's DEF does not):
CELL_LINES = (("urscript", re.compile(r"^[^\S\n]*def\s+\w+\(\):", re.M)),
              ("krl", re.compile(r"^[^\S\n]*DEF\s+\w+\s*\([^)]*\)\s*$", re.M | re.I)),
              ("rapid", re.compile(r"^[^\S\n]*MODULE\s+\w+", re.M)))
# A G-code program, in upper case:
GCODE_LINES = (("linuxcnc", re.compile(r"^[ \t]*(N[0-9]+[ \t]*)?G0*93[ \t]*$", re.M)),)


class ProgramFile:
    """A program's file (and, for KRL's .src, the .dat beside it), checked at once: a regular file of
    at most max_bytes (opening a FIFO would block, /dev/zero never ends)."""

    def __init__(self, path: str, max_bytes: int, kind: str = "winding program") -> None:
        self.path = path
        self.paths = [path]
        if path.lower().endswith(".src"):  # a KRL program's points are in the .dat beside it
            src, dat = (".SRC", ".DAT") if path.endswith(".SRC") else (".src", ".dat")
            checked_size(path, path, kind, max_bytes)
            # a program split per layer (docs/math/10-robot-cell.md 10.10): the modules its .src calls,
            # every .src before every .dat, as the reader takes them
            folder = os.path.dirname(path)
            modules = [os.path.join(folder, m) for m in _called_modules(path)]
            self.paths = [path] + [m + src for m in modules] + [path[:-4] + dat] + [m + dat for m in modules]
        self.size = sum(checked_size(p, p, kind if p == path else "KRL module" if p.endswith(("src", "SRC"))
                                     else "KRL data list", max_bytes) for p in self.paths)

    def lines(self) -> Iterator[str]:
        """The lines of the file(s), in order, as str.splitlines gives them (module docstring)."""
        number = 0
        for k, path in enumerate(self.paths):
            try:
                fh = open(path, "rb")  # noqa: SIM115 - closed below, also when the reader stops early
            except OSError as exc:
                raise ConfigError(f"{path}: cannot read the file: {exc.strerror or exc}") from exc
            with fh:
                first = True
                while raw := fh.readline(MAX_LINE_BYTES + 1):
                    if len(raw) > MAX_LINE_BYTES and not raw.endswith(b"\n"):
                        raise ConfigError(f"{path}: line {number + 1}: longer than {MAX_LINE_BYTES:,} bytes, which "
                                          "no winding program's line is")
                    text = raw.decode("utf-8", errors="replace")
                    if first:
                        text, first = text.removeprefix("\ufeff"), False
                    pieces = text.splitlines() or [""]
                    number += len(pieces)
                    yield from pieces

    def text(self, limit: int) -> str:
        """The whole text (a robot cell's program), refused past limit bytes."""
        if self.size > limit:
            raise ConfigError(f"{self.path}: the program has {self.size:,} bytes, more than simulate reads for this "
                              f"job ({limit:,}: its plan's points, with room for the program's own lines)")
        return "\n".join(self.lines()) + "\n"

    def survey(self, max_lines: int) -> tuple[str | None, str, int]:
        """(cell dialect or None, G-code dialect, lines): one streaming pass, the dialect decided as
        gcode.detect and cells.detect_cell decide it over the whole text (module docstring); it
        stops past max_lines lines (the caller refuses the program: its dialect is then moot)."""
        found: set[str] = set()
        count, first = 0, None
        for line in self.lines():
            count += 1
            if count > max_lines:
                break
            if first is None and line.strip():
                first = line.lstrip().upper()
            if len(found) < len(_TESTS):
                upper = line.upper()
                found.update(name for name, pattern in _TESTS
                             if name not in found and pattern.match(upper if name in _UPPER else line))
        cell = next((name for name, _ in CELL_LINES if name in found), None)
        if first is not None and first.startswith(_MARLIN_FIRST):
            return cell, "marlin", count
        return cell, next((name for name, _ in GCODE_LINES if name in found), "generic"), count


def _called_modules(path: str) -> list[str]:
    """The layers' modules a KRL .src calls (`<name>_L<N>( )`, winder.readback.subprograms.KRL), each
    once, in order."""
    from winder.readback.subprograms import KRL  # noqa: PLC0415

    found: list[str] = []
    try:
        with open(path, "rb") as fh:  # of a size checked before
            for raw in fh:
                hit = KRL.call.match(raw.decode("utf-8", errors="replace").split(";")[0].strip())
                if hit and hit[1] not in found:
                    found.append(hit[1])
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the file: {exc.strerror or exc}") from exc
    return found


_UPPER = tuple(name for name, _ in GCODE_LINES)  # tested in upper case, as parse.detect tests them
_TESTS = (*CELL_LINES, *GCODE_LINES)

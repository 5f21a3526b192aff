"""Reading a winding program back: the text of any dialect winder writes (generic, marlin, linuxcnc,
robot) to its rows of logical axes and the pass each row belongs to (from the pass comments).

The result is in winder's axis conventions whatever the dialect: (carriage, rotation, cross_feed,
yaw) for a straight-axis winder (marlin's A and B negated back, its fixed cross-feed from the
`; fixed eye` comment), (x, y, z, i, j, k) for robot poses (their B and C read back as the unit
direction: winder.export.dialects.robot). A robot's program is a robot config's: its machine says so. Every row, the rapid to the start of a
linuxcnc program included, is one programmed point. A line that is not what the dialect writes is
an error naming the line. A program is refused unless it is whole and within the machine: one
without its end (M2: a file cut short; marlin writes no end, simulate checks that its last row ends
the plan), one with an axis value outside machine.limits, and a move no controller runs (a word
given twice, a value not finite or past MAX_WORD_VALUE, a feed F <= 0), naming the line and the value.
"""

from __future__ import annotations

import re

import numpy as np

from winder.config.machine import MachineConfig
from winder.readback.gcode_syntax import DETECTED as _DETECTED
from winder.readback.gcode_syntax import syntax_of, unwrap
from winder.readback.parsed import ParsedProgram
from winder.readback.program_file import GCODE_LINES, ProgramFile
from winder.errors import ConfigError
from winder.export.dialects import marlin
from winder.export.dialects import robot as poses
from winder.export.dialects.text import JOB_LINE

_PASS = re.compile(r"^layer\s+(\d+)\s+circuit\s+(\d+)\s+pass\s+(\d+)\s+(\w+)\s*$", re.ASCII | re.I)  # a comment's text
MAX_PASS_NUMBER = 10**9  # of a layer, circuit or pass in a pass comment: far past any plan (int64 keys)
_END = ("M2", "M30")  # either ends a program (M30 also rewinds it)
# (...) anywhere (never nested: RS274 refuses it; [^()] keeps a line of 200,000 `(` linear), ; to the end
_COMMENT = re.compile(r"\([^()]*\)|;.*$")
# A word: a letter and a decimal number of ASCII digits, as controllers read it (no exponent, no `_`,
# no other script's digits); words may be written without spaces (G1X54.303A-44.415).
_WORD = re.compile(r"([A-Z])[ \t]*([-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))[ \t]*")
_WORDS = re.compile(r"(?:[A-Z][ \t]*[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)[ \t]*)*")
_BLOCK_NUMBER = re.compile(r"^N[0-9]+\s*")
_PADDED_G = re.compile(r"^G0+(\d)$")  # G01 is G1, G00 is G0
_SKIP = {"G21", "G90", "G94", "G93", "%", "G21 G90 G94 G17 G40 G49 G80 G54"}
_ROLE_COLUMN = {"carriage": 0, "rotation": 1, "cross_feed": 2, "yaw": 3}
# The largest value of a word: a job's cumulative rotation stays below 1e9 deg (1.5 million points,
# less than a turn each); beyond, squared distances and times of the dynamics overflow to inf and nan.
MAX_WORD_VALUE = 1e12
# The moves simulate reads at most (its caller passes the plan's own bound): the work budget's points
# of a whole job, with room for a program's approach and turnaround rows.
MAX_MOVES = 3_000_000
BLOCK_ROWS = 65_536
# A robot cell's program is read whole (winder.readback.program_file): at most this per move (a
# KRL move is a LIN line and a DECL E6POS of about 200 bytes; RAPID's robtarget about 250).
CELL_BYTES_PER_MOVE = 1_000
CELL_BYTES_SLACK = 1_000_000


def detect(text: str) -> str:
    """The dialect of a program text, from what only that dialect writes (in any letter case)."""
    upper = text.upper()
    if upper.lstrip().startswith(marlin.HEADER.strip().upper()):
        return "marlin"
    return next((name for name, pattern in GCODE_LINES if pattern.search(upper)), "generic")


def _code(line: str) -> str:
    """A line's code as a controller reads it: comments and a block number dropped, upper case, single
    spaces, G01 as G1 (a program edited by hand or by another tool reads as the one winder wrote)."""
    if (line.isupper() and ";" not in line and "(" not in line and "\t" not in line and "  " not in line
            and line[0] != "N" and ("G0" not in line or line.startswith("G0 "))):
        return line  # as winder writes it: the regular expressions would change nothing (4x the time)
    code = _BLOCK_NUMBER.sub("", _COMMENT.sub("", line).strip().upper())
    return " ".join(_PADDED_G.sub(r"G\1", word) for word in code.split())


def parse_program(text: str | ProgramFile, machine: MachineConfig, source: str = "program",
                  max_moves: int = MAX_MOVES) -> ParsedProgram:
    """Read a program (its text, or its file read line by line: winder.readback.program_file)
    written for `machine`, its dialect detected from the text; refused past max_moves moves, as soon
    as the line past them is read (or at once when the text has more than twice as many lines: a
    winder program has a comment line per pass, not per move). Memory: the rows read, in numpy blocks."""
    from winder.readback.cell_programs import parse_cell  # noqa: PLC0415
    from winder.readback.cells import detect_cell  # noqa: PLC0415

    if isinstance(text, ProgramFile):
        cell, dialect, lines_in_text = text.survey(2 * max_moves + 10_000)
    else:
        cell, dialect, lines_in_text = detect_cell(text), None, text.count("\n") + 1
    if lines_in_text > 2 * max_moves + 10_000:  # a file's survey stops counting one line past that
        counted = f"{lines_in_text:,}" if isinstance(text, str) else f"more than {2 * max_moves + 10_000:,}"
        raise ConfigError(f"{source}: {counted} lines for at most {max_moves:,} moves, past what simulate "
                          f"reads for this job (its plan's points, with room for the program's own rows and comments)")
    if cell is not None:
        whole = text.text(CELL_BYTES_PER_MOVE * max_moves + CELL_BYTES_SLACK) if isinstance(text, ProgramFile) else text
        return parse_cell(whole, machine, source, cell)
    if dialect is None:
        dialect = detect(text)
    if machine.robot:  # a robot's poses are G-code too: the config says whose program it is
        dialect = "robot"
    syntax = syntax_of(machine, dialect, _code)
    own = syntax.controller.name not in _DETECTED  # read by the config's own controller, not by its text
    if own:
        dialect = syntax.controller.engine
    ax = machine.axes
    if dialect == "robot":
        letters, prefixes = poses.LETTERS, ("G1", "G0")
    elif dialect == "marlin":
        letters, prefixes = marlin.LETTERS, ("G1", "G0")
    else:
        letters, prefixes = (ax.carriage, ax.rotation, ax.cross_feed, ax.yaw), ("G1", "G0")
    rows = _Rows(len(letters))
    kinds: list[str] = []
    key, kind = (0, 0, 0), ""
    job, job_line = None, None
    fixed_z = None
    end = None
    tension, turns = np.nan, 0.0  # the tension set so far (N); whole turns a reset took off the rotation
    for number, raw in enumerate(text.lines() if isinstance(text, ProgramFile) else text.splitlines(), start=1):
        line = raw.strip()
        bare = syntax.bare(line)
        if not bare.startswith(("G1 ", "G0 ")):  # a move's line is read as before: the rest may be the controller's
            if (read := syntax.tension(bare)) is not None:
                tension = read
                continue
            if (said := syntax.comment(bare)) is not None:
                hit = _PASS.match(said)
                if hit:
                    key, kind = tuple(_pass_number(hit[i], line, number, source) for i in (1, 2, 3)), hit[4].lower()
                elif said.lower().startswith(JOB_LINE[1:].strip()) and job is None:
                    job, job_line = said[len(JOB_LINE[1:].strip()):].strip(), number
                elif ("; " + said).upper().startswith(marlin.FIXED_EYE.upper()):
                    fixed_z = _fixed_eye("; " + said, number, source)
                continue
            if (position := syntax.reset(bare)) is not None:
                turns = (rows.last_rotation - position) if rows.count else 0.0
                continue
        code = _code(line)
        if not code or code in _SKIP or (code.startswith("G64 P") and dialect == "linuxcnc") or (
                not code.startswith(("G1 ", "G0 ")) and syntax.skip(code)):  # linuxcnc's, or the controller's own
            continue
        if (code in _END or code == syntax.end) and dialect != "marlin":
            end = number
            continue
        if end is not None:
            raise ConfigError(f"{source}: line {number}: a move after the program's end (line {end}), "
                              f"got {line[:60]!r}")
        head, words = _words(code, prefixes, dialect, line, number, source)
        values = {letter: float(digits) for letter, digits in words}
        _check_words([letter + digits for letter, digits in words], values, number, source)
        extra = next((letter for letter in values if letter not in letters and letter != "F"), None)
        if extra is not None:  # Z0e999 reads as Z0 and E999: no axis of this machine
            raise ConfigError(f"{source}: line {number}: {extra} is no axis of this {dialect} program (its axes: "
                              f"{', '.join(letters)}, and F), got {line[:60]!r}")
        if rows.count >= max_moves:
            raise ConfigError(f"{source}: line {number}: more than {max_moves:,} moves, past what simulate reads "
                              f"for this job (its plan's points, with room for the program's own)")
        missing = [c for c in letters if c not in values]
        if missing:
            raise ConfigError(f"{source}: line {number}: axis {missing[0]} missing in {line[:60]!r}")
        if key == (0, 0, 0):  # winder writes a pass comment before a pass's first move
            raise ConfigError(f"{source}: line {number}: a move before any '; layer L circuit C pass P kind' "
                              f"comment, which winder writes before each pass and simulate reads, got {line[:60]!r}")
        row = [values[c] for c in letters]
        if turns and dialect != "robot":
            row[1] += turns
        rows.add(row, key, values.get("F", np.nan), number, tension)
        kinds.append(kind)
    if not rows.count:  # an empty file, or comments only: there is no last move to name a line by
        raise ConfigError(f"{source}: the program has no moves")
    if end is None and dialect != "marlin" and syntax.needs_end:
        last = rows.last_line
        raise ConfigError(f"{source}: line {last}: the program stops without its end "
                          f"({syntax.end or 'M2'}): cut short? got {rows.count} moves, the last on line {last}")
    written, keys_arr, feeds_arr, lines, tensions = rows.arrays()
    if syntax.wrap and dialect != "robot":  # a modulo axis: each move the shortest way
        written[:, 1] = unwrap(written[:, 1])
    table = written
    if dialect == "marlin":
        if fixed_z is None:
            raise ConfigError(f"{source}: a marlin program without its '{marlin.FIXED_EYE}' comment")
        table = np.column_stack([table[:, 0], -table[:, 1], np.full(len(table), fixed_z), -table[:, 2]])
    kinds_t = tuple(kinds)
    del kinds
    if dialect == "marlin":  # a move cut at full turns of A is one programmed move: its pieces joined
        keep = ~marlin_cuts(written, keys_arr)
        table, lines, keys_arr, feeds_arr = table[keep], lines[keep], keys_arr[keep], feeds_arr[keep]
        tensions = tensions[keep]
        kinds_t = tuple(k for k, ok in zip(kinds_t, keep.tolist()) if ok)
    if dialect == "robot":
        table = np.column_stack([table[:, :3], poses.directions(table[:, 3:5])])
    else:
        _check_limits(table, lines, machine, letters if dialect != "marlin" else (ax.carriage, ax.rotation,
                                                                                  ax.cross_feed, ax.yaw), source)
    name = syntax.controller.name if own else dialect
    return ParsedProgram(name, table, keys_arr, kinds_t, feeds_arr, lines, job, job_line=job_line,
                         tension=tensions, case_blind=syntax.case_blind)


class _Rows:
    """The moves read so far, gathered in numpy blocks of BLOCK_ROWS (72 bytes a move of 4 axes, where
    Python lists of floats took about 400): (values, pass key, feed, line number) per move."""

    def __init__(self, width: int) -> None:
        self.width, self.count, self.last_line, self.last_rotation = width, 0, 0, 0.0
        self._blocks: list[np.ndarray] = []
        self._open: list[tuple] = []

    def add(self, values: list[float], key: tuple[int, int, int], feed: float, number: int,
            tension: float = np.nan) -> None:
        self._open.append((*values, *key, feed, number, tension))
        self.count, self.last_line = self.count + 1, number
        self.last_rotation = values[1] if len(values) > 1 else 0.0
        if len(self._open) == BLOCK_ROWS:
            self._close()

    def _close(self) -> None:
        if self._open:
            self._blocks.append(np.array(self._open, dtype=float))
            self._open = []

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(values (m, width) float, keys (m, 3) int, feeds (m,) float, lines (m,) int, tensions (m,)
        float, N, nan before any); keys and line numbers are exact in float64 (below MAX_PASS_NUMBER
        and 2^53)."""
        self._close()
        block = np.concatenate(self._blocks) if len(self._blocks) != 1 else self._blocks[0]
        self._blocks = []
        w = self.width
        return (block[:, :w].copy(), block[:, w:w + 3].astype(np.int64), block[:, w + 3].copy(),
                block[:, w + 4].astype(np.int64), block[:, w + 5].copy())


def marlin_cuts(written: np.ndarray, keys: np.ndarray) -> np.ndarray:
    """(m,) bool: the rows of a marlin program (X A B as written) where marlin.turn_cuts cut a move:
    A one written unit short of a full turn, on the straight move between the rows either side (X
    and B within the written rounding), in the same pass."""
    m = written.shape[0]
    out = np.zeros(m, dtype=bool)
    if m < 3:
        return out
    unit = 10.0**-marlin.DECIMALS
    a = written[:, 1]
    near = np.minimum(np.abs(np.mod(a + unit + 180.0, 360.0) - 180.0), np.abs(np.mod(a - unit + 180.0, 360.0) - 180.0))
    mid = np.flatnonzero(near[1:-1] < 0.1 * unit) + 1
    if mid.size == 0:
        return out
    prev, cur, nxt = written[mid - 1], written[mid], written[mid + 1]
    span = nxt[:, 1] - prev[:, 1]
    f = np.where(span != 0.0, (cur[:, 1] - prev[:, 1]) / np.where(span != 0.0, span, 1.0), -1.0)
    on = ((f > 0.0) & (f < 1.0) & np.all(np.abs(prev[:, [0, 2]] + f[:, None] * (nxt[:, [0, 2]] - prev[:, [0, 2]])
                                              - cur[:, [0, 2]]) <= unit, axis=1)
          & np.all(keys[mid] == keys[mid + 1], axis=1))
    out[mid[on]] = True
    return out


def _pass_number(digits: str, line: str, number: int, source: str) -> int:
    value = int(digits) if len(digits) <= 12 else MAX_PASS_NUMBER + 1
    if value > MAX_PASS_NUMBER:
        raise ConfigError(f"{source}: line {number}: a layer, circuit or pass number past {MAX_PASS_NUMBER:g}, which "
                          f"no plan has, got {line[:60]!r}")
    return value


def _words(code: str, prefixes: tuple[str, ...], dialect: str, line: str, number: int,
           source: str) -> tuple[str, list[tuple[str, str]]]:
    """The move's command (G1, G0) and its words (letter, number text), with or without spaces
    between them; ConfigError naming the line for anything else."""
    head = next((p for p in prefixes if code.startswith(p) and not code[len(p):len(p) + 1].isdigit()), None)
    if head is None:
        raise ConfigError(f"{source}: line {number}: not a move of a {dialect} program: {line[:60]!r}")
    rest = code[len(head):].lstrip(" ")
    if "E" in rest or "N" in rest:  # a value Python reads (inf, nan, 1e300): said as one no controller moves to
        try:
            loose = {w[0]: float(w[1:]) for w in rest.split()}
        except (ValueError, IndexError):
            loose = None
        if loose is not None:
            _check_words(rest.split(), loose, number, source)
    if not _WORDS.fullmatch(rest):
        raise ConfigError(f"{source}: line {number}: unreadable number in {line[:60]!r} (a letter and a "
                          f"decimal number of ASCII digits per word, as controllers read them)")
    return head, _WORD.findall(rest)


def _fixed_eye(line: str, number: int, source: str) -> float:
    """The cross-feed of marlin's `; fixed eye: cross-feed Z70.000 mm ...` comment."""
    rest = line[len(marlin.FIXED_EYE):].split()
    try:
        value = float(rest[0])
    except (IndexError, ValueError) as exc:
        raise ConfigError(f"{source}: line {number}: unreadable cross-feed in the fixed-eye comment, got "
                          f"{line[:60]!r}") from exc
    if not np.isfinite(value):
        raise ConfigError(f"{source}: line {number}: the fixed-eye cross-feed must be a finite number, got {value!r}")
    return value


def _check_words(words: list[str], values: dict[str, float], number: int, source: str) -> None:
    """Refuse a move a controller refuses: an axis written twice (which one would it take?), a value
    that is not finite (a rotation has no travel limit to catch it), a feed it cannot move at."""
    if len(values) < len(words):
        twice = next(w[0] for i, w in enumerate(words) if any(v[0] == w[0] for v in words[:i]))
        raise ConfigError(f"{source}: line {number}: {twice} given twice in one move, got "
                          f"{' '.join(words)[:60]!r}")
    for letter, value in values.items():
        if not abs(value) <= MAX_WORD_VALUE:
            raise ConfigError(f"{source}: line {number}: {letter} must be a finite number within "
                              f"+-{MAX_WORD_VALUE:g}, got {value!r}")
    if "F" in values and not values["F"] > 0.0:
        raise ConfigError(f"{source}: line {number}: the feed F must be > 0 (no controller moves at it), "
                          f"got {values['F']!r}")


def _check_limits(table: np.ndarray, lines: np.ndarray, machine: MachineConfig, letters, source: str) -> None:
    """Refuse the first row with an axis outside the machine's travel (machine.limits) or not finite."""
    for role, (lo, hi) in machine.limits.items():
        column = table[:, _ROLE_COLUMN[role]]
        out = np.flatnonzero(~((column >= lo) & (column <= hi)))
        if out.size:
            k = out[0]
            raise ConfigError(f"{source}: line {lines[k]}: axis {letters[_ROLE_COLUMN[role]]} ({role}) outside the "
                              f"machine's limits [{lo:g}, {hi:g}] (machine.limits.{role}), got {float(column[k])!r}")

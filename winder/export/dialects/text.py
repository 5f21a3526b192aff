"""What every controller dialect writes the same way: the comment header, the layer, circuit and pass
comments, the number format, and one line per move (consecutive identical lines dropped).

A dialect (generic.py, robot.py) adds its machine description, the words of a move and its line prefix.
The text is deterministic: no timestamps, no timings.
"""

from __future__ import annotations

import dataclasses
import re
from typing import Protocol

import numpy as np

from winder.config.controllers import Controller
from winder.errors import ExportError
from winder.escape import gcode_comment
from winder.export.dialects.post_text import check_digits, controller_lines, render, reset_line, template_lines
from winder.export.fixed_text import fixed_rows, printed
from winder.machine.limits import AXIS_DECIMALS
from winder.machine.program import APPROACH, MotionProgram
from winder.winding.results import LayerPlan, PassKind

JOB_LINE = "; job:"  # the header line naming the job (simulate reads it back)
DECIMALS = AXIS_DECIMALS  # mm and deg: the limits hold for the values as written
MAX_LINE = 255  # characters (bytes as UTF-8) of a program line: LinuxCNC's limit, comments included
ELLIPSIS = "..."
_NEG_ZERO = re.compile(r"(?<![0-9])-(0\.0+)(?![0-9])")


@dataclasses.dataclass(frozen=True)
class Move:
    """One programmed line: the pass it comes from and the index of its contact point in the pass.

    values : the line's numbers as written (rounded): (carriage, rotation, cross_feed, yaw) for a
    winder, (x, y, z, i, j, k) for a robot pose.
    """

    layer: int
    circuit: int
    number: int
    kind: PassKind
    index: int
    values: tuple[float, ...]
    u: float = 0.0  # the contact point's fractional point index (densified passes); index its nearest


class Dialect(Protocol):
    """How one controller spells a program."""

    prefix: str  # the word starting a move line
    controller: Controller  # its description: header, preamble, footer, decimals, comments, tension

    def describe(self, program: MotionProgram) -> list[str]: ...  # machine comment lines

    def letters(self, program: MotionProgram) -> tuple[str, ...]: ...  # one per written column

    def decimals(self, program: MotionProgram) -> tuple[int, ...]: ...  # one per written column

    def first_lines(self, program: MotionProgram) -> list[str]: ...  # before the comment header

    def preamble(self, program: MotionProgram) -> list[str]: ...

    def end(self, program: MotionProgram) -> list[str]: ...

    def columns(self, program: MotionProgram) -> np.ndarray: ...  # (m, k) the values written

    def move_lines(self, program: MotionProgram, row: int, words: str,
                   prev: tuple[float, ...] | None, cur: tuple[float, ...]) -> list[str]: ...


class BaseDialect:
    """What a dialect does unless it says otherwise: its controller's header, preamble and footer
    (winder.config.controllers), the program's columns and `PREFIX words F<feed>` move lines."""

    prefix = "G1"

    def __init__(self, controller: Controller) -> None:
        self.controller = controller

    def first_lines(self, program: MotionProgram) -> list[str]:
        return template_lines(self.controller.header, program)

    def preamble(self, program: MotionProgram) -> list[str]:
        return template_lines(self.controller.preamble, program)

    def end(self, program: MotionProgram) -> list[str]:
        rotary = self.controller.rotary
        cancel = [rotary.cancel] if rotary.mode.startswith("reset") and rotary.cancel else []
        return cancel + template_lines(self.controller.footer, program)

    def columns(self, program: MotionProgram) -> np.ndarray:
        return program.values

    def move_lines(self, program: MotionProgram, row: int, words: str,
                   prev: tuple[float, ...] | None, cur: tuple[float, ...]) -> list[str]:
        # The whole feed column formatted once per program (fmt_column: fmt of each value).
        cached = getattr(self, "_feeds", None)
        if cached is None or cached[0] is not program:
            cached = (program, fmt_column(program.feed))
            _refuse_zero_feed(program, cached[1])
            self._feeds = cached
        return [f"{self.prefix} {words} F{cached[1][row]}"]


    def elapsed(self, program: MotionProgram, row: int) -> float:
        """The planned time (s, machine.dynamics, acceleration included) from the last row this
        dialect wrote to `row`: the rows a dialect leaves out (the same words) are part of the move
        that follows, so the written moves' times add up to the program's (winding_time_s)."""
        clock = getattr(self, "_clock", None)
        if clock is None or clock[0] is not program:
            clock = [program, np.cumsum(program.times.time_s), 0]
            self._clock = clock
        seconds = float(clock[1][row] - clock[1][clock[2]]) if row > clock[2] else 0.0
        clock[2] = row
        return seconds


def _refuse_zero_feed(program: MotionProgram, feeds: list[str]) -> None:
    """A feed the axes' top speeds hold below what DECIMALS decimals write reads F0.000, at which no
    controller moves (simulate refuses it): ExportError naming the move's pass."""
    zero = fmt(0.0)
    if zero not in feeds:
        return
    row = feeds.index(zero)
    where = next((f"layer {seg.layer} circuit {seg.circuit} pass {seg.number}: " for segments in program.segments
                  for seg in segments if seg.start <= row < seg.stop), "")
    raise ExportError(f"{where}machine.dynamics: a move's feed would be written F{zero} ({program.feed[row]:.3g} "
                      f"mm/min, held down by the axes' top speeds); raise the speeds in machine.dynamics, or use the "
                      f"linuxcnc dialect (inverse time)")


def fmt_significant(value: float, digits: int = 6) -> str:
    """A positive number with about `digits` significant digits, fixed-point (no exponent), at
    least DECIMALS decimals."""
    decimals = max(DECIMALS, digits - 1 - int(np.floor(np.log10(max(abs(value), 1e-12)))))
    return fmt(value, min(decimals, 12))


def fmt(value: float, decimals: int = DECIMALS) -> str:
    """A number as written: fixed decimals, never "-0.000"."""
    return _NEG_ZERO.sub(r"\1", f"{value:.{decimals}f}")


def fmt_column(values: np.ndarray, decimals: int = DECIMALS) -> list[str]:
    """fmt of every value of a column (k,), a whole program's at once (no regex per number; the
    digits of finite values from winder.export.fixed_text, the others one by one)."""
    found = fixed_rows([(np.asarray(values, dtype=float), decimals)], [""])
    if found is not None:
        return found
    rule = f"%.{decimals}f"
    text = [rule % v for v in np.asarray(values, dtype=float).tolist()]
    if decimals <= 0:
        return text
    zero = "-0." + "0" * decimals  # the only negative zero fmt's pattern matches in a lone number
    return [t[1:] if t == zero else t for t in text]


def clean(text: str) -> str:
    """A comment's text (a config's path, the job's name): winder.escape.gcode_comment's."""
    return gcode_comment(text)


def shortened(text: str, room: int, keep_end: bool = False) -> str:
    """text within `room` bytes as UTF-8: whole if it fits, else its start (or, keep_end, its end:
    a path's file name) with ELLIPSIS where it was cut."""
    if len(text.encode("utf-8")) <= room:
        return text
    budget = room - len(ELLIPSIS)
    part = text[::-1] if keep_end else text
    out, used = [], 0
    for c in part:
        used += len(c.encode("utf-8"))
        if used > budget:
            break
        out.append(c)
    kept = "".join(out)
    return ELLIPSIS + kept[::-1] if keep_end else kept + ELLIPSIS


def wrapped(line: str) -> list[str]:
    """A comment line as lines of at most MAX_LINE bytes (split between words, `; ` continuing)."""
    if len(line.encode("utf-8")) <= MAX_LINE:
        return [line]
    import textwrap  # noqa: PLC0415 - only for a comment past the limit

    text = line.lstrip(";").strip()
    width = MAX_LINE - 2
    while True:  # characters: narrower until every piece fits in bytes (multi-byte characters)
        pieces = textwrap.wrap(text, width)
        if all(len(p.encode("utf-8")) <= MAX_LINE - 2 for p in pieces):
            return ["; " + p for p in pieces]
        width -= 8


def layer_line(layer: LayerPlan) -> str:
    return (f"layer {layer.index}: {layer.type.value}, angle {fmt(layer.angle_deg)} deg (requested "
            f"{fmt(layer.requested_angle_deg)}), circuits {layer.circuits}, pattern {layer.pattern}, "
            f"passes {len(layer.passes)}, fiber {fmt(layer.fiber_length_mm)} mm")


def _header(program: MotionProgram, dialect: Dialect) -> list[str]:
    room = MAX_LINE - len(JOB_LINE) - 1
    lines = ["; winder filament-winding program", f"{JOB_LINE} {shortened(clean(program.name), room)}",
             f"; source: {shortened(clean(program.source), MAX_LINE - len('; source: '), keep_end=True)}"]
    lines += [part for line in dialect.describe(program) + controller_lines(program, dialect.controller)
              for part in wrapped(line)]
    if program.envelope_radius is not None:
        lines.append(f"; eye envelope: radius {fmt(program.envelope_radius)} mm around the axis")
    else:
        lines.append(f"; eye envelope: clearance {fmt(program.envelope_clearance)} mm from the mandrel")
    machine = program.machine
    lines.append(f"; feed {fmt(machine.feed)} mm/min, chord tolerance {fmt(machine.chord_tolerance)} mm")
    lines.append(f"; layers: {len(program.layers)}, fiber {fmt(program.total_fiber_length_mm)} mm")
    lines += [part for layer in program.layers for part in wrapped(f"; {layer_line(layer)}")]
    return lines


def serialize(program: MotionProgram, dialect: Dialect, moves: bool = True) -> tuple[list[str], list[Move]]:
    """The program's lines (without newlines) and the moves they write, in order (moves=False: the
    lines alone, the moves list left empty), in the form of the dialect's controller (its rotary
    axis, tension command, comments and block numbers: winder.export.dialects.post_text)."""
    controller = dialect.controller
    program, written, values, shown, resets = _rows_as_written(program, dialect)
    first = dialect.first_lines(program)
    lines = first + _header(program, dialect) + dialect.preamble(program)
    found: list[Move] = []
    last_words: str | None = None
    last: tuple[float, ...] | None = None
    tension: list[str | None] = [None]
    for layer, segments in zip(program.layers, program.segments):
        lines += wrapped(f"; {layer_line(layer)}")
        circuit = None
        for seg in segments:
            if seg.circuit != circuit:
                circuit = seg.circuit
                lines.append(f"; layer {layer.index} circuit {circuit}")
            head = f"; layer {layer.index} circuit {circuit} pass {seg.number}"
            lines += _pass_start(head, seg, controller, dialect.letters(program)[1], resets, tension)
            for row in range(seg.start, seg.stop):
                if seg.approach and row == seg.start + seg.approach:
                    lines.append(f"{head} {seg.kind.value}")
                words = written[row]
                if words == last_words:
                    continue
                last_words = words
                cur = tuple(values[row])
                lines += dialect.move_lines(program, row, shown[row], last, cur)
                last = cur
                if moves:
                    u = float(program.index[row])
                    found.append(Move(seg.layer, seg.circuit, seg.number, seg.kind, int(round(u)), cur, u))
    lines += dialect.end(program)
    lines = render(lines, controller, len(first))
    _refuse_long(lines, controller.max_line_length)
    return lines, found


def _rows_as_written(program: MotionProgram, dialect: Dialect) -> tuple:
    """(the program, cut at half turns where the controller wraps its rotary axis; every row's words
    as the moves are made (rows repeating them are left out); their values read back; the words as
    written, the rotation less the whole turns a wrap or reset takes off; resets: row -> the position
    the axis is set to before it). ExportError for a value past the controller's digits."""
    from winder.machine.rotary import rotary_shifts, split_turns  # noqa: PLC0415

    controller = dialect.controller
    if controller.rotary.mode == "wrap":
        program = split_turns(program)
    letters, decimals = dialect.letters(program), dialect.decimals(program)
    columns = dialect.columns(program)
    rotation = columns[:, 1] if columns.ndim == 2 and columns.shape[1] > 1 else np.zeros(0)
    turns, resets = rotary_shifts(rotation, program, controller.rotary.mode, decimals[1] if len(decimals) > 1 else 3)
    written, values = _words(columns, letters, decimals)
    shown = written
    if resets or np.any(turns):
        columns = columns.copy()
        columns[:, 1] -= turns
        shown, _ = _words(columns, letters, decimals)
    check_digits(columns, letters, decimals, controller)
    return program, written, values, shown, resets


def _pass_start(head: str, seg, controller: Controller, rotary_letter: str, resets: dict[int, float],
                tension: list[str | None]) -> list[str]:
    """The lines before a pass's moves: its comment, the tension command where the tension as written
    changes (tension[0]: the last written), the rotary axis' reset, a note of capped points."""
    out = [f"{head} {APPROACH if seg.approach else seg.kind.value}"]
    if seg.tension is not None and controller.tension:
        said = controller.tension_line(seg.tension)
        if said != tension[0]:
            out.append(said)
            tension[0] = said
    if seg.start in resets:
        out.append(reset_line(controller, rotary_letter, resets[seg.start]))
    if seg.capped:
        out.append(f"; note: {seg.capped} points of this pass run nearly along the axis: the eye is held at the "
                   f"largest lead, {fmt(seg.max_lead)} mm, off the envelope")
    return out


def _words(columns: np.ndarray, letters: tuple[str, ...], decimals: tuple[int, ...]) -> tuple[list[str], list]:
    """Every row's words as written, all at once, and the values as written read back."""
    written = fixed_rows([(columns[:, j], n) for j, n in enumerate(decimals)], list(letters)) if len(columns) else []
    if written is None:  # a value that is not finite: one number at a time
        texts = [fmt_column(columns[:, j], n) for j, n in enumerate(decimals)]
        written = list(map(" ".join, zip(*[[c + t for t in col] for c, col in zip(letters, texts)])))
        return written, np.array(texts, dtype=float).T.tolist()
    return written, np.column_stack([printed(columns[:, j], n) for j, n in enumerate(decimals)]).tolist()


def _refuse_long(lines: list[str], longest: int = MAX_LINE) -> None:
    """ExportError for a line past `longest` (a move's words: a value past any machine's travel)."""
    for number, line in enumerate(lines, 1):
        if len(line) > longest // 4 and len(line.encode("utf-8")) > longest:  # 4 bytes a character at most
            raise ExportError(f"line {number} of the program would have {len(line.encode('utf-8'))} characters, "
                              f"past a controller's {longest}: {line[:60]!r}")

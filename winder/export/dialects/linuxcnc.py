"""The linuxcnc dialect: the generic program's axes (letters from machine.axes) in LinuxCNC's
inverse-time feed mode.

Preamble `%`, `G21 G90 G94 G17 G40 G49 G80 G54` (mm, absolute, per-minute feed, XY plane, no
compensation, no canned cycle, work offset 1), `G64 P<chord_tolerance>` (blend the short moves
within the tolerance instead of stopping at each). The first move, to the program's start, is a
rapid `G0`; then `G93`: every `G1` carries F = 60 / t, t the move's planned time (s) from
machine.dynamics (axis speeds and accelerations: the trapezoidal profile), so the controller runs
each move in its planned time whatever mix of linear and rotary axes it has (at G94 a rotary-heavy
move would run at the wrong surface speed), and the moves' times add up to winding_time_s. The end:
`G94`, `M2`, `%`. The rotary axis must not be configured as wrapped (A is cumulative, unless a post
file resets it: G92). The lines around the moves are its description's
(winder/config/posts/linuxcnc.post.yaml); a post file extending it (Sinumerik, Fanuc) changes them.
"""

from __future__ import annotations

from winder.export.dialects.generic import GenericGcode
from winder.export.dialects.text import fmt_significant
from winder.machine.program import MotionProgram

MIN_MOVE_S = 1e-4  # s: a move is never asked to be faster than this


class LinuxcncGcode(GenericGcode):
    """LinuxCNC G-code with inverse-time feed."""

    def describe(self, program: MotionProgram) -> list[str]:
        return super().describe(program) + [
            "; feed: G93 inverse time, F = 60 / (the move's time in s), from the machine dynamics (acceleration included)"]

    def move_lines(self, program: MotionProgram, row: int, words: str,
                   prev: tuple[float, ...] | None, cur: tuple[float, ...]) -> list[str]:
        seconds = self.elapsed(program, row)
        if prev is None:
            return [f"G0 {words}", "G93"]
        inverse = 60.0 / max(seconds, MIN_MOVE_S)
        return [f"G1 {words} F{fmt_significant(inverse)}"]


def make(program: MotionProgram, band_width: float = 0.0) -> LinuxcncGcode:
    """The dialect registry's entry (winder.config.dialects)."""
    return LinuxcncGcode(program.machine.controller)

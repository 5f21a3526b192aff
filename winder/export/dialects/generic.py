"""The G-code of a straight-axis winder (docs/guide/conventions.md): the generic and the linuxcnc
dialects, and the posts that extend them (Sinumerik, Fanuc, a shop's own).

`G1` moves of the four axes, letters from machine.axes, in the order carriage, rotation, cross-feed,
yaw. The controller's description (winder.config.controllers) says the rest: its decimals, the lines
around the moves, and its feed,

- `fiber` (generic): F the fiber's feed (mm/min, G94) on every move;
- `inverse_time` (linuxcnc): the first move, to the program's start, a rapid `G0`; then `G93`: every
  `G1` carries F = 60 / t, t the move's planned time (s) from machine.dynamics (axis speeds and
  accelerations: the trapezoidal profile), so the controller runs each move in its planned time
  whatever mix of linear and rotary axes it has (at G94 a rotary-heavy move would run at the wrong
  surface speed), and the moves' times add up to winding_time_s.

The axis values are the motion program's (winder.machine.program), whose docstring and
winder.machine.kinematics define them.
"""

from __future__ import annotations

from winder.export.dialects.text import BaseDialect, fmt_significant
from winder.machine.program import MotionProgram

PREFIX = "G1"
MIN_MOVE_S = 1e-4  # s: an inverse-time move is never asked to be faster than this
INVERSE_TIME = "inverse_time"


class GenericGcode(BaseDialect):
    """A straight-axis winder's G-code."""

    prefix = PREFIX

    def letters(self, program: MotionProgram) -> tuple[str, ...]:
        ax = program.machine.axes
        return (ax.carriage, ax.rotation, ax.cross_feed, ax.yaw)

    def decimals(self, program: MotionProgram) -> tuple[int, ...]:
        c = self.controller
        return (c.linear, c.angular, c.linear, c.angular)

    def describe(self, program: MotionProgram) -> list[str]:
        ax = program.machine.axes
        return [f"; machine: straight-axis winder; {ax.carriage} carriage (mm), {ax.rotation} mandrel "
                f"rotation (deg, cumulative), {ax.cross_feed} cross-feed: eye distance from the axis "
                f"(mm), {ax.yaw} eye yaw (deg)",
                f"; kinematics: eye at mandrel-frame ({ax.cross_feed} cos(-{ax.rotation}), "
                f"{ax.cross_feed} sin(-{ax.rotation}), {ax.carriage}), on the tangent line of the "
                "fiber path at its contact point",
                f"; yaw: {ax.yaw} = eye rotation about the cross-feed axis from the hoop orientation: the "
                f"free fiber's direction d at the eye, {ax.yaw} = atan2(d.z, d.u), u the eye's tangential direction",
                f"; yaw: 0 hoop, + forward, - return; on a cylinder of radius R with the eye at {ax.cross_feed}: "
                f"tan({ax.yaw}) = {ax.cross_feed} / (R tan(alpha)), alpha the winding angle on the mandrel",
                "; F: the fiber's feed along its path on the mandrel (machine.feed), not the axes' speed",
                "; F: for a controller that reads F as the axes' speed (G94) use the linuxcnc dialect (inverse "
                "time, from the machine dynamics)"] + ([
            "; feed: G93 inverse time, F = 60 / (the move's time in s), from the machine dynamics (acceleration included)"]
            if self.controller.feed == INVERSE_TIME else [])

    def move_lines(self, program: MotionProgram, row: int, words: str,
                   prev: tuple[float, ...] | None, cur: tuple[float, ...]) -> list[str]:
        if self.controller.feed != INVERSE_TIME:
            return super().move_lines(program, row, words, prev, cur)
        seconds = self.elapsed(program, row)
        if prev is None:
            return [f"G0 {words}", "G93"]
        return [f"G1 {words} F{fmt_significant(60.0 / max(seconds, MIN_MOVE_S))}"]


def make(program: MotionProgram, band_width: float = 0.0) -> GenericGcode:
    """The dialect registry's entry (winder.config.dialects)."""
    return GenericGcode(program.machine.controller)

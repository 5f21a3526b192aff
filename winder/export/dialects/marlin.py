"""The marlin dialect: the X A B program of fiberpath-compatible Marlin winders (Marlin >= 2.1 with
the extra axes A and B, both rotational).

Axes: X carriage (mm, the eye along the mandrel axis), A mandrel rotation (deg, cumulative), B the
delivery head (payout eye) rotation (deg). fiberpath's conventions: A grows as the mandrel winds
(A = -winder's rotation, so the eye sits at mandrel-frame (Z cos A, Z sin A, X)) and B is
-(90 - alpha') on a forward pass, +(90 - alpha') on a return pass (B = -winder's yaw).
There is no cross-feed: the eye stays at a fixed distance from the axis, stated in a comment
(`; fixed eye: cross-feed Z<value> mm`); a program whose eye distance would vary by more than
machine.chord_tolerance (an eye envelope that follows a cone or a dome) is refused: give the machine
`eye: {radius: Z}`.

What the controller and fiberpath's `simulate` read: line 1 is the `; Parameters {json}` header
(mandrel diameter = twice the largest mandrel radius, windLength = the axial length, tow width =
band width, tow thickness when known, else 0), then G21 G90 G94, then `G1` moves with X A B and F
on every line; comments only on their own lines; no dwell word, no M codes, no postamble.
F (mm/min, G94): Marlin's planner measures a move by its linear axes when one moves, by its
rotational axes otherwise, so F = that distance / the move's planned time (|dX| when X moves, else
the hypotenuse of dA and dB, per minute; the time from machine.dynamics, acceleration included),
which makes the controller take the planned time.
"""

from __future__ import annotations

import json

import numpy as np

from winder.errors import ExportError
from winder.export.dialects.text import DECIMALS, BaseDialect, fmt, fmt_significant
from winder.machine.program import MotionProgram

LETTERS = ("X", "A", "B")
HEADER = "; Parameters "
FIXED_EYE = "; fixed eye: cross-feed Z"
MIN_MOVE_S = 1e-4  # s: a move is never asked to be faster than this
TURN_DEG = 360.0
# Each logical axis (carriage, rotation, cross_feed, yaw) as written: A and B in fiberpath's sense.
AXIS_SIGNS = (1.0, -1.0, 1.0, -1.0)


def parameters(program: MotionProgram, band_width: float, thickness: float) -> dict:
    return {"irVersion": "1.0",
            "mandrel": {"diameter": round(2.0 * program.mandrel_radius, 6),
                        "windLength": round(program.axial_length, 6)},
            "tow": {"width": round(float(band_width), 6), "thickness": round(float(thickness), 6)}}


class MarlinGcode(BaseDialect):
    """fiberpath-compatible Marlin X A B G-code."""

    prefix = "G1"

    def __init__(self, controller, band_width: float = 0.0, thickness: float = 0.0) -> None:
        super().__init__(controller)
        self.band_width = band_width
        self.thickness = thickness

    def letters(self, program: MotionProgram) -> tuple[str, ...]:
        return LETTERS

    def decimals(self, program: MotionProgram) -> tuple[int, ...]:
        return (self.controller.linear, self.controller.angular, self.controller.angular)

    def fixed_eye(self, program: MotionProgram) -> float:
        z = program.values[:, 2]
        if z.size == 0:
            return 0.0
        lo, hi = float(np.min(z)), float(np.max(z))
        if hi - lo > program.machine.chord_tolerance:
            raise ExportError(f"{program.source}: machine.dialect: marlin has no cross-feed axis, but the eye "
                              f"distance from the axis varies from {lo:.3f} to {hi:.3f} mm on this job; give "
                              "the machine a fixed eye, machine.eye: {radius: Z}")
        return 0.5 * (lo + hi)

    def first_lines(self, program: MotionProgram) -> list[str]:
        text = json.dumps(parameters(program, self.band_width, self.thickness), separators=(",", ":"))
        return [HEADER + text] + super().first_lines(program)

    def describe(self, program: MotionProgram) -> list[str]:
        return ["; machine: Marlin X A B winder (fiberpath axes); X carriage (mm), A mandrel rotation (deg, "
                "cumulative, growing as the mandrel winds), B delivery head (deg)",
                "; kinematics: eye at mandrel-frame (Z cos(A), Z sin(A), X), on the tangent line of the fiber "
                "path at its contact point",
                f"{FIXED_EYE}{fmt(self.fixed_eye(program))} mm from the mandrel axis",
                "; B = -(eye yaw from the hoop orientation): -(90 - alpha') forward, +(90 - alpha') return",
                "; F: mm/min over X when X moves, else deg/min over A and B: the move's planned time"]

    def columns(self, program: MotionProgram) -> np.ndarray:
        v = program.values
        return (np.column_stack([AXIS_SIGNS[0] * v[:, 0], AXIS_SIGNS[1] * v[:, 1], AXIS_SIGNS[3] * v[:, 3]])
                if v.size else np.zeros((0, 3)))

    def move_lines(self, program: MotionProgram, row: int, words: str,
                   prev: tuple[float, ...] | None, cur: tuple[float, ...]) -> list[str]:
        seconds = self.elapsed(program, row)
        if prev is None:
            return [f"{self.prefix} {words} F{fmt(program.machine.feed)}"]
        cuts = turn_cuts(prev[1], cur[1])
        if cuts.size == 0:
            return [f"{self.prefix} {words} F{move_feed(prev, cur, seconds)}"]
        # The same straight move in pieces, each within one turn of A, each in its share of the time.
        share = (cuts - prev[1]) / (cur[1] - prev[1])
        ends = [tuple(float(a) + f * (float(b) - float(a)) for a, b in zip(prev, cur)) for f in share.tolist()]
        ends = [(float(fmt(x)), float(fmt(a)), float(fmt(b))) for x, a, b in ends] + [tuple(cur)]
        fractions = np.diff(np.concatenate([[0.0], share, [1.0]])).tolist()
        lines, last = [], tuple(prev)
        for end, frac in zip(ends, fractions):
            piece = words if end is ends[-1] else " ".join(f"{c}{fmt(v)}" for c, v in zip(LETTERS, end))
            lines.append(f"{self.prefix} {piece} F{move_feed(last, end, seconds * frac)}")
            last = end
        return lines


def move_feed(prev: tuple[float, ...], cur: tuple[float, ...], seconds: float) -> str:
    """F of a move (X A B as written) that takes `seconds`: Marlin's distance (|dX| when X moves,
    else the hypotenuse of dA and dB) per minute."""
    dx = abs(cur[0] - prev[0])
    distance = dx if dx > 0.0 else float(np.hypot(cur[1] - prev[1], cur[2] - prev[2]))
    return fmt_significant(60.0 * distance / max(seconds, MIN_MOVE_S))


def turn_cuts(a0: float, a1: float) -> np.ndarray:
    """Where a move of A from a0 to a1 (deg, as written) is cut so that no piece crosses a full turn
    (fiberpath's plot draws a piece within one turn only): one written unit short of each multiple
    of 360 deg the move passes, in the move's direction."""
    unit = 10.0**-DECIMALS
    if a1 > a0:
        k = np.arange(np.floor((a0 + unit) / TURN_DEG) + 1, np.ceil((a1 + unit) / TURN_DEG))
        cuts = k * TURN_DEG - unit
        return cuts[(cuts > a0 + 0.5 * unit) & (cuts < a1 - 0.5 * unit)]
    if a1 < a0:
        k = np.arange(np.ceil((a0 - unit) / TURN_DEG) - 1, np.floor((a1 - unit) / TURN_DEG), -1.0)
        cuts = k * TURN_DEG + unit
        return cuts[(cuts < a0 - 0.5 * unit) & (cuts > a1 + 0.5 * unit)]
    return np.zeros(0)


def make(program: MotionProgram, band_width: float = 0.0) -> MarlinGcode:
    """The dialect registry's entry (winder.config.dialects): band_width (mm) for the header."""
    return MarlinGcode(program.machine.controller, band_width)

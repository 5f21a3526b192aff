"""The rotary axis as a controller keeps it (a post file's `rotary`, winder.config.controllers.Rotary).

The motion program's rotation is cumulative: a long job's A runs to hundreds of thousands of degrees,
past the digits many controllers take. A controller may instead keep it

- `wrap`: modulo 360 (a modulo / roll-over axis), each programmed value in [0, 360) and the axis
  taking the shortest way to it, so no move may turn half a turn or more: longer moves are cut into
  equal pieces along the same straight move in axis space (split_turns);
- `reset_per_layer`, `reset_per_pass`: cumulative within a layer (a pass), the position set to its
  value modulo 360 at the layer's (pass's) first move (G92 on LinuxCNC), so the program's values
  differ from the motion program's by whole turns (rotary_shifts).

Either way the eye goes where the cumulative program takes it: a reader that adds the turns back
(winder.readback.gcode) reads the same moves.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.machine.dynamics import MoveTimes
from winder.machine.program import MotionProgram

TURN_DEG = 360.0
MAX_STEP_DEG = 120.0  # the longest piece of a wrapped move: well inside half a turn, whatever the rounding


def split_turns(program: MotionProgram, max_step: float = MAX_STEP_DEG) -> MotionProgram:
    """The program with every move turning the rotation by more than max_step (deg) cut into equal
    pieces of the same straight move (axes interpolated linearly; feed kept; fiber and times shared
    equally; a piece's contact index interpolated within its pass). Robot poses are returned as they are."""
    m = program.values.shape[0]
    if program.robot or m < 2:
        return program
    turn = np.abs(np.diff(program.values[:, 1]))
    pieces = np.concatenate([[1], np.maximum(np.ceil(turn / max_step), 1).astype(int)])
    if np.all(pieces == 1):
        return program
    row = np.repeat(np.arange(m), pieces)  # the program's row each new row ends on (or leads toward)
    last = np.cumsum(pieces) - 1  # the new index of each program row
    step = np.arange(row.size) - (last[row] - pieces[row] + 1) + 1  # 1..k within a row's pieces
    share = step / pieces[row]
    prev = np.maximum(row - 1, 0)
    values = program.values[prev] + share[:, None] * (program.values[row] - program.values[prev])
    starts = np.array([seg.start for segs in program.segments for seg in segs if seg.stop > seg.start], dtype=int)
    same_pass = ~np.isin(row, starts)
    index = np.where(same_pass, program.index[prev] + share * (program.index[row] - program.index[prev]),
                     program.index[row])
    scale = 1.0 / pieces[row]
    times = MoveTimes(program.times.cruise_s[row] * scale, program.times.time_s[row] * scale, program.times.feed[row])

    def moved(seg):
        if seg.stop <= seg.start:
            at = int(last[seg.start - 1]) + 1 if seg.start > 0 else 0
            return dataclasses.replace(seg, start=at, stop=at)
        first = int(last[seg.start] - pieces[seg.start] + 1)
        laying = seg.start + seg.approach  # its first row after the approach: its pieces lay the pass
        approach = int(last[laying] - pieces[laying] + 1) - first if seg.approach else 0
        return dataclasses.replace(seg, start=first, stop=int(last[seg.stop - 1]) + 1, approach=approach)

    segments = tuple(tuple(moved(seg) for seg in segs) for segs in program.segments)
    return dataclasses.replace(program, values=values, feed=program.feed[row], index=index,
                               fiber=program.fiber[row] * scale, times=times, segments=segments)


def rotary_shifts(column: np.ndarray, program: MotionProgram, mode: str, decimals: int
                  ) -> tuple[np.ndarray, dict[int, float]]:
    """(shift (m,) deg: whole turns taken off each row's rotation `column` (as its dialect writes it)
    to write it in `mode`; resets: the row a reset comes before -> the position (deg, as written) the
    axis is set to there)."""
    m = column.shape[0]
    resets: dict[int, float] = {}
    if program.robot or mode == "continuous" or m == 0:
        return np.zeros(m), resets
    written = np.round(column, decimals)
    if mode == "wrap":
        return TURN_DEG * np.floor(written / TURN_DEG), resets
    firsts: list[int] = []
    for segs in program.segments:
        rows = [seg.start for seg in segs if seg.stop > seg.start]
        firsts += rows if mode == "reset_per_pass" else rows[:1]
    current = 0.0
    marks = np.zeros(m)
    for row in firsts:
        if row == 0:
            continue
        turns = TURN_DEG * np.floor(written[row - 1] / TURN_DEG)
        resets[row] = float(round(written[row - 1] - turns, decimals))
        marks[row] = turns - current
        current = turns
    return np.cumsum(marks), resets

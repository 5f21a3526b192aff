"""Moves whose midpoint strays from the fiber, cut where the exact eye path bends faster than the
program's densify check saw (winder.machine.densify measures each planned interval's bow at its
midpoint and assumes a smooth eye path: round a dome's pole the eye swings 6.5 mm while the contact
moves 1/257 of an interval, and such a move's midpoint lay 0.068 mm off the fiber, tolerance 0.05).

A move to row r whose midpoint is past the chord tolerance (winder.machine.deviation) gets rows at
the exact contacts between its two, CUT_PIECES pieces, each placed as the program places its rows
(the eye on the fiber's tangent at the envelope, winder.machine.kinematics; A and B on the turns of
the move's own rows); the moves' fiber is shared out by contact index and the times are those of the
new rows. MEND_ROUNDS rounds at most, each on the moves still past the tolerance.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.machine.as_wound import finished_part
from winder.machine.dynamics import move_times
from winder.machine.envelope import eye_envelope
from winder.machine.exact import exact_points
from winder.machine.smooth import SmoothPaths
from winder.winding.results import WindingPlan

CUT_PIECES = 4  # pieces a straying move is cut in, a round
MEND_ROUNDS = 3


def _owners(program) -> tuple[np.ndarray, np.ndarray]:
    """(layer index (m,), pass number in its layer (m,)) of every row (-1 outside any pass)."""
    m = program.values.shape[0]
    layer, number = np.full(m, -1), np.full(m, -1)
    for i, segments in enumerate(program.segments):
        for j, seg in enumerate(segments):
            layer[seg.start:seg.stop], number[seg.start:seg.stop] = i, j
    return layer, number


def _eyes(plan: WindingPlan, program, env, guide, p: np.ndarray, d: np.ndarray, th: np.ndarray,
          near: np.ndarray) -> np.ndarray:
    """Program rows (k, 4) or poses (k, 6) of contacts p, d (k, 3) at angles th (k,), A and B (or
    nothing on a robot) on the turns nearest the rows `near` (k, width) (the move's mean)."""
    from winder.machine.kinematics import eye_path, robot_poses  # noqa: PLC0415

    machine = program.machine
    if program.robot:
        poses = robot_poses(p, d, plan.outer_surface, machine, envelope=env, guide=guide)
        return np.column_stack([poses.position, poses.direction])
    path = eye_path(p, d, plan.outer_surface, machine, theta=th, envelope=env)
    rows = np.column_stack([path.x, path.a_deg, path.z, path.b_deg])
    for col in (1, 3):  # the turn of A and of B (made continuous by the program) nearest the move's
        rows[:, col] += 360.0 * np.rint((near[:, col] - rows[:, col]) / 360.0)
    return rows


def mend(plan: WindingPlan, program, moves: np.ndarray):
    """The program with each move to the rows `moves` (k,) cut in CUT_PIECES (module docstring), or
    the program itself where none can be (a robot cell's, or no move given)."""
    if moves.size == 0 or program.cell is not None:
        return program
    layer, number = _owners(program)
    u0, u1 = program.index[moves - 1], program.index[moves]
    f = np.arange(1, CUT_PIECES) / CUT_PIECES
    u_new = u0[:, None] + f * (u1 - u0)[:, None]  # (k, pieces - 1)
    rows = np.empty((moves.size, f.size, program.values.shape[1]))
    env = eye_envelope(plan.outer_surface, program.machine, finished_part(plan))
    guide = None
    if program.robot:
        from winder.machine.kinematics import make_guide  # noqa: PLC0415

        guide = make_guide(plan.outer_surface, env)
    for li in np.unique(layer[moves]).tolist():
        mine = np.flatnonzero(layer[moves] == li)
        the_layer = plan.layers[li]
        paths = SmoothPaths(plan.surface_of(the_layer.index), list(the_layer.passes))
        at = (paths.offset[number[moves[mine]]][:, None] + u_new[mine]).ravel()
        _, th, p, d = exact_points(paths, at)
        # theta with the program's turns: the planned angle's turn offset is read back from A
        near = np.repeat(0.5 * (program.values[moves[mine] - 1] + program.values[moves[mine]]), f.size, axis=0)
        rows[mine] = _eyes(plan, program, env, guide, p, d, th, near).reshape(mine.size, f.size, -1)
    return _inserted(program, moves, rows, u_new, f)


def _inserted(program, moves: np.ndarray, rows: np.ndarray, u_new: np.ndarray, f: np.ndarray):
    """The program with rows (k, q, width) inserted before each row of moves (k,), their contact
    indices u_new (k, q), the moves' fiber shared out at the fractions f (q,)."""
    q = f.size
    at = np.repeat(moves, q)
    values = np.insert(program.values, at, rows.reshape(-1, rows.shape[2]), axis=0)
    index = np.insert(program.index, at, u_new.ravel())
    share = np.diff(np.concatenate([[0.0], f, [1.0]]))  # each piece's part of the move's fiber
    fiber = program.fiber.copy()
    pieces = fiber[moves][:, None] * share[None, :]
    fiber[moves] = pieces[:, -1]
    fiber = np.insert(fiber, at, pieces[:, :-1].ravel())
    added = np.searchsorted(moves, np.arange(program.values.shape[0] + 1), side="right") * q

    def shift(row: int) -> int:  # a segment bound: rows inserted before it move it on
        return row + int(added[row - 1]) if row > 0 else row

    segments = tuple(tuple(dataclasses.replace(seg, start=shift(seg.start), stop=shift(seg.stop)) for seg in segs)
                     for segs in program.segments)
    times = move_times(values[:, :3] if program.robot else values, fiber, program.machine, program.robot)
    return dataclasses.replace(program, values=values, index=index, fiber=fiber, segments=segments, times=times,
                               feed=times.feed)

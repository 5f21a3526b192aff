"""Moves whose midpoint strays from the fiber, cut where the exact eye path bends faster than the
program's densify check saw (winder.machine.densify measures each planned interval's bow at its
midpoint and assumes a smooth eye path: round a dome's pole the eye swings 6.5 mm while the contact
moves 1/257 of an interval, and such a move's midpoint lay 0.068 mm off the fiber, tolerance 0.05).

A move to row r whose midpoint is past the chord tolerance (winder.machine.deviation) gets rows at
the exact contacts between its two, CUT_PIECES pieces, each placed as the program places its rows
(the eye on the fiber's tangent at the envelope, winder.machine.kinematics; A and B on the turns of
the move's own rows); the moves' fiber is shared out by contact index and the times are those of the
new rows. MEND_ROUNDS rounds at most, each on the moves still past the tolerance.

The cuts go where the eye travels, not evenly in the contact index: the move's exact eye path is read
at TRAVEL_SAMPLES contacts and the cuts split its length (3-D, mandrel frame) in equal parts. On a
rectangular tube's section the eye is tied while the contact runs along a flat (its tangent rays are
one line) and sweeps the whole corner while the contact rounds it: at 70.5 deg over a 7.5 mm corner
(issue 41, a generated tube) the sweep, 19 deg of A and 8 mm of X, took the first 1/20 of a move whose
contact ran on along the flat, and even cuts in the index each left it in the first piece (0.2647 mm
off after three rounds, tolerance 0.05).
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
TRAVEL_SAMPLES = 64  # contacts of a straying move at which its eye's travel is read (where to cut)
EVEN_SHARE = 1e-3  # of the cuts' measure spread evenly over the contact index (a move whose eye is still)
TRAVEL_STILL = 1e-9  # of a move's eye travel: a step of its samples that moves less, the eye still


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
    g = np.linspace(0.0, 1.0, TRAVEL_SAMPLES)
    u_new = np.empty((moves.size, f.size))  # (k, pieces - 1): the cuts' contacts
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
        offset = paths.offset[number[moves[mine]]][:, None]
        mean = 0.5 * (program.values[moves[mine] - 1] + program.values[moves[mine]])

        def read(u_at: np.ndarray, mean=mean, offset=offset, paths=paths) -> np.ndarray:
            """The exact eye (k_l, s, 3) at the contacts u_at (k_l, s) (theta with the program's turns:
            the planned angle's turn offset is read back from A)."""
            _, th, p, d = exact_points(paths, (offset + u_at).ravel())
            seen = _eyes(plan, program, env, guide, p, d, th, np.repeat(mean, u_at.shape[1], axis=0))
            return _positions(seen, program.robot).reshape(u_at.shape[0], u_at.shape[1], 3)

        u_seen = u0[mine, None] + g * (u1 - u0)[mine, None]  # (k_l, TRAVEL_SAMPLES)
        u_seen, eyes = _finer(u_seen, read(u_seen), read)
        u_new[mine] = _travel_cuts(u_seen, eyes, f)
        _, th, p, d = exact_points(paths, (offset + u_new[mine]).ravel())
        rows[mine] = _eyes(plan, program, env, guide, p, d, th,
                           np.repeat(mean, f.size, axis=0)).reshape(mine.size, f.size, -1)
    span = u1 - u0
    share = np.where((span != 0.0)[:, None], (u_new - u0[:, None]) / np.where(span != 0.0, span, 1.0)[:, None], f)
    return _inserted(program, moves, rows, u_new, share)


def _positions(rows: np.ndarray, robot: bool) -> np.ndarray:
    """The eye (k, 3) in the mandrel frame of rows (k, 4) or poses (k, 6) (deviation.written_eyes)."""
    from winder.machine.deviation import written_eyes  # noqa: PLC0415

    return written_eyes(rows, robot)


def _travel_cuts(u: np.ndarray, eyes: np.ndarray, f: np.ndarray) -> np.ndarray:
    """(k, q) contacts that cut the eye paths read at contacts u (k, s) (eyes (k, s, 3)) at the
    fractions f (q,) of their length, EVEN_SHARE of the measure spread over the contact index (module
    docstring): strictly between each row's ends."""
    step = np.linalg.norm(np.diff(eyes, axis=1), axis=2)  # (k, s - 1)
    travel = np.concatenate([np.zeros((u.shape[0], 1)), np.cumsum(step, axis=1)], axis=1)
    total = travel[:, -1:]
    span = u[:, -1:] - u[:, :1]
    even = (u - u[:, :1]) / np.where(span != 0.0, span, 1.0)  # the contact index's share
    measure = (1.0 - EVEN_SHARE) * travel / np.where(total > 0.0, total, 1.0) + EVEN_SHARE * even
    measure = np.where(total > 0.0, measure, even)
    measure /= measure[:, -1:]
    return np.stack([np.interp(f, m, x) for m, x in zip(measure, u)]) if u.shape[0] else np.zeros((0, f.size))


def _finer(u: np.ndarray, eyes: np.ndarray, read) -> tuple[np.ndarray, np.ndarray]:
    """The contacts u (k, s) and their eyes (k, s, 3) with TRAVEL_SAMPLES more contacts evenly between
    the first and the last of them between which the eye moves (read (k, s') eyes of contacts (k, s')):
    a move into a flat face's row (winder.machine.reduce.far_contacts) runs its contact over the corner
    and the whole flat, its eye still along the flat, and the even samples left the corner's sweep a few
    (configs like issue 41's tube 6, 70.5 deg: cuts on the flat, whose eyes lie on its line)."""
    step = np.linalg.norm(np.diff(eyes, axis=1), axis=2)  # (k, s - 1)
    moving = step > TRAVEL_STILL * np.maximum(step.sum(axis=1, keepdims=True), 1e-300)
    first = np.argmax(moving, axis=1)
    last = step.shape[1] - np.argmax(moving[:, ::-1], axis=1)  # the sample after the last step that moves
    rows = np.arange(u.shape[0])
    lo, hi = u[rows, first], u[rows, last]
    fine = lo[:, None] + np.linspace(0.0, 1.0, TRAVEL_SAMPLES) * (hi - lo)[:, None]
    at = np.concatenate([u, fine], axis=1)
    order = np.argsort(at, axis=1, kind="stable")
    both = np.concatenate([eyes, read(fine)], axis=1)
    return np.take_along_axis(at, order, axis=1), np.take_along_axis(both, order[:, :, None], axis=1)


def _inserted(program, moves: np.ndarray, rows: np.ndarray, u_new: np.ndarray, f: np.ndarray):
    """The program with rows (k, q, width) inserted before each row of moves (k,), their contact
    indices u_new (k, q), the moves' fiber shared out at the fractions f (k, q) (increasing in [0, 1])."""
    q = f.shape[1]
    at = np.repeat(moves, q)
    values = np.insert(program.values, at, rows.reshape(-1, rows.shape[2]), axis=0)
    index = np.insert(program.index, at, u_new.ravel())
    ends = np.ones((f.shape[0], 1))
    share = np.diff(np.concatenate([0.0 * ends, f, ends], axis=1), axis=1)  # each piece's part of the move's fiber
    fiber = program.fiber.copy()
    pieces = fiber[moves][:, None] * share
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

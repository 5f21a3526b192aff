"""How far the written program's eye lies from the fiber it lays (docs/guide/conventions.md,
what a job proves): every programmed point and every move's midpoint against the exact tangent ray of
the planned path at its contact.

The free fiber runs from its contact point p on the mandrel along the path's unit tangent d to the
eye (winder.machine.kinematics), so an eye E is right where it lies on the ray p + lambda d,
lambda >= 0; its deviation is its distance from that ray. Each programmed row knows its contact:
MotionProgram.index is the fractional point index of the pass it aims at (planned and densified points
alike), and the exact path there (winder.machine.exact: the geodesic between planned points where it
stands for the fiber, the smooth path elsewhere) gives p and d: no search. The eye is read from the
row as the program writes it (its decimals), by the forward kinematics of the machine: mandrel-frame
(Z cos(-A), Z sin(-A), X) on a straight winder, the pose's position on a robot.

Between two rows the controller moves the axes linearly, and the eye at the move's midpoint lays the
fiber from a contact between the rows' two: its deviation is the least distance from the rays of the
contacts u in [u0, u1]. That is sought on the cubic Hermite of the two rows' own contacts and
directions (MIDPOINT_SAMPLES points and a parabola through the least three of the squared distance,
which is smooth in u), then read on the exact path at the contact found: an upper bound of the least
distance. Where that bound is past REFINE_SHARE of the tolerance the search is repeated on the exact
path itself (nine points, then REFINE_PER_POINT a planned interval with golden-section steps and the
tangent plane's sign changes: docs/math/15-invariants.md), so a coarse model never condemns a good
move: a move over a flat of a rectangular tube's section runs many planned intervals
(the eye hardly moves while the contact runs along the flat, whose tangent rays are one line), and its
midpoint's contact lies near one end.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.geometry.measure import row_norms
from winder.machine.exact import exact_points
from winder.machine.smooth import SmoothPaths
from winder.winding.results import WindingPlan

MIDPOINT_SAMPLES = 9  # points of a move's chord of contacts where the midpoint's contact is sought
REFINE_PER_POINT = 3  # ... and of the exact path a planned interval, where the chord's answer is in doubt
REFINE_MOST = 1024  # samples of a move, at most
REPORT_TOP = 64  # a layer's largest midpoint bounds sought again too, a round at a time
REPORT_ROUNDS = 8
BRACKET_REACH, BRACKET_MM = 4.0, 5.0  # a bracket is closed where it starts within this of the least sample
FALSI_STEPS = 14  # regula falsi steps closing a bracket of the tangent plane through the eye
GOLDEN_STEPS = 16  # golden-section steps around the least sample (its bracket shrinks 0.618^16 ~ 5e-4)
REFINE_SHARE = 1.0  # of the chord tolerance: a midpoint whose bound is past this is sought again on the path


@dataclasses.dataclass(frozen=True, eq=False)
class Deviations:
    """Per program row (m,): the written eye's distance (mm) from its contact's tangent ray (NaN on a
    row that lays no fiber: an approach move's), and that of the midpoint of the move to the row (NaN
    where the move lays none: the first row of a pass, an approach)."""

    point: np.ndarray
    midpoint: np.ndarray


def written_eyes(values: np.ndarray, robot: bool) -> np.ndarray:
    """The eye (m, 3) in the mandrel frame of program rows (m, 4) (carriage, rotation deg, cross-feed,
    yaw) or robot poses (m, 6) (position first), by the machine's forward kinematics."""
    if robot:
        return values[:, :3].copy()
    a = -np.radians(values[:, 1])
    return np.column_stack([values[:, 2] * np.cos(a), values[:, 2] * np.sin(a), values[:, 0]])


def ray_distance(e: np.ndarray, p: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Distance (m,) of points e (m, 3) from the rays p + lambda d, lambda >= 0 (d unit, (m, 3))."""
    w = e - p
    along = np.maximum(np.einsum("ij,ij->i", w, d), 0.0)
    return row_norms(w - along[:, None] * d)


def _samples(e: np.ndarray, at, u0: np.ndarray, u1: np.ndarray, samples: int) -> tuple[np.ndarray, ...]:
    """(u (k, samples), distance (k, samples), k_min (k,)): the rays at(u) -> (p, d) at `samples`
    points of [u0, u1] (k,) against the points e (k, 3), and each row's least."""
    f = np.linspace(0.0, 1.0, samples)
    u = u0[:, None] + f * (u1 - u0)[:, None]
    p, d = at(u.ravel())
    dist = ray_distance(np.repeat(e, samples, axis=0), p, d).reshape(u.shape)
    return u, dist, np.argmin(dist, axis=1)


def _least_on(e: np.ndarray, at, u0: np.ndarray, u1: np.ndarray, samples: int) -> tuple[np.ndarray, np.ndarray]:
    """(u (k,), distance (k,)): where on [u0, u1] the rays at(u) -> (p, d) pass nearest the points e
    (k, 3): the least of `samples` points, then the parabola through it and its neighbours of the
    squared distance (smooth in u), read again: the better of both."""
    u, dist, k_min = _samples(e, at, u0, u1, samples)
    rows = np.arange(e.shape[0])
    k = np.clip(k_min, 1, samples - 2)
    g0, g1, g2 = (dist[rows, k + j] ** 2 for j in (-1, 0, 1))
    curve = g0 - 2.0 * g1 + g2
    shift = np.where(curve > 0.0, 0.5 * (g0 - g2) / np.where(curve > 0.0, curve, 1.0), 0.0)
    best_u = u[rows, k] + np.clip(shift, -1.0, 1.0) * (u[rows, 1] - u[rows, 0])
    p, d = at(best_u)
    best = ray_distance(e, p, d)
    worse = best > dist[rows, k_min]
    best_u[worse], best[worse] = u[rows, k_min][worse], dist[rows, k_min][worse]
    return best_u, best


def _refined(e: np.ndarray, plane, u0: np.ndarray, u1: np.ndarray) -> np.ndarray:
    """The least distance (k,) of the rays on [u0, u1] (k,) from the points e (k, 3), sought on the
    path itself; plane(u) -> (p, d, n): the contact, its tangent and the surface's unit normal there.

    REFINE_PER_POINT samples a planned interval (moves of like counts together), then each bracket
    where the tangent plane sweeps through the point (h = (e - p) . n changes sign: the fiber from an
    eye touches the mandrel where the tangent plane holds the eye) closed by regula falsi, and
    GOLDEN_STEPS golden-section steps between the least sample's neighbours: near a corner of the
    section the rays turn so fast that the least distance is a notch a thousandth of an interval wide,
    which samples step over but a sign change does not."""
    span = np.abs(u1 - u0)
    count = np.left_shift(1, np.ceil(np.log2(np.clip(span * REFINE_PER_POINT, 8, REFINE_MOST))).astype(int)) + 1
    lo, hi, best = np.empty(e.shape[0]), np.empty(e.shape[0]), np.empty(e.shape[0])
    roots: list[tuple[np.ndarray, ...]] = []  # (move, a, b, h(a), h(b)) of each bracket

    def at(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return plane(x)[:2]

    for n in np.flatnonzero(np.bincount(count)).tolist():
        sub = np.flatnonzero(count == n)
        f = np.linspace(0.0, 1.0, n)
        u = u0[sub, None] + f * (u1 - u0)[sub, None]
        p, d, nrm = plane(u.ravel())
        w = np.repeat(e[sub], n, axis=0) - p
        dist = ray_distance(np.repeat(e[sub], n, axis=0), p, d).reshape(u.shape)
        h = np.einsum("ij,ij->i", w, nrm).reshape(u.shape)
        k_min = np.argmin(dist, axis=1)
        rows = np.arange(sub.size)
        step = (u1[sub] - u0[sub]) / (n - 1)
        lo[sub], hi[sub] = u[rows, k_min] - step, u[rows, k_min] + step
        best[sub] = dist[rows, k_min]
        i, j = np.nonzero(np.signbit(h[:, :-1]) != np.signbit(h[:, 1:]))
        # Only brackets whose nearer end lies within BRACKET_REACH of the move's least sample: the eye
        # is on a tangent plane there, but far off its ray a step away is far off it at the root too.
        near = np.minimum(dist[i, j], dist[i, j + 1]) <= BRACKET_REACH * dist[i, k_min[i]] + BRACKET_MM
        i, j = i[near], j[near]
        roots.append((sub[i], u[i, j], u[i, j + 1], h[i, j], h[i, j + 1]))
    lo, hi = np.maximum(lo, np.minimum(u0, u1)), np.minimum(hi, np.maximum(u0, u1))
    best = np.minimum(best, _golden(e, at, lo, hi, GOLDEN_STEPS)[1])
    move, a, b, ha, hb = (np.concatenate(c) for c in zip(*roots))
    if move.size:
        root = _falsi(lambda x: np.einsum("ij,ij->i", e[move] - (q := plane(x))[0], q[2]), a, b, ha, hb)
        p, d = at(root)
        np.minimum.at(best, move, ray_distance(e[move], p, d))
    return best


def _falsi(h, a: np.ndarray, b: np.ndarray, ha: np.ndarray, hb: np.ndarray) -> np.ndarray:
    """Roots (k,) of h(x) (k,) -> (k,) in the brackets [a, b] (h(a), h(b) of opposite signs), all at
    once: FALSI_STEPS steps of regula falsi, Illinois-modified (an end kept twice has its value halved)."""
    side = np.zeros(a.size)
    x = a
    for _ in range(FALSI_STEPS):
        x = np.where(hb != ha, (a * hb - b * ha) / np.where(hb != ha, hb - ha, 1.0), 0.5 * (a + b))
        hx = h(x)
        left = np.signbit(hx) == np.signbit(ha)  # the root lies in [x, b]
        a, ha = np.where(left, x, a), np.where(left, hx, ha)
        b, hb = np.where(left, b, x), np.where(left, hb, hx)
        ha = np.where(~left & (side == -1.0), 0.5 * ha, ha)
        hb = np.where(left & (side == 1.0), 0.5 * hb, hb)
        side = np.where(left, 1.0, -1.0)
    return x


def _golden(e: np.ndarray, at, lo: np.ndarray, hi: np.ndarray, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Golden-section search of the rays' distance from e (k, 3) on [lo, hi] (k,), all at once."""
    ratio = 0.5 * (np.sqrt(5.0) - 1.0)

    def dist_at(u: np.ndarray) -> np.ndarray:
        p, d = at(u)
        return ray_distance(e, p, d)

    a, b = lo.copy(), hi.copy()
    c, d_ = b - ratio * (b - a), a + ratio * (b - a)
    fc, fd = dist_at(c), dist_at(d_)
    for _ in range(steps):
        left = fc < fd  # the least lies in [a, d_]
        b = np.where(left, d_, b)
        a = np.where(left, a, c)
        new_c, new_d = b - ratio * (b - a), a + ratio * (b - a)
        probe = np.where(left, new_c, new_d)
        f_new = dist_at(probe)
        # left: the old c becomes d and c is new; else the old d becomes c and d is new
        c, d_, fc, fd = (np.where(left, new_c, d_), np.where(left, c, new_d),
                         np.where(left, f_new, fd), np.where(left, fc, f_new))
    better = fc < fd
    return np.where(better, c, d_), np.where(better, fc, fd)


def layer_deviations(paths: SmoothPaths, planned: np.ndarray, eyes: np.ndarray, midway: np.ndarray, u: np.ndarray,
                     move: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """(point (m,), midpoint (m,)) deviations of one layer's fiber rows: planned (n, 3) the layer's planned
    points (the paths' nodes), eyes (m, 3) written, midway
    (m, 3) the eye halfway along the move to each row, u (m,) their global parameters on the layer's
    paths, move (m,) bool: the move to the row lays fiber from the row before (the midpoint's NaN
    elsewhere); tol the chord tolerance (module docstring)."""
    memo: dict = {}

    def exact(at: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        _, _, p, d = exact_points(paths, at, memo)
        return p, d

    def plane(at: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        s, th, p, d = exact_points(paths, at, memo)
        ev = paths.surface.evaluate(s, th, order=1, with_point=False)
        n = np.cross(ev.ps, ev.pt)
        return p, d, n / row_norms(n)[:, None]

    # Every interval's geodesic run at once, kept in the memo for the searches below (each reads a few).
    exact(np.arange(paths.s.size - 1) + 0.5)
    p, d = exact(u)
    # A planned point's contact is the plan's own point and direction (where a joint of the guide
    # falls on it, the smooth path's side of the joint is not the plan's).
    node = np.flatnonzero(u == np.floor(u))
    p[node], d[node] = planned[u[node].astype(np.int64)], paths.d[u[node].astype(np.int64)]
    point = ray_distance(eyes, p, d)
    mid = np.full(u.size, np.nan)
    k = np.flatnonzero(move)
    if k.size == 0:
        return point, mid
    e_mid = midway[k]
    p0, p1, d0, d1 = p[k - 1], p[k], d[k - 1], d[k]

    span = row_norms(p1 - p0)[:, None]  # the cubic's end tangents: the contacts' directions, the chord long

    def chord(at: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        # at: each move's parameters in a run (as _least_on asks them); the contact on the cubic Hermite
        # of the rows' two contacts and directions, its direction the cubic's tangent
        reps = at.size // k.size
        lo, hi = np.repeat(u[k - 1], reps), np.repeat(u[k], reps)
        g = ((at - lo) / np.where(hi != lo, hi - lo, 1.0))[:, None]
        a0, a1, m0, m1 = (np.repeat(x, reps, axis=0) for x in (p0, p1, span * d0, span * d1))
        g2, g3 = g * g, g * g * g
        pp = (2 * g3 - 3 * g2 + 1) * a0 + (g3 - 2 * g2 + g) * m0 + (3 * g2 - 2 * g3) * a1 + (g3 - g2) * m1
        dd = (6 * g2 - 6 * g) * a0 + (3 * g2 - 4 * g + 1) * m0 + (6 * g - 6 * g2) * a1 + (3 * g2 - 2 * g) * m1
        return pp, dd / np.maximum(row_norms(dd), 1e-300)[:, None]

    found, _ = _least_on(e_mid, chord, u[k - 1], u[k], MIDPOINT_SAMPLES)
    p_f, d_f = exact(found)
    mid[k] = ray_distance(e_mid, p_f, d_f)
    # Past the tolerance: sought again on the exact path, the few still past it to the end (_refined);
    # then the largest few until the largest is sought (reported as the least, not a bound), at most
    # REPORT_ROUNDS rounds.
    bound, done = mid[k], np.zeros(k.size, dtype=bool)
    doubt = np.flatnonzero(bound > REFINE_SHARE * tol)
    for round_ in range(REPORT_ROUNDS):
        if doubt.size:
            bound[doubt] = np.minimum(bound[doubt], _least_on(e_mid[doubt], exact, u[k - 1][doubt], u[k][doubt],
                                                              MIDPOINT_SAMPLES)[1])
            done[doubt] = True
            # The largest are reported: sought to the end whatever their bound (the figure then holds
            # from run to run, not one search's bound).
            still = doubt[bound[doubt] > REFINE_SHARE * tol] if round_ == 0 else doubt
            if still.size:
                bound[still] = np.minimum(bound[still], _refined(e_mid[still], plane, u[k - 1][still], u[k][still]))
        top = np.argsort(bound)[-REPORT_TOP:]
        doubt = top[~done[top]]
        if done[top[-1]] or doubt.size == 0:
            break
    mid[k] = bound
    return point, mid


def program_deviations(plan: WindingPlan, program, tol: float) -> Deviations:
    """Deviations of every row of a MotionProgram (winder.machine.program) from the plan it lays,
    from the rows as written (module docstring)."""
    from winder.machine.program import as_written  # noqa: PLC0415 - program imports the machine stage

    values = as_written(program.values, program.robot)
    eyes = written_eyes(values, program.robot)
    point = np.full(values.shape[0], np.nan)
    mid = np.full(values.shape[0], np.nan)
    for layer, segments in zip(plan.layers, program.segments):
        rows, us, moves = [], [], []
        for j, seg in enumerate(segments):
            first = seg.start + seg.approach
            if seg.stop <= first:
                continue
            r = np.arange(first, seg.stop)
            rows.append(r)
            us.append(program.index[r])
            lays = np.ones(r.size, dtype=bool)
            lays[0] = False  # the move into a pass belongs to the join before it
            moves.append(lays)
        if not rows:
            continue
        paths = SmoothPaths(plan.surface_of(layer.index), list(layer.passes))
        offsets = [paths.offset[j] for j, seg in enumerate(segments) if seg.stop > seg.start + seg.approach]
        r = np.concatenate(rows)
        u = np.concatenate([o + x for o, x in zip(offsets, us)])
        planned = np.concatenate([np.asarray(fp.points, dtype=float).reshape(-1, 3) for fp in layer.passes])
        point[r], mid[r] = layer_deviations(paths, planned, eyes[r], _midway(values, program.robot, r), u,
                                            np.concatenate(moves), tol)
    return Deviations(point, mid)


def _midway(values: np.ndarray, robot: bool, rows: np.ndarray) -> np.ndarray:
    """The eye (k, 3) halfway along the move to each of the rows (k,) from the row before it: the
    axes (or the pose's position) interpolated linearly, as the controller moves them."""
    before = values[np.maximum(rows - 1, 0)]
    half = 0.5 * (before + values[rows])
    return written_eyes(half, robot)

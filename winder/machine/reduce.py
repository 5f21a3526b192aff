"""Point reduction of the motion program (winder.machine.program): Douglas-Peucker on the scaled
axis-space polyline of each pass, every pass of a program in one batch.

Douglas-Peucker splits a polyline at its point farthest from the chord between the ends, then each
half in turn, until every point left out lies within the tolerance of its chord. The splits of one
polyline do not depend on one another's order, so all the open chords of all the passes are taken
at once, one level of the recursion per round: a round costs a few array operations over the points
still under an open chord, instead of one Python step per kept point.

Polylines that are translates of one another within TRANSLATE_TOL (a helical layer's turned circuits: the
same X, Z and B, A shifted by the turn), with the same tolerance, are reduced once: a copy keeps its
representative's points, each dropped point then within tol + 4 TRANSLATE_TOL of its chord (the program's
tolerances keep a margin of micrometres for its own rounding, winder.machine.program).

The contact a kept row stands for (far_contacts). A straight stretch of a pass (a flat face of a box tube:
every point's tangent is one line) gives one eye for all its points, and the reduction keeps one of those
rows, the first at the largest distance (a round-off tie). Seen from that eye the fiber lies along the
whole stretch and leaves it at its far end, where `winder simulate` reads the contact
(winder.readback.contact_windows.far_ties): the row's index and the fiber of the move to it are taken
there, its axes stay. Before, a program read back put each flat face's fiber (157 mm on
configs/rounded_tube.yaml) on the move before the one the program timed it on: the time read back was
0.13 % over the program's.
"""

from __future__ import annotations

import numpy as np
from winder.geometry.measure import row_norms

TRANSLATE_TOL = 1e-9  # scaled mm: polylines that are translates within this are reduced once
TRANSLATE_BUCKET = 1e-6  # scaled mm: the grid of the end's offset that sorts candidates before the comparison
# mm: a dense row whose tangent ray passes this near a kept row's eye shares it: the last decimal the program
# writes (winder.machine.limits.AXIS_DECIMALS), within which `winder simulate` takes two rays to fit an eye
# alike (winder.readback.contacts.TIE is this number)
FLAT_TIE = 1e-3


def reduce_points(q: np.ndarray, tol: float) -> np.ndarray:
    """Indices kept by Douglas-Peucker on the polyline q (m, k) with tolerance tol: every dropped
    point lies within tol of the segment between its kept neighbours. First and last are kept."""
    return reduce_many([q], [tol])[0]


def reduce_many(polylines: list[np.ndarray], tols) -> list[np.ndarray]:
    """reduce_points of every polyline (m_i, k) with its tolerance tols[i], in one batch: the kept
    indices (into each polyline) of each."""
    sizes = np.array([len(q) for q in polylines], dtype=int)
    if sizes.size == 0:
        return []
    width = max((np.asarray(q).shape[1] for q in polylines if len(q)), default=1)
    return reduce_table(np.concatenate([np.asarray(p, dtype=float).reshape(-1, width) for p in polylines]), sizes, tols)


def reduce_table(q: np.ndarray, sizes: np.ndarray, tols) -> list[np.ndarray]:
    """reduce_many of the polylines stored one after the other in q (sum(sizes), k), polyline i
    sizes[i] rows long: the kept indices (into each polyline) of each; translated copies reduced
    once (module docstring)."""
    q = np.asarray(q, dtype=float)
    sizes = np.asarray(sizes, dtype=int)
    tols = np.broadcast_to(np.asarray(tols, dtype=float), sizes.shape)
    width = q.shape[1] if q.ndim == 2 else 1
    q = q.reshape(-1, width)
    start = np.cumsum(sizes) - sizes
    # Each polyline against the representatives so far of its size, tolerance and end offset (on a
    # coarse grid, so that distinct polylines are rarely compared; a copy split off by a cell
    # boundary is only reduced on its own).
    reps: dict[tuple, list[tuple[int, np.ndarray]]] = {}
    rep = np.arange(sizes.size)
    for i, (a, n) in enumerate(zip(start.tolist(), sizes.tolist())):
        if n < 3:
            continue
        rel = q[a:a + n] - q[a]
        known = reps.setdefault((n, float(tols[i]), *np.round(rel[-1] / TRANSLATE_BUCKET).tolist()), [])
        same = next((r for r, other in known if np.max(np.abs(rel - other)) <= TRANSLATE_TOL), None)
        if same is None:
            known.append((i, rel))
        else:
            rep[i] = same
    own = np.flatnonzero(rep == np.arange(sizes.size))
    if own.size == sizes.size:
        return _reduce_distinct(q, sizes, tols)
    rows = np.concatenate([np.arange(start[i], start[i] + sizes[i]) for i in own.tolist()])
    kept = _reduce_distinct(q[rows], sizes[own], tols[own])
    at = np.full(sizes.size, -1)
    at[own] = np.arange(own.size)
    return [kept[at[r]] for r in rep.tolist()]


def _reduce_distinct(q: np.ndarray, sizes: np.ndarray, tols) -> list[np.ndarray]:
    """reduce_table without looking for copies."""
    q = np.asarray(q, dtype=float)
    sizes = np.asarray(sizes, dtype=int)
    if sizes.size == 0:
        return []
    width = q.shape[1] if q.ndim == 2 else 1
    q = q.reshape(-1, width)
    start = np.cumsum(sizes) - sizes
    keep = np.zeros(q.shape[0], dtype=bool)
    some = sizes > 0
    keep[start[some]] = True
    keep[(start + sizes - 1)[some]] = True
    tol_of = np.repeat(np.asarray(tols, dtype=float), sizes)  # per point: the tolerance of its pass
    lo, hi = start[sizes > 2], (start + sizes - 1)[sizes > 2]  # the open chords, in point order
    while lo.size:
        n = hi - lo - 1  # interior points of each chord
        open_ = n > 0
        lo, hi, n = lo[open_], hi[open_], n[open_]
        if lo.size == 0:
            break
        first = np.cumsum(n) - n
        idx = np.arange(int(first[-1] + n[-1])) + np.repeat(lo + 1 - first, n)
        a = q[lo]
        seg = q[hi] - a
        seg_p = np.repeat(seg, n, axis=0)
        rel = q[idx] - np.repeat(a, n, axis=0)
        len2_p = np.repeat(np.einsum("ij,ij->i", seg, seg), n)
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.clip(np.einsum("ij,ij->i", rel, seg_p) / len2_p, 0.0, 1.0)  # the nearest point of the chord
        u[~(len2_p > 0.0)] = 0.0
        dist = row_norms(rel - u[:, None] * seg_p)
        top = np.maximum.reduceat(dist, first)
        # The first point at the largest distance (np.argmax's choice).
        at_top = np.where(dist == np.repeat(top, n), np.arange(dist.size), dist.size)
        j = idx[np.minimum.reduceat(at_top, first)]
        split = top > tol_of[lo]
        j, lo, hi = j[split], lo[split], hi[split]
        keep[j] = True
        # Each split chord's halves side by side: the chords stay in point order.
        lo, hi = np.column_stack([lo, j]).ravel(), np.column_stack([j, hi]).ravel()
    kept = np.flatnonzero(keep)
    cuts = np.searchsorted(kept, start + sizes)
    return [kept[a:b] - s for a, b, s in zip(np.concatenate([[0], cuts[:-1]]).tolist(), cuts.tolist(), start.tolist())]


def far_contacts(table: np.ndarray, points: np.ndarray, u: np.ndarray, n: np.ndarray, rows: np.ndarray,
                 first: np.ndarray, written: np.ndarray) -> np.ndarray:
    """(k,) the contact each kept row stands for (module docstring), as a fractional row of the dense table
    (m, 4) of logical axes (carriage, rotation deg, cross-feed, yaw) or (m, 6) eye poses, all passes one
    after the other (n (passes,) rows each, a pass's first and last row kept), with contact points
    points (m, 3) and point indices u (m,): rows (k,) the kept rows, first their positions that start a
    pass (kept as they are: a pass's first row lays nothing), written (k, width) their axes as printed.
    A kept row moves over the rows after it, before the next kept one, whose rays pass within FLAT_TIE of
    its eye as written beyond its own ray's distance from it (the rounding); then on toward the next row
    by the share where the stretch ends, from the two rows after it, whose rays miss its eye in
    proportion to their way past the end (the corner's tangent turns from it)."""
    count, robot = table.shape[0], table.shape[1] > 4
    if rows.size == 0 or count < 2:
        return rows.astype(float)
    eye = _eyes(table, robot)
    ray = eye - points
    ray /= np.maximum(row_norms(ray), 1e-300)[:, None]
    kept = np.zeros(count, dtype=bool)
    kept[rows] = True
    at = np.arange(count)
    owner = np.maximum.accumulate(np.where(kept, at, 0))  # the kept row at or before each row
    miss = _miss(_eyes(written, robot)[np.cumsum(kept) - 1], points, ray)
    stop = np.where(kept | (miss > miss[owner] + FLAT_TIE), at, count)  # a kept row, or a ray that misses
    after = np.append(np.minimum.accumulate(stop[::-1])[::-1][1:], count)
    far = after[rows] - 1
    far[first] = rows[first]
    share = np.zeros(rows.size)
    last = np.repeat(np.cumsum(n) - 1, n)  # each row's pass's last row
    ok = np.flatnonzero((far > rows) & (far + 2 <= last[far]))
    if ok.size:
        f, e = far[ok], eye[rows[ok]]
        m1, m2 = _miss(e, points[f + 1], ray[f + 1]), _miss(e, points[f + 2], ray[f + 2])
        u0, u1, u2 = u[f], u[f + 1], u[f + 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            end = u1 - m1 * (u2 - u1) / (m2 - m1)
            t = np.where((m2 > m1) & (u1 > u0), (np.clip(end, u0, u1) - u0) / (u1 - u0), 0.0)
        share[ok] = np.where(np.isfinite(t), t, 0.0)
    return far + share


def _eyes(table: np.ndarray, robot: bool) -> np.ndarray:
    """(m, 3) the eye of each row in the mandrel frame: a pose's position; with the mandrel turned by A,
    (Z cos(-A), Z sin(-A), X) (docs/guide/conventions.md)."""
    if robot:
        return table[:, :3]
    a = np.radians(table[:, 1])
    return np.column_stack([table[:, 2] * np.cos(-a), table[:, 2] * np.sin(-a), table[:, 0]])


def _miss(eye: np.ndarray, points: np.ndarray, ray: np.ndarray) -> np.ndarray:
    """(m,) how far the rays from points (m, 3) along the unit ray (m, 3) pass from eye (m, 3) (from the
    ray's start where the eye lies behind it)."""
    rel = eye - points
    along = np.einsum("ij,ij->i", rel, ray)
    return np.where(along > 0.0, row_norms(rel - along[:, None] * ray), row_norms(rel))

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
"""

from __future__ import annotations

import numpy as np
from winder.geometry.measure import row_norms

TRANSLATE_TOL = 1e-9  # scaled mm: polylines that are translates within this are reduced once
TRANSLATE_BUCKET = 1e-6  # scaled mm: the grid of the end's offset that sorts candidates before the comparison


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

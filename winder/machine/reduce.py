"""Point reduction of the motion program (winder.machine.program): Douglas-Peucker on the scaled
axis-space polyline of each pass, every pass of a program in one batch.

Douglas-Peucker splits a polyline at its point farthest from the chord between the ends, then each
half in turn, until every point left out lies within the tolerance of its chord. The splits of one
polyline do not depend on one another's order, so all the open chords of all the passes are taken
at once, one level of the recursion per round: a round costs a few array operations over the points
still under an open chord, instead of one Python step per kept point.

The arithmetic per chord is that of the one-pass form (the same products in the same order), so the
kept points are the same.
"""

from __future__ import annotations

import numpy as np
from winder.geometry.measure import row_norms


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
    q = np.concatenate([np.asarray(p, dtype=float).reshape(-1, width) for p in polylines])
    start = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    keep = np.zeros(q.shape[0], dtype=bool)
    some = sizes > 0
    keep[start[some]] = True
    keep[(start + sizes - 1)[some]] = True
    tol_of = np.repeat(np.asarray(tols, dtype=float), sizes)  # per point: the tolerance of its pass
    lo, hi = start[sizes > 2], (start + sizes - 1)[sizes > 2]  # the open chords
    while lo.size:
        n = hi - lo - 1  # interior points of each chord
        open_ = n > 0
        lo, hi, n = lo[open_], hi[open_], n[open_]
        if lo.size == 0:
            break
        order = np.argsort(lo, kind="stable")  # chords in point order: the gathers below run forward
        lo, hi, n = lo[order], hi[order], n[order]
        first = np.concatenate([[0], np.cumsum(n)[:-1]])
        chord = np.repeat(np.arange(lo.size), n)
        idx = np.arange(int(n.sum())) + np.repeat(lo + 1 - first, n)
        a = q[lo]
        seg = q[hi] - a
        len2 = np.matmul(seg[:, None, :], seg[:, :, None])[:, 0, 0]  # as seg @ seg, bit for bit
        rel = q.take(idx, axis=0) - a.take(chord, axis=0)
        seg_p = seg.take(chord, axis=0)
        len2_p = len2[chord]
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.clip(np.einsum("ij,ij->i", rel, seg_p) / len2_p, 0.0, 1.0)  # as rel @ seg
        u[~(len2_p > 0.0)] = 0.0
        rel -= u[:, None] * seg_p
        dist = row_norms(rel)
        top = np.maximum.reduceat(dist, first)
        # The first point at the largest distance (np.argmax's choice).
        at_top = np.where(dist == top[chord], np.arange(dist.size), dist.size)
        j = idx[np.minimum.reduceat(at_top, first)]
        split = top > tol_of[lo]
        j, lo, hi = j[split], lo[split], hi[split]
        keep[j] = True
        lo, hi = np.concatenate([lo, j]), np.concatenate([j, hi])
    return [np.flatnonzero(keep[s:s + m]) for s, m in zip(start, sizes)]

"""A sample's contact held off its ray by its neighbours' (winder.app.simulate, after contacts.repair).

At a dome's turnaround the rays sweep fast: a move's midpoint may fit a ray a little past the true
contact of the row after it (parts/copv_12.yaml: the midpoint 0.004 mm off at u = 196.47, the row's only
fit at u = 196.15..196.31), so the contacts of three samples pile up on one point and the row reads
1.1 mm off its ray, although the midpoint also fits at u = 195.32 (0.014 mm) and every sample of the
stretch fits within the chord tolerance in order. repair moves one sample at a time between its
neighbours and keeps a move only where that sample does better, so it cannot undo such a pile-up.
Here each sample still off by more than the tolerance is matched again together with WINDOW samples on
either side: the dynamic program of winder.readback.contacts over fine reads of the stretch the samples just
outside leave (REPAIR_TURN apart, and REPAIR_STEP), the least total ray distance in order, each read
picked then refined between its neighbouring reads (winder.readback.contacts.refine); the new contacts are
kept where the stretch's largest distance drops.
"""

from __future__ import annotations

import numpy as np

from winder.readback.contacts import monotone_group, ray_distance, refine, window_reads
from winder.machine.smooth import SmoothPaths

WINDOW = 1  # samples matched again on either side of one off its ray
ROUNDS = 3  # stretches that share a sample are matched in later rounds
MAX_STRETCHES = 2_000  # more samples off than this: the program is reported as it reads


def unpin(paths: SmoothPaths, eye: np.ndarray, u: np.ndarray, chain: np.ndarray, position: np.ndarray,
          tol: float) -> np.ndarray:
    """u (n,) with the stretches around samples off their rays by more than tol matched again
    (module docstring); eye (n, 3), chain and position (n,) as in winder.readback.contacts.repair."""
    order = np.lexsort((position, chain))
    ch = chain[order]
    out = u.astype(float, copy=True)
    for _ in range(ROUNDS):
        _, _, p, d = paths.point(out[order])
        dist = ray_distance(eye[order], p, d)
        bad = np.flatnonzero(dist > tol)
        if not bad.size or bad.size > MAX_STRETCHES:
            break
        # Stretches that share no sample with an earlier one this round.
        keep = np.concatenate([[True], np.diff(bad) > 2 * WINDOW + 2])
        q = bad[keep]
        offs = np.arange(-WINDOW - 1, WINDOW + 2)
        at = np.clip(q[:, None] + offs, 0, order.size - 1)
        same = ch[at] == ch[q][:, None]
        inner = same[:, 1:-1]
        seq = np.where(inner, order[at[:, 1:-1]], -1)
        # The stretch left between the contacts of the samples just outside (or its own ends).
        span = np.where(inner, out[order[at[:, 1:-1]]], np.nan)
        lo = np.where(same[:, 0], out[order[at[:, 0]]], np.nanmin(span, axis=1))
        hi = np.where(same[:, -1], out[order[at[:, -1]]], np.nanmax(span, axis=1))
        window, reads, rp, rd = window_reads(paths, lo, hi)
        count = np.bincount(window, minlength=q.size)
        begin = np.cumsum(count) - count
        jmax = int(count.max())
        index = np.minimum(begin[:, None] + np.arange(jmax), (begin + count - 1)[:, None])
        pick = monotone_group(eye, seq, rp[index], rd[index], count)
        new_u = _polished(paths, eye, seq, inner, reads, index, pick)
        rows = seq[inner]
        _, _, p1, d1 = paths.point(new_u[inner])
        new_d = np.full(seq.shape, -np.inf)
        old_d = np.full(seq.shape, -np.inf)
        new_d[inner] = ray_distance(eye[rows], p1, d1)
        old_d[inner] = dist[np.clip(q[:, None] + offs[1:-1], 0, order.size - 1)][inner]
        better = new_d.max(axis=1) < old_d.max(axis=1)
        take = inner & better[:, None]
        out[seq[take]] = new_u[take]
    return out


def _polished(paths: SmoothPaths, eye: np.ndarray, seq: np.ndarray, inner: np.ndarray, reads: np.ndarray,
              index: np.ndarray, pick: np.ndarray) -> np.ndarray:
    """(q, l) the contacts of the stretches' samples seq (q, l) (inner: those in the stretch): each
    read the dynamic program picked (pick (q, l) into index (q, j), the stretch's reads) refined
    between the reads either side of it (contacts.refine), then held nondecreasing along the stretch.
    Near a dome's polar opening the rays of an eye 120 mm out sweep past it by 0.015 mm per 1e-3 of
    the point index, and the reads are up to 1/64 apart (REPAIR_STEP): the read alone left a
    programmed point of parts/tank_20.yaml 0.091 mm off its ray, its contact 0.006 short of the one
    it was written for (0.001 mm off)."""
    rows = np.arange(seq.shape[0])[:, None]
    last = index.shape[1] - 1
    mid = reads[index[rows, pick]]
    left = reads[index[rows, np.maximum(pick - 1, 0)]]
    right = reads[index[rows, np.minimum(pick + 1, last)]]
    out = mid.copy()
    out[inner] = refine(paths, eye[seq[inner]], left[inner], mid[inner], right[inner])
    # Two picks on neighbouring reads may cross once refined: the later one is held at the earlier's.
    held = np.maximum.accumulate(np.where(inner, out, -np.inf), axis=1)
    return np.where(inner, held, out)

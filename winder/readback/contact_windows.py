"""A sample's contact held off its ray by its neighbours' (winder.app.simulate, after contacts.repair).

At a dome's turnaround the rays sweep fast: a move's midpoint may fit a ray a little past the true
contact of the row after it (parts/copv_12.yaml: the midpoint 0.004 mm off at u = 196.47, the row's only
fit at u = 196.15..196.31), so the contacts of three samples pile up on one point and the row reads
1.1 mm off its ray, although the midpoint also fits at u = 195.32 (0.014 mm) and every sample of the
stretch fits within the chord tolerance in order. repair moves one sample at a time between its
neighbours and keeps a move only where that sample does better, so it cannot undo such a pile-up.
Here each sample still off by more than the tolerance is matched again together with WINDOW samples on
either side: the dynamic program of winder.readback.contacts over fine reads of the stretch the samples just
outside leave (at a chain's end, to its pass's end; REPAIR_TURN apart, and REPAIR_STEP), the least total
ray distance in order, each read picked then refined between its neighbouring reads
(winder.readback.contacts.refine); the new contacts are kept where the stretch's largest distance drops.

A sample on a flat face (far_ties). An eye on a flat's line (within TIE, the rounding of the printed
values) fits every point of the flat to round-off, so the dynamic program's pick and its refinement land
anywhere on it and the flat's fiber (157 mm on configs/rounded_tube.yaml) is split between two moves by
chance. Seen from that eye the fiber lies along the whole flat and leaves it at its far end, where the
program writer puts that row's contact (winder.machine.reduce.far_contacts): far_ties moves each sample
there, short of the next sample's contact.
"""

from __future__ import annotations

import numpy as np

from winder.readback.contacts import TIE, monotone_group, pass_span, ray_distance, refine, window_reads
from winder.machine.smooth import SmoothPaths

WINDOW = 1  # samples matched again on either side of one off its ray
ROUNDS = 3  # stretches that share a sample are matched in later rounds
MAX_STRETCHES = 2_000  # more samples off than this: the program is reported as it reads
FAR_STEPS = 48  # bisections of the far end of a flat (a point interval to 4e-15)
FAR_LEVEL = 1e-5  # mm: past a flat's last candidate its rays fit no worse than that one's, within this


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
        start, end = pass_span(paths, out[order[q]])  # a stretch at a chain's end: to its pass's end
        lo = np.where(same[:, 0], out[order[at[:, 0]]], start)
        hi = np.where(same[:, -1], out[order[at[:, -1]]], end)
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


def far_ties(paths: SmoothPaths, eye: np.ndarray, u: np.ndarray, chain: np.ndarray, position: np.ndarray,
             cand: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    """u with every sample but a chain's first and last (widen_ends' own) that lies on a straight
    stretch of its pass (a flat face seen along its line) moved forward to the stretch's far end, no
    farther than the next sample's contact. On such a stretch the candidates around the contact fit
    its eye within TIE of its own fit: at least two of the run of them through the contact (the one
    at it, or nearest before or after it, and another), while where the rays turn (a corner, any
    curve) the neighbours of a contact miss by far (the candidates are TURN_STEP apart there). From
    the last candidate of the run ahead (or the contact), FAR_STEPS bisections up to the first point
    whose ray misses by more than FAR_LEVEL beyond that one's: past a flat's end the rays turn away
    (an eye a rounding's width off the flat's line, on its far side, is passed by them once, just
    past the end)."""
    cu, cp, cd, _ = cand
    order = np.lexsort((position, chain))
    ch = chain[order]
    inner = np.zeros(order.size, dtype=bool)
    inner[1:-1] = (ch[1:-1] == ch[:-2]) & (ch[1:-1] == ch[2:])
    at = np.flatnonzero(inner)
    out = u.astype(float, copy=True)
    if not at.size:
        return out
    k, bound = order[at], u[order[at + 1]]
    _, _, p, d = paths.point(u[k])
    own = ray_distance(eye[k], p, d)
    a = np.searchsorted(cu, u[k], "right")
    count = np.maximum(np.searchsorted(cu, bound, "right") - a, 0)  # the candidates in (u, bound]
    of = np.repeat(np.arange(k.size), count)
    step = np.arange(of.size) - np.repeat(np.cumsum(count) - count, count)
    c = np.repeat(a, count) + step
    fails = ray_distance(eye[k][of], cp[c], cd[c]) > own[of] + TIE
    run = count.copy()  # the candidates ahead that fit before the first that does not
    np.minimum.at(run, of[fails], step[fails])
    # and the two at or before the contact, on its pass
    start = pass_span(paths, u[k])[0]
    behind = np.zeros(k.size, dtype=int)
    for back in (1, 2):
        j = a - back
        on = (j >= 0) & (cu[np.maximum(j, 0)] >= start) & (behind == back - 1)
        jj = np.maximum(j[on], 0)
        behind[np.flatnonzero(on)[ray_distance(eye[k[on]], cp[jj], cd[jj]) <= own[on] + TIE]] = back
    straight = run + behind >= 2
    last = np.maximum(a + run - 1, 0)
    lo = np.where(run > 0, cu[last], u[k])
    hi = np.where(run < count, cu[np.minimum(a + run, cu.size - 1)], bound)
    level = np.where(run > 0, ray_distance(eye[k], cp[last], cd[last]), own) + FAR_LEVEL

    def fits(v: np.ndarray, rows: np.ndarray) -> np.ndarray:
        _, _, pv, dv = paths.point(v)
        return ray_distance(eye[k[rows]], pv, dv) <= level[rows]

    whole = np.flatnonzero(straight & (run > 0) & (run == count))  # all candidates to the next contact fit
    done = np.zeros(k.size, dtype=bool)
    done[whole] = fits(hi[whole], whole)
    lo[done] = hi[done]
    open_ = np.flatnonzero(straight & ~done & (hi > lo))
    for _ in range(FAR_STEPS if open_.size else 0):
        mid = 0.5 * (lo[open_] + hi[open_])
        ok = fits(mid, open_)
        lo[open_] = np.where(ok, mid, lo[open_])
        hi[open_] = np.where(ok, hi[open_], mid)
    out[k] = np.where(straight, np.minimum(np.maximum(lo, u[k]), bound), u[k])
    return out

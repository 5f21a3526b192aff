"""Contact points of eyes on the planned passes, for `winder simulate` (winder.app.simulate).

The contact point of an eye E is the point p(u) of its pass's smooth path whose tangent ray
p + lambda d, lambda > 0, passes closest to E. Sample by sample that is ambiguous: on a flat face
every point of a straight stretch shares one tangent line, so an eye in the face's plane fits any of
them within rounding; and where the tangent turns fast (a corner between flats) the planned points
straddle the true contact, each missing it by more than the flat does. The eyes of one pass come in
the order the machine lays it, and the contact only moves forward along the pass, so the contacts of
a pass's samples are chosen together: the nondecreasing sequence of planned points with the least
total ray distance (a dynamic program over the samples in order, all passes of a group in each
step), then each refined between the points on either side (sampled finer, then golden-section
search), then held nondecreasing along the pass (a tie on a flat resolves forward, never back); a sample
still off its ray by more than the chord tolerance is searched again finely between its neighbours'
contacts (`repair`: an eye far out sees a corner's rays sweep millimetres between two candidates).
An eye that fits a flat (its line, within TIE) fits every point of it to round-off: the pick lands
anywhere on it; winder.readback.contact_windows.far_ties takes it to the flat's far end.
"""

from __future__ import annotations

import numpy as np

from winder.machine.reduce import FLAT_TIE
from winder.machine.smooth import SmoothPaths

GOLDEN_STEPS = 40  # the bracket of two samples shrinks by 0.618^40 ~ 5e-9 of it
SUB_STEPS = 8  # samples per candidate interval before the golden-section search
TURN_STEP = 0.01  # rad: the most the tangent turns between candidates (an eye 100 mm out: 1 mm apart)
TURN_READS = 4  # the tangent is read at that many even steps along each interval for its turning
MAX_SPLIT = 64  # at most that many candidates per point interval
TIE = FLAT_TIE  # mm: rays that near an eye's best fit it as well (the program's values are rounded to 1e-3)
REPAIR_TURN = 2e-4  # rad between the repair's samples: an eye 250 mm out, 0.05 mm apart
REPAIR_SPLIT = 256  # at most that many per point interval
REPAIR_STEP = 1.0 / 64.0  # and evenly that far apart (u): the rays also move sideways where they turn little
REPAIR_GRID = 2048  # at most that many even reads per window
REPAIR_ROUNDS = 12  # half-sweeps (alternate samples of a chain, then the others)
# The repair is for a program's few misses at corners (configs/rounded_tube.yaml: 645 of 20,017
# samples, 4 s). One mostly off its plan, such as another config's (29,566 of 30,425 off, 67 s), is
# reported off without it: past this share of its samples, or this many, the search is skipped.
REPAIR_MAX_SHARE = 0.1
REPAIR_MAX_SAMPLES = 2_000
TABLE_ENTRIES = 8_000_000  # back-pointers kept at once by the dynamic program (int32 each)
WIDEN_ENTRIES = 2_000_000  # chain ends times candidates measured at once by widen_ends
_INV_PHI = (np.sqrt(5.0) - 1.0) / 2.0


def ray_distance(e: np.ndarray, p: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Distance of eyes e (..., 3) from the tangent rays p + lambda d, lambda > 0 (unit d (..., 3)):
    from the ray's start where the eye lies behind it."""
    rel = e - p
    along = np.einsum("...j,...j->...", rel, d)
    off = np.linalg.norm(rel - along[..., None] * d, axis=-1)
    return np.where(along > 0.0, off, np.linalg.norm(rel, axis=-1))


def segment_miss(eye: np.ndarray, points: np.ndarray, dirs: np.ndarray) -> np.ndarray:
    """(c, j): how near each eye (c, 3) comes to the rays of candidates j to j + 1 (points / dirs
    (3, c, j): a component each, the arithmetic running along j; the last one repeated): the eye's
    offset from the ray, linear between two candidates (the tangent turns little between them), at
    its smallest. Between two candidates a corner's rays sweep past an eye that neither of them
    passes near."""
    rel = [eye[:, i, None] - points[i] for i in range(3)]
    along = rel[0] * dirs[0] + rel[1] * dirs[1] + rel[2] * dirs[2]
    ahead = along > 0.0
    off = [np.where(ahead, r - along * d, r) for r, d in zip(rel, dirs)]
    ab = []
    for o in off:
        step = np.zeros_like(o)
        step[:, :-1] = o[:, 1:] - o[:, :-1]
        ab.append(step)
    den = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]
    h = np.clip(-(off[0] * ab[0] + off[1] * ab[1] + off[2] * ab[2]) / np.where(den > 0, den, 1.0), 0.0, 1.0)
    near = [o + h * s for o, s in zip(off, ab)]
    return np.sqrt(near[0] * near[0] + near[1] * near[1] + near[2] * near[2])


def prefix_argmin(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(running minimum, index of its first occurrence) along the last axis of v (c, j)."""
    low = np.minimum.accumulate(v, axis=1)
    new = np.ones(v.shape, dtype=bool)
    new[:, 1:] = v[:, 1:] < low[:, :-1]
    return low, np.maximum.accumulate(np.where(new, np.arange(v.shape[1]), 0), axis=1)


def monotone_group(eye: np.ndarray, seq: np.ndarray, points: np.ndarray, dirs: np.ndarray,
                   count: np.ndarray) -> np.ndarray:
    """The dynamic program for c chains at once: seq (c, l) sample indices (-1 past a chain's end),
    points / dirs (c, j, 3) of each chain's pass, count (c,) its points. The chosen point of each
    entry of seq (c, l)."""
    c, length = seq.shape
    jj = points.shape[1]
    points, dirs = (np.ascontiguousarray(np.moveaxis(v, -1, 0)) for v in (points, dirs))
    valid = np.arange(jj) < count[:, None]
    rows = np.arange(c)
    back = np.zeros((length, c, jj), dtype=np.int32)
    total = np.zeros((c, jj))
    for i in range(length):
        on = seq[:, i] >= 0
        cost = segment_miss(eye[np.maximum(seq[:, i], 0)], points, dirs)
        cost = np.where(valid, np.where(on[:, None], cost, 0.0), np.inf)
        if i:
            low, back[i] = prefix_argmin(total)
            total = cost + low
        else:
            total = cost
    pick = np.zeros((c, length), dtype=int)
    pick[:, -1] = np.argmin(total, axis=1)
    for i in range(length - 1, 0, -1):
        pick[:, i - 1] = back[i][rows, pick[:, i]]
    return pick


def monotone_points(eye: np.ndarray, chain: np.ndarray, position: np.ndarray, pass_of: np.ndarray,
                    points: np.ndarray, dirs: np.ndarray, start: np.ndarray) -> np.ndarray:
    """For each sample (eye (n, 3)) the candidate of its pass (pass_of (n,); pass j's candidates are
    points / dirs (c, 3) [start[j]:start[j + 1]]) that makes the contacts of every chain (samples
    with one chain id, ordered by position, all of one pass) nondecreasing with the least total ray
    distance. (n,) indices into points."""
    n = eye.shape[0]
    out = np.zeros(n, dtype=int)
    order = np.lexsort((position, chain))
    _, begin, length = np.unique(chain[order], return_index=True, return_counts=True)
    of_chain = pass_of[order[begin]]
    size = start[of_chain + 1] - start[of_chain]
    # Chains of like lengths and candidate counts share a table (little padding), a bounded number at once.
    key = np.array([int(v).bit_length() * 64 + int(w).bit_length() for v, w in zip(length, size)])
    for k in np.unique(key):
        members = np.flatnonzero(key == k)
        lmax, jmax = int(length[members].max()), int(size[members].max())
        step = max(1, TABLE_ENTRIES // (lmax * jmax))
        for chunk in np.array_split(members, -(-members.size // step)):
            at = np.arange(lmax)
            inside = at[None, :] < length[chunk, None]
            seq = np.full((chunk.size, lmax), -1, dtype=int)
            seq[inside] = order[(begin[chunk, None] + at[None, :])[inside]]
            jj = np.arange(jmax)
            index = np.minimum(start[of_chain[chunk], None] + jj, start[of_chain[chunk] + 1, None] - 1)
            pick = monotone_group(eye, seq, points[index], dirs[index], size[chunk])
            out[seq[inside]] = index[np.nonzero(inside)[0], pick[inside]]
    return out


def candidates(paths: SmoothPaths, step: float = TURN_STEP, max_split: int = MAX_SPLIT,
               wanted: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Points of the smooth paths the contact search starts from: the planned points, and between
    two of them where the tangent turns by more than TURN_STEP, evenly spaced ones (in u) that it
    turns less between (at a corner the rays of neighbouring points miss an eye between them by far).
    wanted (n,) bool: only these nodes and the intervals they start (default: all).
    (u (c,), p (c, 3), unit d (c, 3), start (passes + 1,): pass j's candidates are start[j]:start[j+1])."""
    count = paths.s.size
    last = np.zeros(count, dtype=bool)
    last[paths.last] = True
    if wanted is None:
        wanted = np.ones(count, dtype=bool)
    inside = ~last[:-1] & wanted[:-1]
    # The turning along each interval, read at its quarters: at a corner's end the tangent may turn
    # and turn back between two points whose own tangents nearly agree. At the ends: the nodes'.
    k = np.flatnonzero(inside)
    dq = np.empty((k.size, TURN_READS + 1, 3))
    q = (k[:, None] + np.linspace(0.0, 1.0, TURN_READS + 1)[1:-1]).ravel()
    dq[:, 1:-1] = paths.point(q)[3].reshape(k.size, TURN_READS - 1, 3)
    dq[:, 0], dq[:, -1] = _unit(paths.d[k]), _unit(paths.d[k + 1])
    turn = np.zeros(count - 1 if count else 0)
    turn[k] = np.arccos(np.clip(np.einsum("kij,kij->ki", dq[:, :-1], dq[:, 1:]), -1.0, 1.0)).sum(axis=1)
    split = np.where(inside, np.clip(np.ceil(turn / step), 1, max_split), 0).astype(int)
    per_node = np.concatenate([split, [0]]) + (last & wanted)  # a pass's last node: one more
    at = np.repeat(np.arange(count), per_node)
    within = np.arange(at.size) - np.repeat(np.cumsum(per_node) - per_node, per_node)
    u = at + within / np.maximum(np.concatenate([split, [1]])[at], 1)
    _, _, p, d = paths.point(u)
    start = np.concatenate([[0], np.cumsum(per_node)[paths.last]])
    return u, p, d, start


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=1)
    return v / np.where(n > 0, n, 1.0)[:, None]


def refine(paths: SmoothPaths, eye: np.ndarray, left: np.ndarray, mid: np.ndarray,
           right: np.ndarray) -> np.ndarray:
    """u of the closest tangent ray in [left, right] (n,) for each eye (n, 3): the best of SUB_STEPS
    even samples on either side of mid (the candidate picked, a sample itself), then golden-section
    search between that sample's neighbours (kept only where it does better)."""
    def f(u):
        _, _, p, d = paths.point(u.ravel())
        return ray_distance(np.repeat(eye, u.size // len(eye), axis=0), p, d).reshape(u.shape)

    left, mid, right = (np.asarray(v, dtype=float) for v in (left, mid, right))
    frac = np.linspace(0.0, 1.0, SUB_STEPS + 1)
    grid = np.hstack([left[:, None] + (mid - left)[:, None] * frac[:-1], mid[:, None] + (right - mid)[:, None] * frac])
    miss = f(grid)
    rows, at = np.arange(len(mid)), np.argmin(miss, axis=1)
    best, fbest = grid[rows, at], miss[rows, at]
    a, b = grid[rows, np.maximum(at - 1, 0)], grid[rows, np.minimum(at + 1, grid.shape[1] - 1)]
    a, b = golden(lambda v: f(v[:, None])[:, 0], a, b)
    found = 0.5 * (a + b)
    return np.where(f(found[:, None])[:, 0] <= fbest, found, best)


def golden(f, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The brackets [a, b] (n,) of f's minima after GOLDEN_STEPS golden-section steps (f of (n,) u:
    (n,) values). Each step reads f once: the inner point kept is the next step's other one."""
    c, d = b - _INV_PHI * (b - a), a + _INV_PHI * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(GOLDEN_STEPS):
        left_side = fc < fd
        b, a = np.where(left_side, d, b), np.where(left_side, a, c)
        # Left: the old c is the new d; right: the old d is the new c; the other one is read.
        new = np.where(left_side, b - _INV_PHI * (b - a), a + _INV_PHI * (b - a))
        fnew = f(new)
        c, d = np.where(left_side, new, d), np.where(left_side, c, new)
        fc, fd = np.where(left_side, fnew, fd), np.where(left_side, fc, fnew)
    return a, b


def forward(u: np.ndarray, chain: np.ndarray, position: np.ndarray) -> np.ndarray:
    """u held nondecreasing along each chain (in the order of position): a later sample's contact
    never behind an earlier one's."""
    order = np.lexsort((position, chain))
    ch = chain[order]
    # Each chain lifted above all before it, so one running maximum serves all chains.
    lift = (np.cumsum(np.concatenate([[False], ch[1:] != ch[:-1]])) * (np.abs(u).max() * 2.0 + 1.0))
    out = np.empty_like(u)
    out[order] = np.maximum.accumulate(u[order] + lift) - lift
    return out


def widen_ends(paths: SmoothPaths, eye: np.ndarray, u: np.ndarray, chain: np.ndarray, position: np.ndarray,
               pass_of: np.ndarray, cand: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    """u with each chain's first sample moved back, and its last forward, over the candidates whose
    rays fit its eye within TIE of its own (a pass starting or ending on a flat face: the eye lies
    on the line of all of it, and the fiber of the whole flat is laid)."""
    cu, cp, cd, start = cand
    order = np.lexsort((position, chain))
    ch = chain[order]
    out = u.copy()
    for end, side in ((np.concatenate([[True], ch[1:] != ch[:-1]]), -1),
                      (np.concatenate([ch[1:] != ch[:-1], [True]]), 1)):
        for k in _chunks(order[end], start[pass_of[order[end]] + 1] - start[pass_of[order[end]]]):
            out[k] = _widen(paths, eye, u, k, pass_of, cand, side)
    return out


def _chunks(k: np.ndarray, size: np.ndarray) -> list[np.ndarray]:
    """k (c,) split into runs whose rows times the largest of their sizes (c,) stay within
    WIDEN_ENTRIES (one chain's end against all candidates of its pass at once)."""
    if not k.size:
        return []
    rows = max(1, WIDEN_ENTRIES // max(int(size.max()), 1))
    return [k[i:i + rows] for i in range(0, k.size, rows)]


def _widen(paths: SmoothPaths, eye: np.ndarray, u: np.ndarray, k: np.ndarray, pass_of: np.ndarray,
           cand: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray], side: int) -> np.ndarray:
    """widen_ends for the chain ends k (c,), the first (side -1) or the last (side 1): their new u."""
    cu, cp, cd, start = cand
    j = pass_of[k]
    jmax = int((start[j + 1] - start[j]).max())
    index = np.minimum(start[j, None] + np.arange(jmax), start[j + 1, None] - 1)
    miss = ray_distance(eye[k][:, None, :], cp[index], cd[index])
    _, _, p, d = paths.point(u[k])
    fits = miss <= ray_distance(eye[k], p, d)[:, None] + TIE
    at = np.arange(jmax)
    here = np.clip(np.searchsorted(cu, u[k], "right" if side < 0 else "left") - (side < 0) - start[j],
                   0, start[j + 1] - start[j] - 1)
    if side < 0:  # the run of fitting candidates up to the contact: back to its first
        bad = np.maximum.accumulate(np.where(fits, -1, at), axis=1)
        reach = np.maximum(bad[np.arange(k.size), here] + 1, 0)
        return np.minimum(u[k], cu[start[j] + reach])
    bad = np.minimum.accumulate(np.where(fits, jmax, at)[:, ::-1], axis=1)[:, ::-1]
    reach = np.minimum(bad[np.arange(k.size), here], start[j + 1] - start[j]) - 1
    return np.maximum(u[k], cu[start[j] + reach])


def _touched(count: int, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(count,) bool: the nodes floor(lo) to floor(hi) + 1 of each window [lo, hi] (k,)."""
    first = np.clip(np.floor(lo).astype(int), 0, count)
    stop = np.clip(np.floor(hi).astype(int) + 2, 0, count)
    edge = np.zeros(count + 1, dtype=int)
    np.add.at(edge, first, 1)
    np.add.at(edge, stop, -1)
    return np.cumsum(edge)[:count] > 0


def window_reads(paths: SmoothPaths, lo: np.ndarray,
                 hi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(window (r,), u (r,), p (r, 3), unit d (r, 3)) of the reads of every window [lo, hi] (k,): the
    fine candidates (REPAIR_TURN) in it and reads REPAIR_STEP apart (at most REPAIR_GRID + 1), all
    windows in one evaluation, sorted by window, then u (a candidate before an even read of the same u)."""
    # The fine reads of the nodes and intervals the windows touch, not the whole layer's.
    fu, fp, fd, _ = candidates(paths, REPAIR_TURN, REPAIR_SPLIT, _touched(paths.s.size, lo, hi))
    a0, b0 = np.searchsorted(fu, lo, "left"), np.searchsorted(fu, hi, "right")
    n_even = np.minimum(np.ceil((hi - lo) / REPAIR_STEP), REPAIR_GRID).astype(int) + 1
    win_e = np.repeat(np.arange(lo.size), n_even)
    at_e = np.arange(win_e.size) - np.repeat(np.cumsum(n_even) - n_even, n_even)
    steps = np.maximum(n_even - 1, 1)[win_e]
    even = np.where(at_e == n_even[win_e] - 1, hi[win_e], lo[win_e] + (hi - lo)[win_e] * (at_e / steps))
    _, _, ep, ed = paths.point(even)
    n_fine = b0 - a0
    win_f = np.repeat(np.arange(lo.size), n_fine)
    at_f = np.repeat(a0, n_fine) + np.arange(win_f.size) - np.repeat(np.cumsum(n_fine) - n_fine, n_fine)
    window = np.concatenate([win_f, win_e])
    reads = np.concatenate([fu[at_f], even])
    sort = np.lexsort((reads, window))  # stable
    return window[sort], reads[sort], np.vstack([fp[at_f], ep])[sort], np.vstack([fd[at_f], ed])[sort]


def pass_span(paths: SmoothPaths, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first, last) u of the pass each parameter u (k,) lies on: its first and last point."""
    j = np.clip(np.searchsorted(paths.offset, u, "right") - 1, 0, paths.offset.size - 1)
    return paths.offset[j].astype(float), paths.last[j].astype(float)


def _best_read(paths: SmoothPaths, eye: np.ndarray, lo: np.ndarray,
               hi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(u of the best read, the reads before and after it) (k,) in each window [lo, hi] (k,) for its
    eye (k, 3) (window_reads); a tie goes to the first in u."""
    window, reads, p, d = window_reads(paths, lo, hi)
    dist = ray_distance(eye[window], p, d)
    # The first least distance of each window (lexsort on (position, distance, window)).
    pos = np.arange(reads.size)
    best = np.lexsort((pos, dist, window))
    begin = np.concatenate([[0], np.cumsum(np.bincount(window, minlength=lo.size))[:-1]])
    end = begin + np.bincount(window, minlength=lo.size) - 1
    j = best[begin]
    return reads[j], reads[np.maximum(j - 1, begin)], reads[np.minimum(j + 1, end)]


def repair(paths: SmoothPaths, eye: np.ndarray, u: np.ndarray, chain: np.ndarray,
           position: np.ndarray, tol: float) -> np.ndarray:
    """u with each sample whose ray misses its eye by more than tol searched again over the whole
    stretch its neighbours' contacts leave it (the previous sample's contact to the next one's; at a
    chain's end, its pass's end: the move into a pass that continues the last one has its midpoint
    first, and where the pass climbs a hoop's edge the rays of its first interval sweep past that
    midpoint twice, the later fit lifting the row after it 0.38 mm off its ray).
    The candidates' rays sweep an eye far out by millimetres between two candidates where the tangent
    turns fast, and a spline's small overshoot where a corner meets a flat turns the tangent back: the
    dynamic program may then prefer the flat, off by the sweep, and refine only looks beside it.
    The search reads the path where its tangent turns by at most REPAIR_TURN between reads (on a flat
    one read an interval: one tangent line), then golden-section between the best read's neighbours.
    Alternate samples of a chain are searched in turn, so every window stays between the contacts
    of its neighbours and the contacts stay nondecreasing; a search is kept only where it does better.
    A program with more misses than REPAIR_MAX_SHARE or REPAIR_MAX_SAMPLES is left as it is."""
    order = np.lexsort((position, chain))
    ch = chain[order]
    first = np.concatenate([[True], ch[1:] != ch[:-1]])
    last = np.concatenate([ch[1:] != ch[:-1], [True]])
    rank = np.arange(order.size) - np.maximum.accumulate(np.where(first, np.arange(order.size), 0))
    out = u.astype(float, copy=True)

    def miss(k, v):
        _, _, p, d = paths.point(v.ravel())
        return ray_distance(np.repeat(eye[k], v.size // k.size, axis=0), p, d).reshape(v.shape)

    _, _, p, d = paths.point(out[order])
    dist = ray_distance(eye[order], p, d)  # of each sample in chain order, kept as contacts move
    for sweep in range(REPAIR_ROUNDS):
        bad = dist > tol
        if not bad.any():
            break
        if sweep == 0 and np.count_nonzero(bad) > min(REPAIR_MAX_SHARE * bad.size, REPAIR_MAX_SAMPLES):
            return out
        # A neighbour within tol may still hold the window shut (its contact a little past the true
        # one, on a flat its ray fits nearly as well): it is searched again too.
        near = bad | np.concatenate([bad[1:] & ~last[:-1], [False]]) | np.concatenate([[False], bad[:-1] & ~first[1:]])
        todo = np.flatnonzero(near & (rank % 2 == sweep % 2))
        if not todo.size:
            continue
        k = order[todo]
        start, end = pass_span(paths, out[k])
        lo = np.where(first[todo], start, out[order[np.maximum(todo - 1, 0)]])
        hi = np.where(last[todo], end, out[order[np.minimum(todo + 1, order.size - 1)]])
        found, a, b = _best_read(paths, eye[k], lo, hi)
        fbest = miss(k, found[:, None])[:, 0]
        a, b = golden(lambda v: miss(k, v[:, None])[:, 0], a, b)
        mid = 0.5 * (a + b)
        fmid = miss(k, mid[:, None])[:, 0]
        found, got = np.where(fmid <= fbest, mid, found), np.minimum(fmid, fbest)
        better = got < dist[todo]
        out[k] = np.where(better, found, out[k])
        dist[todo] = np.where(better, got, dist[todo])
    return out

"""Bands on a circle (docs/math/05-winding.md): the covered length, longest gap, widest overlap, least and most bands
over a section of perimeter P, for one set of bands (union_stats) or many sets at once (union_stats_many,
the same numbers to round-off).

The overlap is a band's: the widest stretch of one band that bands before it along the perimeter also
cover (at most the band's own width), what a shop reads as bands lapping each other. The longest run
covered twice is not: where the planner adds circuits to close the gaps a bend spreads open, the
straight pieces are covered twice all round and that run is the whole perimeter.
"""

from __future__ import annotations

import numpy as np

EDGE_TOL = 1e-6  # mm, far below the 3 decimals the summary prints

Stats = tuple[float, float, float, int, int]


def union_stats(centres: np.ndarray, halves: np.ndarray, perimeter: float) -> Stats:
    """Covered length, longest gap, widest overlap, min and max band count on a circle of perimeter P.

    centres, halves : (k,) float, band centres and half-widths along the perimeter (mm).
    """
    if centres.size == 0:
        return 0.0, perimeter, 0.0, 0, 0
    lo = np.mod(centres - halves, perimeter)
    hi = lo + np.minimum(2.0 * halves, perimeter)
    # Events on [0, 2P): each band is counted on its own stretch and on its copy shifted by -P,
    # so that stretches wrapping past P are seen on [0, P).
    pos = np.concatenate([lo, hi, lo - perimeter, hi - perimeter, [0.0, perimeter]])
    delta = np.concatenate([np.ones_like(lo), -np.ones_like(hi), np.ones_like(lo), -np.ones_like(hi), [0, 0]])
    order = np.lexsort((-delta, pos))
    pos, delta = pos[order], delta[order]
    count = np.cumsum(delta)
    seg = np.diff(pos)
    mid = count[:-1]
    # A stretch shorter than EDGE_TOL is where two band edges meet (hoop turns abut exactly): whether
    # round-off puts a sliver of overlap or of gap there must not change the counts.
    inside = (pos[:-1] >= 0.0) & (pos[1:] <= perimeter) & (seg > EDGE_TOL)
    seg, mid = seg[inside], mid[inside]
    covered = float(np.sum(seg[mid > 0]))
    return covered, _longest_run(seg, mid == 0, perimeter), _overlap(lo, hi, perimeter), int(mid.min()), int(mid.max())


def _overlap(lo: np.ndarray, hi: np.ndarray, perimeter: float) -> float:
    """The widest stretch of a band (lo, hi (k,), lo in [0, P)) that the bands starting before it
    cover, the bands taken twice (and a turn on) so that one wrapping past P covers those after the
    seam; less than EDGE_TOL is none. A band at most P wide meets its own copy only end to end."""
    both_lo, both_hi = np.concatenate([lo, lo + perimeter]), np.concatenate([hi, hi + perimeter])
    order = np.argsort(both_lo, kind="stable")
    both_lo, both_hi = both_lo[order], both_hi[order]
    reach = np.maximum.accumulate(both_hi)
    shared = np.minimum(reach[:-1], both_hi[1:]) - both_lo[1:]
    widest = float(shared.max()) if shared.size else 0.0
    return widest if widest > EDGE_TOL else 0.0


def _longest_run(seg: np.ndarray, flag: np.ndarray, perimeter: float) -> float:
    """Longest stretch of consecutive flagged segments around the circle."""
    if not flag.any():
        return 0.0
    if flag.all():
        return perimeter
    # Rotate so the sequence starts on an unflagged segment: runs then never wrap.
    start = int(np.argmin(flag))
    seg, flag = np.roll(seg, -start), np.roll(flag, -start)
    run = np.where(flag, seg, 0.0)
    breaks = np.cumsum(~flag)
    return float(np.max(np.bincount(breaks, weights=run)))


def union_stats_many(centres: list[np.ndarray], halves: list[np.ndarray], perimeters: list[float]) -> list[Stats]:
    """union_stats of each set of bands (centres[j], halves[j] on perimeters[j]), all at once.

    The sets' events are sorted together with the set as the first key (a stable sort: each set's
    events keep union_stats' order), their counts come from one running sum (each set's deltas sum to
    zero), and each set's sums are over its own values in union_stats' order.
    """
    sizes = np.array([c.size for c in centres])
    full = np.nonzero(sizes)[0]
    out: list[Stats | None] = [None] * len(centres)
    for j in np.nonzero(sizes == 0)[0].tolist():
        out[j] = union_stats(centres[j], halves[j], perimeters[j])
    if full.size == 0:
        return out
    c = np.concatenate([centres[j] for j in full])
    h = np.concatenate([halves[j] for j in full])
    per = np.array([perimeters[j] for j in full], dtype=float)
    owner = np.repeat(np.arange(full.size), sizes[full])
    p = per[owner]
    lo = np.mod(c - h, p)
    hi = lo + np.minimum(2.0 * h, p)
    k, b = c.size, full.size
    pos = np.concatenate([lo, hi, lo - p, hi - p, np.zeros(b), per])
    delta = np.concatenate([np.ones(k), -np.ones(k), np.ones(k), -np.ones(k), np.zeros(b), np.zeros(b)])
    which = np.concatenate([owner, owner, owner, owner, np.arange(b), np.arange(b)])
    order = np.lexsort((-delta, pos, which))
    pos, delta, which = pos[order], delta[order], which[order]
    count = np.cumsum(delta)
    seg = np.diff(pos)
    mid = count[:-1]
    inside = (which[1:] == which[:-1]) & (pos[:-1] >= 0.0) & (pos[1:] <= per[which[1:]]) & (seg > EDGE_TOL)
    seg, mid, which = seg[inside], mid[inside], which[:-1][inside]
    n = np.bincount(which, minlength=b)
    if np.any(n == 0):  # a set without a stretch longer than EDGE_TOL: union_stats says what that means
        for j in full.tolist():
            out[j] = union_stats(centres[j], halves[j], perimeters[j])
        return out
    first = np.cumsum(n) - n
    covered_seg = seg[mid > 0]
    cuts = np.cumsum(np.bincount(which[mid > 0], minlength=b)).tolist()
    lows, highs = np.minimum.reduceat(mid, first), np.maximum.reduceat(mid, first)
    gaps = _longest_runs(seg, mid == 0, first, n, [perimeters[j] for j in full])
    bounds = np.cumsum(sizes[full])[:-1]
    overlaps = [_overlap(a, z, perimeters[j])
                for a, z, j in zip(np.split(lo, bounds), np.split(hi, bounds), full.tolist())]
    for i, j in enumerate(full.tolist()):
        covered = float(np.sum(covered_seg[(cuts[i - 1] if i else 0):cuts[i]]))
        out[j] = (covered, gaps[i], overlaps[i], int(lows[i]), int(highs[i]))
    return out


def _longest_runs(seg: np.ndarray, flag: np.ndarray, first: np.ndarray, n: np.ndarray,
                  perimeters: list[float]) -> list[float]:
    """_longest_run of each group seg[first_i : first_i + n_i] (n_i >= 1), all at once."""
    b = first.size
    any_ = np.logical_or.reduceat(flag, first)
    all_ = np.logical_and.reduceat(flag, first)
    out = [0.0 if not a else perimeters[i] if al else None for i, (a, al) in enumerate(zip(any_, all_))]
    mixed = np.nonzero(any_ & ~all_)[0]
    if mixed.size:
        # each group rotated to start on its first unflagged segment, as _longest_run does
        owner = np.repeat(np.arange(b), n)
        local = np.arange(seg.size) - first[owner]
        unflagged = np.where(~flag, local, n[owner])
        start = np.minimum.reduceat(unflagged, first)
        keep = np.isin(owner, mixed)
        at = first[owner] + (local + start[owner]) % n[owner]
        at = at[keep]
        fl = flag[at]
        run = np.where(fl, seg[at], 0.0)
        # the running count of unflagged segments numbers the runs; a group's first segment opens a new one
        breaks = np.cumsum(~fl)
        sums = np.bincount(breaks, weights=run)
        opens = breaks[np.cumsum(n[mixed]) - n[mixed]]
        best = np.maximum.reduceat(sums, opens)
        for i, v in zip(mixed.tolist(), best.tolist()):
            out[i] = float(v)
    return out

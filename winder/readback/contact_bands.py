"""The contacts of a long pass read from many samples (winder.app.simulate): the dynamic program of
winder.readback.contacts in a band along the pass.

A hoop pass is one pass of many turns: on an elliptic tube (a point every few degrees, 88 turns) 2,110
samples against 58,429 candidates, a table of 123 million entries for the whole pass; on a 2.5 m tube
5,713 against 157,958, 902 million. The contacts move forward with the samples, and a programmed point
lies on the ray of the contact it was written for, so each pass is first tracked sample by sample
(`track`): a sample's track is the first run of candidates whose rays fit its eye within the chord
tolerance, searched forward from the last sample's track in windows doubling from FIRST_REACH to
MAX_REACH, its best candidate then. A sample that fits nowhere within reach (a move's midpoint bowing
off by more than the tolerance; a program of another job) keeps the last track. The dynamic program
then runs over a band: for each sample from MARGIN candidates before its own track to MARGIN past
the next sample's (its contact is no later than its successor's). A hoop's neighbouring turn is a
band width (10 mm) off the eye, far past the tolerance: the track stays on the turn the program lays.
Memory: the samples times the widest band (back-pointers, int32), which the caller bounds.
"""

from __future__ import annotations

import numpy as np

from winder.readback.contacts import prefix_argmin, segment_miss, monotone_points

BAND_ABOVE = 8_000_000  # a pass's full table (samples x candidates) past this is matched in a band
FIRST_REACH = 64  # candidates searched forward from the last track first (a hoop: about 30 a sample)
MAX_REACH = 4_096  # and at most (41 rad of turning at TURN_STEP; the elliptic tubes' hoops: 75 at most)
MARGIN = 64  # candidates of the band before a sample's track and past the next sample's
COST_ENTRIES = 65_536  # band costs measured at once (samples x band): a few MB of temporaries


class TableTooLarge(Exception):
    """A pass's table past the caller's limit: samples, points (candidates a sample is matched
    against), entries (samples x points) of the worst pass."""

    def __init__(self, samples: int, points: int) -> None:
        super().__init__(f"{samples} x {points}")
        self.samples, self.points, self.entries = samples, points, samples * points


def contact_points(eye: np.ndarray, chain: np.ndarray, position: np.ndarray, pass_of: np.ndarray,
                   points: np.ndarray, dirs: np.ndarray, start: np.ndarray, tol: float, limit: int,
                   band_above: int = BAND_ABOVE) -> np.ndarray:
    """contacts.monotone_points for every chain (same arguments), those whose full table is past
    band_above matched in a band (module docstring); tol the chord tolerance. (n,) indices into points.
    Raises TableTooLarge where a band's table (samples x its widest band) would be past limit; a
    chain read whole is at most band_above entries, which the caller keeps below its limit."""
    order = np.lexsort((position, chain))
    _, begin, length = np.unique(chain[order], return_index=True, return_counts=True)
    of_chain = pass_of[order[begin]]
    size = start[of_chain + 1] - start[of_chain]
    long = length.astype(np.int64) * size > band_above
    out = np.zeros(eye.shape[0], dtype=int)
    short = ~np.repeat(long, length)[np.argsort(order)]  # the samples of chains read whole
    if short.any():
        out[short] = monotone_points(eye[short], chain[short], position[short], pass_of[short],
                                     points, dirs, start)
    bands = []
    for c in np.flatnonzero(long):
        seq = order[begin[c]:begin[c] + length[c]]
        hi = int(start[of_chain[c] + 1])
        first, width = band(eye[seq], points, dirs, int(start[of_chain[c]]), hi, tol)
        if seq.size * int(width.max()) > limit:  # measured before any table is allocated
            raise TableTooLarge(seq.size, int(width.max()))
        bands.append((seq, hi, first, width))
    for seq, hi, first, width in bands:
        out[seq] = banded_chain(eye[seq], points, dirs, hi, first, width)
    return out


def _miss(eye: np.ndarray, points: np.ndarray, dirs: np.ndarray, index: np.ndarray) -> np.ndarray:
    """(k, w) contacts.segment_miss of eyes (k, 3) against the candidates index (k, w + 1) (the last
    column only the next candidate of the one before it)."""
    p = np.moveaxis(points[index], -1, 0)
    d = np.moveaxis(dirs[index], -1, 0)
    return segment_miss(eye, p, d)[:, :-1]


def track(eye: np.ndarray, points: np.ndarray, dirs: np.ndarray, lo: int, hi: int, tol: float) -> np.ndarray:
    """(l,) each sample's track (module docstring) among the candidates lo to hi - 1 of its pass, for
    the eyes (l, 3) of one chain in order."""
    out = np.zeros(eye.shape[0], dtype=int)
    at = lo
    for k in range(eye.shape[0]):
        reach = FIRST_REACH
        while True:
            stop = min(at + reach, hi)
            index = np.minimum(np.arange(at, stop + 1), hi - 1)
            cost = _miss(eye[k][None], points, dirs, index[None])[0]
            fit = cost <= tol
            first = int(np.argmax(fit)) if fit.any() else -1
            # The run of fitting candidates from the first: it must end inside the window (or the pass).
            run_end = first + int(np.argmin(fit[first:])) if first >= 0 and not fit[first:].all() else stop - at
            if (first >= 0 and run_end < stop - at) or stop == hi or reach >= MAX_REACH:
                break
            reach *= 2
        if first >= 0:
            at += first + int(np.argmin(cost[first:run_end]))
        out[k] = at
    return out


def band(eye: np.ndarray, points: np.ndarray, dirs: np.ndarray, lo: int, hi: int,
         tol: float) -> tuple[np.ndarray, np.ndarray]:
    """(first (l,), width (l,)): each sample's band of candidates, first to first + width - 1, from
    MARGIN before its track to MARGIN past the next sample's, within lo to hi - 1 (both nondecreasing)."""
    g = track(eye, points, dirs, lo, hi, tol)
    first = np.maximum(g - MARGIN, lo)
    last = np.minimum(np.concatenate([g[1:], g[-1:]]) + MARGIN, hi - 1)
    return first, last - first + 1


def banded_chain(eye: np.ndarray, points: np.ndarray, dirs: np.ndarray, hi: int, first: np.ndarray,
                 width: np.ndarray) -> np.ndarray:
    """The dynamic program of contacts.monotone_group for one chain's eyes (l, 3) over its bands
    (first, width (l,), first nondecreasing; hi the end of the pass's candidates): the nondecreasing
    candidates, one in each band, with the least total ray distance. (l,) indices into points."""
    length, w = eye.shape[0], int(width.max())
    cols = np.arange(w)
    back = np.zeros((length, w), dtype=np.int32)
    rows = max(1, COST_ENTRIES // w)  # the band's costs are measured that many samples at once
    total = np.zeros(w)
    for k in range(length):
        if k % rows == 0:
            index = np.minimum(first[k:k + rows, None] + np.arange(w + 1), hi - 1)
            cost = np.where(cols < width[k:k + rows, None], _miss(eye[k:k + rows], points, dirs, index), np.inf)
        if k:
            low, arg = prefix_argmin(total[None])
            # Candidate first[k] + c has the previous band's c + shift before it (or all of that band).
            before = np.minimum(cols + (first[k] - first[k - 1]), w - 1)
            back[k] = arg[0, before]
            total = cost[k % rows] + low[0, before]
        else:
            total = cost[0]
    pick = np.zeros(length, dtype=int)
    pick[-1] = int(np.argmin(total))
    for k in range(length - 1, 0, -1):
        pick[k - 1] = back[k, pick[k]]
    return first + pick

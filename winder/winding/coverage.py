"""Coverage of a layer (docs/math/05-winding.md): where the bands cross stations along the winding region.

At a station t each pass crosses the section once; its band covers B / sin(beta) of the perimeter,
beta the angle between the fiber and the section curve (B / cos(alpha) on a surface of revolution),
centred on the crossing. The bands of each direction (forward, return, hoop) must each cover the
perimeter once for an even layer: gaps are uncovered stretches, overlaps doubly covered ones.
"""

from __future__ import annotations

import numpy as np

from winder.winding.bands import union_stats_many
from winder.winding.results import Coverage, FiberPass, PassKind
from winder.geometry.interp import hermite, interp_spline, knot_slopes_runs
from winder.geometry.sections import ArcMap
from winder.geometry.surface import SweepSurface
from winder.geometry.measure import row_norms


def crossings_many(surface: SweepSurface, arcs: ArcMap, passes: list[FiberPass], stations: np.ndarray,
                   band_width: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where the passes cross the stations, concatenated in pass order: (station index, perimeter
    fraction, band half-width / P).

    Cubic splines of s and theta against t (monotone along a pass) give the crossing and the local
    direction Phi_s s'(t) + Phi_theta theta'(t) to O(h^4), far below a band's width: one slope
    system for all the passes where each has four points or more, the surface (pointwise) in one
    evaluation. On a non-circular section the splines run in the perimeter fraction, not in theta
    (docs/math/12 12.2): a path straight in (t, f) bends in theta where a flat meets a corner, and a
    hoop's spline there read theta'(t) up to 2.4 % off at 72 points a turn, the band's width across the
    station with it (a 120 x 80 tube, corners 15: 0.989 covered where the planned turns close exactly).
    """
    if not passes:
        return np.zeros(0, dtype=int), np.zeros(0), np.zeros(0)
    along = None if arcs.identity else arcs
    batched = _spline_crossings_batched(passes, stations, along)
    if batched is None:
        parts = [_spline_crossings(p, stations, along) for p in passes]
        batched = tuple(np.concatenate(c) for c in zip(*parts))
    return _bands(surface, arcs, *_from_fraction(along, batched), band_width)


def _from_fraction(arcs: ArcMap | None, crossings: tuple[np.ndarray, ...]) -> tuple[np.ndarray, ...]:
    """Crossings (station index, s, 2 pi f, s'(t), 2 pi f'(t)) back to (.., theta, .., theta'(t));
    as they are where arcs is None (the splines ran in theta)."""
    if arcs is None:
        return crossings
    idx, s_x, a_x, ds, da = crossings
    th_x = arcs.theta(a_x / (2.0 * np.pi))
    return idx, s_x, th_x, ds, arcs.dtheta_dfrac(th_x) * da / (2.0 * np.pi)


def _angles(p: FiberPass, arcs: ArcMap | None) -> np.ndarray:
    """The coordinate a pass's splines run in around the section: theta, or on a non-circular
    section (arcs given) the perimeter fraction as an angle, 2 pi f (unwrapped as theta is)."""
    return p.theta if arcs is None else 2.0 * np.pi * arcs.fraction(p.theta)


def _spline_crossings(p: FiberPass, stations: np.ndarray, arcs: ArcMap | None = None) -> tuple[np.ndarray, ...]:
    """(station index, s, theta, s'(t), theta'(t)) where the pass crosses the stations (with arcs:
    2 pi f and its rate in place of theta's, _angles)."""
    forward = p.t[-1] > p.t[0]
    if p.t.size < 2:
        return np.zeros(0, dtype=int), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0)
    angle = _angles(p, arcs)
    t, s, th = (p.t, p.s, angle) if forward else (p.t[::-1], p.s[::-1], angle[::-1])
    idx = np.nonzero((stations >= t[0]) & (stations <= t[-1]))[0]
    if idx.size == 0:
        return idx, np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0)
    st = stations[idx]
    cs, ct = interp_spline(t, s), interp_spline(t, th)
    return idx, cs(st), ct(st), cs(st, 1), ct(st, 1)


def _spline_crossings_batched(passes: list[FiberPass], stations: np.ndarray,
                              arcs: ArcMap | None = None) -> tuple[np.ndarray, ...] | None:
    """_spline_crossings of every pass (in the coordinate of arcs), concatenated, from one tridiagonal solve for all the passes'
    splines (s and theta together); None where a pass needs the other kinds of spline (fewer than four
    points, or t not strictly monotone), which _spline_crossings then builds pass by pass.

    The passes' systems stand one after the other on the diagonal with zero couplings, so elimination
    never mixes them: each pass's spline is its CubicSpline, to round-off.
    """
    xs, ss, ths, sts, idxs, sizes, spans = [], [], [], [], [], [], []
    for p in passes:
        if p.t.size < 2:
            continue
        forward = p.t[-1] > p.t[0]
        angle = _angles(p, arcs)
        t, s, th = (p.t, p.s, angle) if forward else (p.t[::-1], p.s[::-1], angle[::-1])
        idx = np.nonzero((stations >= t[0]) & (stations <= t[-1]))[0]
        if idx.size == 0:
            continue
        if t.size < 4:
            return None
        xs.append(t)
        ss.append(s)
        ths.append(th)
        st = stations[idx]
        sts.append(st)
        idxs.append(idx)
        sizes.append(t.size)
        # Each station's interval in its own pass (the end pieces extrapolate).
        spans.append(np.minimum(np.maximum(np.searchsorted(t, st, side="right") - 1, 0), t.size - 2))
    if not xs:
        return (np.zeros(0, dtype=int),) + tuple(np.zeros(0) for _ in range(4))
    x, y = np.concatenate(xs), np.column_stack([np.concatenate(ss), np.concatenate(ths)])
    first = np.cumsum(sizes) - sizes
    rise = np.diff(x) > 0.0
    rise[first[1:] - 1] = True  # from one pass to the next
    if not np.all(rise):
        return None
    slopes = knot_slopes_runs(x, y, first, np.asarray(sizes))
    i = np.concatenate(spans) + np.repeat(first, [a.size for a in spans])
    q = np.concatenate(sts)
    val, der = hermite(x, y, slopes, i, q, 0), hermite(x, y, slopes, i, q, 1)
    return (np.concatenate(idxs), np.ascontiguousarray(val[:, 0]), np.ascontiguousarray(val[:, 1]),
            np.ascontiguousarray(der[:, 0]), np.ascontiguousarray(der[:, 1]))


def _bands(surface: SweepSurface, arcs: ArcMap, idx: np.ndarray, s_x: np.ndarray, th_x: np.ndarray,
           ds: np.ndarray, dth: np.ndarray, band_width: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(station index, perimeter fraction, band half-width / P) of crossings at (s, theta) heading
    (s', theta') per unit t."""
    if idx.size == 0:
        return idx, np.zeros(0), np.zeros(0)
    ev = surface.evaluate(s_x, th_x, order=1)
    d = ev.ps * ds[:, None] + ev.pt * dth[:, None]
    d /= row_norms(d)[:, None]
    e_t = ev.pt / row_norms(ev.pt)[:, None]
    sin_beta = row_norms(np.cross(d, e_t))
    perimeter = surface.perimeter(s_x)
    return idx, arcs.fraction(th_x), 0.5 * band_width / np.maximum(sin_beta, 1e-12) / perimeter


def layer_coverage(surface: SweepSurface, arcs: ArcMap, passes: list[FiberPass], band_width: float,
                   stations: np.ndarray) -> Coverage:
    """Coverage of the passes' bands at the stations (the DWELL passes lay no band in the region)."""
    # Each hoop traverse covers the region once on its own; helical passes cover it per direction.
    groups = [[p for p in passes if p.kind is kind] for kind in (PassKind.FORWARD, PassKind.RETURN)]
    groups += [[p] for p in passes if p.kind is PassKind.HOOP]
    groups = [g for g in groups if g]
    stations = np.asarray(stations, dtype=float)
    perimeters = surface.perimeter(surface.s_of_t(stations))
    # Each group's crossings by station (a stable sort: in pass order within a station).
    hits = []
    for g in groups:
        i, f, h = crossings_many(surface, arcs, g, stations, band_width)
        order = np.argsort(i, kind="stable")
        cuts = np.searchsorted(i[order], np.arange(1, len(stations)))
        hits.append((np.split(f[order], cuts), np.split(h[order], cuts)))
    # Per station: each group's bands, then all of them together (for the band counts); one batch.
    centres, halves, pers = [], [], []
    for k, perimeter in enumerate(perimeters):
        all_c, all_h = [], []
        for fracs, half in hits:
            cs, hs = fracs[k] * perimeter, half[k] * perimeter
            centres.append(cs)
            halves.append(hs)
            all_c.append(cs)
            all_h.append(hs)
        centres.append(np.concatenate(all_c))
        halves.append(np.concatenate(all_h))
        pers += [perimeter] * (len(hits) + 1)
    stats = iter(union_stats_many(centres, halves, pers))
    worst_cov, worst_gap, worst_overlap = 1.0, 0.0, 0.0
    min_layers, max_layers = None, 0
    for perimeter in perimeters:
        for _ in hits:
            covered, gap, overlap, _, _ = next(stats)
            worst_cov = min(worst_cov, covered / perimeter)
            worst_gap = max(worst_gap, gap)
            worst_overlap = max(worst_overlap, overlap)
        _, _, _, lo, hi = next(stats)
        min_layers = lo if min_layers is None else min(min_layers, lo)
        max_layers = max(max_layers, hi)
    return Coverage(stations, worst_cov, worst_gap, worst_overlap, int(min_layers or 0), int(max_layers))

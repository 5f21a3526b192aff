"""The smooth path of planned passes between their points (docs/math/02-energy.md): positions, tangents and arc
length at any fractional point index, for all passes of a plan in one batch. The motion program
densifies along it; `winder simulate` finds contact points on it."""

from __future__ import annotations

from functools import cached_property

import numpy as np

from winder.geometry.index_spline import knot_slopes
from winder.geometry.surface import SweepSurface
from winder.winding.results import FiberPass, PassKind
from winder.geometry.joints import joint_stations
from winder.geometry.sections import polar_arcs
from winder.geometry.measure import grid_groups, row_norms, tangent_coordinates

GAUSS_NODES = 5  # Gauss-Legendre nodes per interval for the arc length
SIDE_STEP = 1e-7  # how far into an interval (of its length) the surface is read for its end slopes
# An interval's end tangent may run at most this many times its chord along the chord (Fritsch and
# Carlson's bound for a monotone cubic Hermite): past it the piece overshoots its far node and comes
# back, a cusp where the planned points' spacing jumps (20 mm steps on a cylinder meeting 1.3 mm on a
# dome: the spline's slope at the junction is the average of both), and the eye, on the tangent, would
# swing from one side of the part to the other in one move.
# Three chords is the edge of that bound: with both ends at it the piece's speed vanishes halfway
# (p'(1/2) = 3/2 - (3 + 3)/4 = 0) and its direction there is round-off (a slip-held helical on a vessel,
# its points 31 mm apart on the cylinder and 0.45 mm near the equator: the tangent swung 180 deg inside
# one interval and the eye jumped 55 mm). Two keeps the speed at half the chord's at least.
SLOPE_LIMIT = 2.0
# Intervals whose stations and theta steps agree within ARC_COPY_MM (mm, rad) and end slopes (mm and
# rad per point index) within ARC_COPY_SLOPE share one arc-length quadrature (SmoothPaths.arc): their
# lengths then agree within about a picometre.
ARC_COPY_MM = 1e-9
ARC_COPY_SLOPE = 1e-12


def _along(surface: SweepSurface, s: np.ndarray, th: np.ndarray, direction: np.ndarray, ds: np.ndarray,
           dth: np.ndarray):
    """Parameter derivatives (s', theta') along the plan's directions (n, 3) at nodes (s, theta)
    (n,), with the spline's speed (ds, dth): pointwise, so all passes' nodes go in one call."""
    ev = surface.evaluate(s, th, order=1)
    ps, pt = ev.ps.T, ev.pt.T  # (3, n): the evaluation's own rows
    a, b = tangent_coordinates(ps, pt, direction.T)
    speed_plan = np.sqrt(_square3(ps * a + pt * b))
    speed_spline = np.sqrt(_square3(ps * ds + pt * dth))
    scale = speed_spline / np.where(speed_plan > 0, speed_plan, 1.0)
    # Where the index spline runs against the planned direction (it oscillates where the points'
    # spacing jumps: 20 mm steps meeting 1.3 mm ones), the plan's direction still holds: with the
    # spline's speed the curve would fold back on itself; the speed is bounded per interval after.
    ok = speed_plan > 0
    return np.where(ok, a * scale, ds), np.where(ok, b * scale, dth)


def _square3(v: np.ndarray) -> np.ndarray:
    """v0^2 + v1^2 + v2^2 of (3, n) rows: row_norms' sum (in order) before its root."""
    return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]


class SmoothPaths:
    """The planned passes' smooth paths, concatenated: pass j owns the global parameter range
    [offset_j, offset_j + n_j - 1] (u = the point index). (s, theta) is cubic Hermite between the
    points (on a non-circular section (s, f), f the perimeter fraction: docs/math/12 12.2), with
    derivatives along the plan's own fiber directions (FiberPass.direction, the smooth path's tangents,
    in each interval's own side of the surface), their size that of a cubic spline through the points:
    the curve passes through every planned point with the planned tangent there
    (C1 in space, also where the surface's metric jumps at a point), and O(h^4) close to the smooth path.
    A dwell is the cubic spline through its points on the parallel, and its direction (the free
    fiber's, swinging round an end that holds it) is interpolated between its points'."""

    def __init__(self, surface: SweepSurface, passes: list[FiberPass]) -> None:
        self.surface = surface
        sizes = np.array([len(fp.s) for fp in passes], dtype=int)
        count = int(sizes.sum())
        self.offset = np.cumsum(sizes) - sizes
        self.last = self.offset + np.maximum(sizes - 1, 0)
        self.s = np.concatenate([fp.s for fp in passes])
        self.th = np.concatenate([fp.theta for fp in passes])
        dwell = np.array([fp.kind is PassKind.DWELL for fp in passes], dtype=bool)
        self.free = np.repeat(dwell, sizes)
        self.d = (np.concatenate([np.asarray(fp.direction, dtype=float).reshape(n, 3) for fp, n in zip(passes, sizes)])
                  if passes else np.zeros((0, 3)))
        # The not-a-knot cubic spline's slopes against the point index (index_spline), the passes of one
        # size in one solve (a column each: the same slopes as pass by pass); a dwell's directions are
        # the free fiber's swing, not its parallel's tangent: the slopes stay.
        self.ds, self.dth = np.zeros(count), np.zeros(count)
        by_size: dict[int, list[int]] = {}
        for i, n in enumerate(sizes.tolist()):
            if n >= 2:
                by_size.setdefault(n, []).append(i)
        for n, group in by_size.items():
            y = np.empty((n, 2 * len(group)))  # the columns s, theta of each pass in turn
            y[:, 0::2] = np.array([passes[i].s for i in group], dtype=float).T
            y[:, 1::2] = np.array([passes[i].theta for i in group], dtype=float).T
            slopes = knot_slopes(y)
            rows = (self.offset[group][:, None] + np.arange(n)).T  # (n, passes of the group)
            self.ds[rows], self.dth[rows] = slopes[:, 0::2], slopes[:, 1::2]
        # Each interval takes its end slopes from the surface on its own side of a node: where the axis
        # changes curvature at a node (a line meeting an arc: geometry.joints), the metric jumps there, and
        # so do (s', theta') of a path whose 3D tangent is continuous. Only a node whose reading SIDE_STEP
        # into an interval lies on another piece of the guide than the node is read again on that side.
        on = np.flatnonzero(np.repeat((sizes >= 2) & ~dwell, sizes))
        if on.size:  # every pass's nodes in one call
            spline = self.ds[on], self.dth[on]
            self.ds[on], self.dth[on] = _along(surface, self.s[on], self.th[on], self.d[on], *spline)
        joints = joint_stations(surface) if on.size else np.empty(0)
        self.ds_in, self.dth_in = (self.ds.copy(), self.dth.copy()) if joints.size else (self.ds, self.dth)
        if joints.size:
            piece = np.searchsorted(joints, self.s[on], side="right")
            for side, ds, dth in ((1, self.ds, self.dth), (-1, self.ds_in, self.dth_in)):
                nb = np.clip(on + side, 0, self.s.size - 1)
                s = self.s[on] + SIDE_STEP * (self.s[nb] - self.s[on])
                other = np.flatnonzero(np.searchsorted(joints, s, side="right") != piece)
                if other.size:
                    k = on[other]
                    th = self.th[k] + SIDE_STEP * (self.th[nb[other]] - self.th[k])
                    ds[k], dth[k] = _along(surface, s[other], th, self.d[k], spline[0][other], spline[1][other])
        self._is_last = np.zeros(count + 1, dtype=bool)  # a table, not np.isin: _interval runs per lookup
        self._is_last[self.last] = True
        if on.size:
            self._limit_slopes(on)
        # On a non-circular section the pieces run in (s, f), f the perimeter fraction: the tangents of
        # theta's pieces are up to 0.2 deg off where a flat meets a corner (geometry.sections.polar_arcs).
        self._arcs = polar_arcs(surface.section)
        if self._arcs is not None:
            rate = self._arcs.dtheta_dfrac(self.th)
            self.f, self.df, self.df_in = self._arcs.fraction(self.th), self.dth / rate, self.dth_in / rate

    def _limit_slopes(self, on: np.ndarray) -> None:
        """Shorten (never turn) the end tangents of each interval of the nodes `on` whose component
        along the interval's chord exceeds SLOPE_LIMIT chords (SLOPE_LIMIT's comment): the curve keeps
        its planned points and tangent directions; only the speed may jump at a node, and there each
        interval reads its own end slopes (ds, dth at its start, ds_in, dth_in at its end)."""
        k = on[~self._is_last[on]]
        if k.size == 0:
            return
        ev = self.surface.evaluate(self.s[on], self.th[on], order=1)
        at = np.full(self.s.size, -1, dtype=int)
        at[on] = np.arange(on.size)
        a, b = at[k], at[k + 1]
        chord = ev.p[b] - ev.p[a]
        square = np.einsum("ij,ij->i", chord, chord)
        safe = np.where(square > 0.0, square, 1.0)
        out = ev.ps[a] * self.ds[k][:, None] + ev.pt[a] * self.dth[k][:, None]
        into = ev.ps[b] * self.ds_in[k + 1][:, None] + ev.pt[b] * self.dth_in[k + 1][:, None]
        ratio0 = np.where(square > 0.0, np.einsum("ij,ij->i", out, chord) / safe, 0.0)
        ratio1 = np.where(square > 0.0, np.einsum("ij,ij->i", into, chord) / safe, 0.0)
        f0 = np.where(ratio0 > SLOPE_LIMIT, SLOPE_LIMIT / np.where(ratio0 > 0.0, ratio0, 1.0), 1.0)
        f1 = np.where(ratio1 > SLOPE_LIMIT, SLOPE_LIMIT / np.where(ratio1 > 0.0, ratio1, 1.0), 1.0)
        if np.all(f0 == 1.0) and np.all(f1 == 1.0):
            return
        if self.ds_in is self.ds:  # a node's slope now differs by side
            self.ds_in, self.dth_in = self.ds.copy(), self.dth.copy()
        self.ds[k] *= f0
        self.dth[k] *= f0
        self.ds_in[k + 1] *= f1
        self.dth_in[k + 1] *= f1

    @cached_property
    def arc(self) -> np.ndarray:
        """(n,) arc length at the nodes, from each pass's first (Gauss-Legendre per node interval):
        worked out when first asked for (the exact fiber's points, `winder simulate`).

        On a surface of revolution the speed does not depend on theta: intervals whose Hermite data
        (end stations, theta step, end slopes) agree within ARC_COPY_MM / ARC_COPY_SLOPE (a helical
        layer's turned circuits) are integrated once."""
        x, w = np.polynomial.legendre.leggauss(GAUSS_NODES)
        k = np.arange(max(self.s.size - 1, 0))
        inside = ~self._is_last[k]  # no interval across passes
        first, group = np.arange(k.size), np.arange(k.size)
        if self.surface.is_revolution and k.size:
            keys = np.column_stack([self.s[k], self.s[k + 1], self.th[k + 1] - self.th[k], self.ds[k],
                                    self.ds_in[k + 1], self.dth[k], self.dth_in[k + 1]])
            first, group = grid_groups(keys, np.array([ARC_COPY_MM] * 3 + [ARC_COPY_SLOPE] * 4))
        u = (k[first, None] + 0.5 * (x + 1.0)).ravel()
        speed = (self.speed(u).reshape(-1, GAUSS_NODES) @ (0.5 * w))[group]
        return np.concatenate([[0.0], np.cumsum(np.where(inside, speed, 0.0))])

    def _interval(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(first node k, fraction h in [0, 1]) of each u's interval within its pass."""
        k = np.clip(np.floor(u).astype(int), 0, self.s.size - 2)
        k = np.where(self._is_last[k], k - 1, k)  # the last node of a pass ends its last interval
        k = np.maximum(k, 0)
        return k, u - k

    def _hermite(self, at: tuple[np.ndarray, np.ndarray]) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
        """((s, theta), (s', theta')) in the intervals at = (k, h), the node values looked up once for
        both; on a non-circular section the pieces run in (s, f) and are read back into theta."""
        k, h = at
        arcs = self._arcs
        second = (self.th, self.dth, self.dth_in) if arcs is None else (self.f, self.df, self.df_in)
        ends = [(v[k], dv[k], v[k + 1], dv_in[k + 1]) for v, dv, dv_in in ((self.s, self.ds, self.ds_in), second)]
        h2, h3 = h**2, h**3
        found = []
        for c in ((2 * h3 - 3 * h2 + 1, h3 - 2 * h2 + h, -2 * h3 + 3 * h2, h3 - h2),  # values
                  (6 * h2 - 6 * h, 3 * h2 - 4 * h + 1, -6 * h2 + 6 * h, 3 * h2 - 2 * h)):  # derivatives
            found.append([c[0] * v0 + c[1] * d0 + c[2] * v1 + c[3] * d1 for v0, d0, v1, d1 in ends])
        if arcs is not None:
            found[0][1] = arcs.theta(found[0][1])
            found[1][1] = found[1][1] * arcs.dtheta_dfrac(found[0][1])
        return tuple((a, b) for a, b in found)

    def speed(self, u: np.ndarray) -> np.ndarray:
        if self.s.size < 2:
            return np.zeros(np.shape(u))
        (s, th), (ds, dth) = self._hermite(self._interval(u))
        ev = self.surface.evaluate(s, th, order=1)
        return row_norms(ev.ps * ds[:, None] + ev.pt * dth[:, None])

    def point(self, u: np.ndarray):
        """(s, theta, p (n, 3), unit d (n, 3)) at global parameters u (n,)."""
        if self.s.size < 2:
            s, th = self.s[np.zeros(len(u), int)], self.th[np.zeros(len(u), int)]
            return s, th, self.surface.points(s, th), np.zeros((len(u), 3))
        k, h = self._interval(u)
        (s, th), (ds, dth) = self._hermite((k, h))
        ev = self.surface.evaluate(s, th, order=1)
        d = ev.ps * ds[:, None] + ev.pt * dth[:, None]
        free = self.free[k]
        if np.any(free):  # the free fiber's direction on a dwell: between its nodes' directions
            d = np.where(free[:, None], (1.0 - h)[:, None] * self.d[k] + h[:, None] * self.d[k + 1], d)
        # At a node the planned direction itself: the surface read exactly there may be the other side's.
        d = np.where((h == 0.0)[:, None], self.d[k], np.where((h == 1.0)[:, None], self.d[k + 1], d))
        n = row_norms(d)
        return s, th, ev.p, d / np.where(n > 0, n, 1.0)[:, None]

    def arc_at(self, u: np.ndarray) -> np.ndarray:
        """Arc length from the first node to u (within u's pass, the node table plus the rest)."""
        k = np.clip(np.floor(u).astype(int), 0, self.arc.size - 1)
        h = u - k
        x, w = np.polynomial.legendre.leggauss(GAUSS_NODES)
        uu = (k[:, None] + 0.5 * h[:, None] * (x + 1.0)).ravel()
        part = (self.speed(uu).reshape(-1, GAUSS_NODES) @ (0.5 * w)) * h
        return self.arc[k] + np.where(h > 0, part, 0.0)



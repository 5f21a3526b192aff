"""The smooth length across the joints of a guide curve made of pieces (docs/math/02-energy.md).

Where a path's line meets its arc the guide's curvature K jumps, and with it Phi_s = z1 (1 - R K.n) T:
the surface is C1 (its tangent plane is continuous) but its parametrization is not. A geodesic's
(s, theta) against the vertex index then has a kink at the joint (s' jumps, (1 - R K.n) s' and theta'
do not), which one cubic spline through all the vertices smears over its neighbours: an O(h) error
of the length and of its sign. So the smooth curve is built piece by piece: each segment of the
vertex chain that straddles a joint station s_j is cut where the chain crosses it, at the fractional
index i + phi and angle theta_j that cubics in s through the four vertices on the nearer side give
at s_j (O(h^4); the cubic passes through the nearer vertex, so a crossing next to it is consistent
with it); every piece is the not-a-knot cubic spline through its vertices and its crossings
(non-uniform end knots), kept on its own side of the joint, and integrated with the rule of the
unsplit path. A piece of fewer than four sites (a path's end just past a joint) also takes its
neighbour's velocity at the crossing, carried over the joint.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.geometry.curves import Line
from winder.geometry.index_spline import hermite_nodes
from winder.geometry.interp import knot_slopes_runs
from winder.geometry.surface import SweepSurface

JUMP_TOL = 1e-9  # a curvature jump below this share of the curve's largest curvature is no joint
PHI_MIN = 1e-3  # a crossing this close to a vertex (in segments) takes its place as a knot
TRANSFER_SPAN = 0.5  # segments a short piece must span to take its neighbour's slope
CUBIC_POINTS = 4  # vertices of the one-sided cubic that locates a crossing
ALONG_JOINT = 1e-9  # relative: a segment stepping across a joint by less (in s) runs along it
_NONE = np.empty(0)


def joint_stations(surface: SweepSurface) -> np.ndarray:
    """The internal stations s_j (sorted, (q,) float) where the surface's guide curve joins pieces
    of different curvature, so that Phi_s jumps; empty for one-piece curves. A point of station
    s >= s_j is evaluated on the piece after the joint, s < s_j on the one before (as Path does)."""
    curve = surface.curve
    if isinstance(curve, Line) or len(getattr(curve, "pieces", ())) < 2:
        return _NONE
    z = np.asarray(curve.starts[1:], dtype=float)
    before, after = curve.evaluate(np.nextafter(z, -np.inf)).d2, curve.evaluate(z).d2
    z = z[np.sqrt(np.sum((after - before) ** 2, axis=1)) > JUMP_TOL * curve.max_curvature()]
    if surface.is_axial_parameter or z.size == 0:
        return z
    # s(z) rounded: step to the least s whose station reaches the joint (z(s) increases).
    s = np.asarray(surface.s_of_t(z), dtype=float)
    for _ in range(8):
        low = surface.t_of_s(s) < z
        s = np.where(low, np.nextafter(s, np.inf), s)
        prev = np.nextafter(s, -np.inf)
        high = ~low & (surface.t_of_s(prev) >= z)
        s = np.where(high, prev, s)
        if not (low.any() or high.any()):
            break
    return s


@dataclasses.dataclass(frozen=True, eq=False)
class SplitNodes:
    """The quadrature of a path split at its joint crossings: its length is
    sum w |Phi_s s' + Phi_theta theta'| over the evaluated nodes (s, theta, du, w) and over the vertex
    knots (index, du, w) where the caller has the surface (Gauss-Lobatto with knots).

    s, theta, w : (q,) float; du : (2, q) the spline's slopes per unit of the node's weight.
    knot_index : (r,) int vertex indices; knot_du : (2, r); knot_w : (r,).
    """

    s: np.ndarray
    theta: np.ndarray
    du: np.ndarray
    w: np.ndarray
    knot_index: np.ndarray
    knot_du: np.ndarray
    knot_w: np.ndarray


def split_nodes(surface: SweepSurface, joints: np.ndarray, s: np.ndarray, theta: np.ndarray, fractions: np.ndarray,
                weights: np.ndarray, end_weight: float, with_knots: bool) -> SplitNodes | None:
    """The nodes of the piecewise smooth curve through the vertices (s, theta) (m,), or None where
    the chain crosses no joint (the one spline is right) or two joints in one segment (a piece of
    the guide shorter than a segment: the caller then keeps the one spline).

    fractions, weights : the rule's interior nodes (q,) on a segment [0, 1] and their weights;
    end_weight : the weight of each segment's two ends (0: the rule has no nodes there, Gauss).
    with_knots : the caller has Phi_s, Phi_theta at the vertices (Lobatto's vertex knots use them).
    """
    side = np.searchsorted(joints, s, side="right")
    cut = np.flatnonzero(side[1:] != side[:-1])
    if cut.size == 0 or np.any(np.abs(side[cut + 1] - side[cut]) > 1):
        return None
    # A chain along a joint station (a hoop on it) steps across it only by roundoff: no crossing.
    if np.any(np.abs(s[cut + 1] - s[cut]) <= ALONG_JOINT * (1.0 + np.abs(joints).max())):
        return None
    ends = np.concatenate([[-1], cut, [s.shape[0] - 1]])  # piece k: vertices ends[k] + 1 .. ends[k + 1]
    crossings = []
    for k, i in enumerate(cut):
        crossings.append(_crossing(s, theta, int(i), float(joints[min(side[i], side[i + 1])]), ends[k] + 1,
                                   ends[k + 2]))
    y = np.stack([s, theta], axis=1)
    index = np.arange(s.shape[0], dtype=float)
    pieces: list[tuple | None] = []
    for k in range(cut.size + 1):
        lo, hi = ends[k] + 1, ends[k + 1] + 1
        x, vals, vertex = index[lo:hi], y[lo:hi], np.arange(lo, hi)
        if k > 0:
            x, vals, vertex = _with_crossing(x, vals, vertex, crossings[k - 1], first=True)
        if k < cut.size:
            x, vals, vertex = _with_crossing(x, vals, vertex, crossings[k], first=False)
        p = side[lo]
        bounds = (joints[p - 1] if p > 0 else -np.inf, np.nextafter(joints[p], -np.inf) if p < joints.size else np.inf)
        pieces.append((x, vals, vertex, bounds) if x.size >= 2 else None)  # < 2: a path's end on the joint
    slopes = [piece_slopes(pc[0], pc[1]) if pc is not None and pc[0].size >= CUBIC_POINTS else None
              for pc in pieces]
    for k, pc in enumerate(pieces):
        if pc is not None and slopes[k] is None:
            slopes[k] = _short_slopes(surface, pieces, slopes, k)
    out = _Nodes(fractions, weights, end_weight, with_knots)
    for pc, dy in zip(pieces, slopes):
        if pc is not None:
            out.add_piece(*pc, dy)
    return out.result()


def _short_slopes(surface: SweepSurface, pieces: list, slopes: list, k: int) -> np.ndarray:
    """Knot slopes of a piece of two or three sites (a path's end, or two joints, within three
    segments of a joint). Its own sites carry a line or a parabola only; a long neighbour's slope at
    the shared crossing carries over the joint as the same 3D velocity (the chain is C1 in 3D; Phi_s
    jumps, Phi_theta does not), so the piece is the polynomial through its sites with that slope too."""
    x, vals, _, bounds = pieces[k]
    if x[-1] - x[0] < TRANSFER_SPAN:  # a sliver: its chord is accurate, a slope over it would not be
        return piece_slopes(x, vals)
    conds = []
    for end, nb, nb_end in ((0, k - 1, -1), (-1, k + 1, 0)):
        if 0 <= nb < len(pieces) and pieces[nb] is not None and slopes[nb] is not None:
            sc, tc = vals[end]
            ev = surface.evaluate(np.array([np.clip(sc, *pieces[nb][3]), np.clip(sc, *bounds)]), np.full(2, tc),
                                  order=1, with_point=False)
            v = ev.ps[0] * slopes[nb][nb_end][0] + ev.pt[0] * slopes[nb][nb_end][1]
            conds.append((x[end], np.linalg.lstsq(np.stack([ev.ps[1], ev.pt[1]], axis=1), v, rcond=None)[0]))
    if not conds:
        return piece_slopes(x, vals)
    # The polynomial through the values and slopes (degree sites + slopes - 1, at most 4), about x[0].
    deg = x.size + len(conds) - 1
    powers = np.arange(deg + 1)
    rows = [(x - x[0])[:, None] ** powers]
    rows += [np.where(powers > 0, powers * (xc - x[0]) ** np.maximum(powers - 1, 0), 0.0)[None] for xc, _ in conds]
    coef = np.linalg.solve(np.concatenate(rows), np.concatenate([vals] + [d[None] for _, d in conds]))
    der = powers[1:] * (x - x[0])[:, None] ** (powers[1:] - 1)
    return der @ coef[1:]


def _crossing(s: np.ndarray, theta: np.ndarray, i: int, s_j: float, first: int,
              last: int) -> tuple[float, float, float, np.ndarray]:
    """(x, s_j, theta_j, vertices): where the chain crosses s_j in segment [i, i + 1], x = i + phi,
    and the vertices that located it. The index and theta as cubics of s through CUBIC_POINTS
    vertices of the piece first..last on the side nearer the crossing (the other side where that
    has more): no root to find, and s_j lies within the segment's stations, so the extrapolation
    reaches at most one segment. A vertex on the joint is the crossing itself; where the stations
    do not run one way (the chain grazes the joint, where s' and so the kink vanish) the chord's
    crossing. A crossing is kept PHI_MIN from a vertex its cubic does not pass through."""
    for v in (i, i + 1):
        if s[v] == s_j:
            return float(v), s_j, float(theta[v]), np.array([v])
    phi = (s_j - s[i]) / (s[i + 1] - s[i])
    below = np.arange(max(first, i - CUBIC_POINTS + 1), i + 1)
    above = np.arange(i + 1, min(last, i + CUBIC_POINTS) + 1)
    near, far = (below, above) if phi < 0.5 else (above, below)
    use = near if near.size >= min(CUBIC_POINTS, far.size) else far
    ds = np.diff(s[use]) * np.sign(s[i + 1] - s[i])
    if use.size < 2 or np.any(ds <= 0.0):
        return i + phi, s_j, float(theta[i] + phi * (theta[i + 1] - theta[i])), np.empty(0, dtype=int)
    offset = s[use] - s_j
    x = i + float(np.polyfit(offset, use - float(i), use.size - 1)[-1])
    theta_j = float(np.polyfit(offset, theta[use], use.size - 1)[-1])
    lo = i + (0.0 if i in use else PHI_MIN)
    hi = i + 1 - (0.0 if i + 1 in use else PHI_MIN)
    return min(max(x, lo), hi), s_j, theta_j, use


def _with_crossing(x: np.ndarray, vals: np.ndarray, vertex: np.ndarray,
                   crossing: tuple[float, float, float, np.ndarray],
                   first: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A piece's sites with a crossing added at its start (first) or end. A vertex of the crossing's
    cubic within PHI_MIN of it gives its place up: the crossing lies on the cubic through it, so the
    spline loses nothing, and two sites that close would make its slopes roundoff over their gap."""
    xc, sc, tc, used = crossing
    keep = (np.abs(x - xc) >= PHI_MIN) | ~np.isin(vertex, used)
    x, vals, vertex = x[keep], vals[keep], vertex[keep]
    point = np.array([[sc, tc]])
    if first:
        return np.concatenate([[xc], x]), np.concatenate([point, vals]), np.concatenate([[-1], vertex])
    return np.concatenate([x, [xc]]), np.concatenate([vals, point]), np.concatenate([vertex, [-1]])


def piece_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """dy/dx at the sites x (p,) of the not-a-knot cubic through y (p, 2): (p, 2); the parabola
    through three sites and the line through two, as the uniform spline."""
    p = x.size
    if p >= 4:
        return knot_slopes_runs(x, y, np.array([0]), np.array([p]))
    d = (y[1:] - y[:-1]) / (x[1:] - x[:-1])[:, None]
    if p == 2:
        return np.concatenate([d, d])
    h0, h1 = x[1] - x[0], x[2] - x[1]
    curv = (d[1] - d[0]) / (h0 + h1)  # half the parabola's second derivative
    return np.stack([d[0] - curv * h0, d[0] + curv * h0, d[1] + curv * h1])


class _Nodes:
    """Collects the pieces' quadrature nodes (see split_nodes)."""

    def __init__(self, fractions: np.ndarray, weights: np.ndarray, end_weight: float, with_knots: bool):
        self.fractions, self.weights, self.end_weight, self.with_knots = fractions, weights, end_weight, with_knots
        self.nodes: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = []
        self.knots: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []

    def add_piece(self, x: np.ndarray, y: np.ndarray, vertex: np.ndarray, bounds: tuple[float, float],
                  dy: np.ndarray) -> None:
        """A piece: sites x (p,), values y (p, 2), the vertex index of each site (-1: a crossing),
        kept to its side of the joints (its stations clipped to bounds (lo, hi)), knot slopes dy (p, 2)."""
        width = x[1:] - x[:-1]
        u, du = hermite_nodes(y[:-1], dy[:-1] * width[:, None], y[1:], dy[1:] * width[:, None], self.fractions)
        self._add(u, du, np.tile(self.weights, width.size), bounds)
        if self.end_weight == 0.0:
            return
        # Each site is an end of the segments beside it: its weight per unit slope, by their widths.
        reach = np.zeros(x.size)
        reach[:-1] += width
        reach[1:] += width
        w = self.end_weight * reach
        own = vertex >= 0
        if self.with_knots:
            self.knots.append((vertex[own], dy[own].T, w[own]))
            own = ~own
        else:
            own = np.ones(x.size, dtype=bool)
        self._add(y[own], dy[own], w[own], bounds)

    def _add(self, u: np.ndarray, du: np.ndarray, w: np.ndarray, bounds: tuple[float, float]) -> None:
        self.nodes.append((np.clip(u[:, 0], *bounds), u[:, 1], du.T, w))

    def result(self) -> SplitNodes:
        s, th, du, w = (np.concatenate(c, axis=-1) for c in zip(*self.nodes))
        if self.knots:
            index, kdu, kw = (np.concatenate(c, axis=-1) for c in zip(*self.knots))
        else:
            index, kdu, kw = np.empty(0, dtype=int), np.empty((2, 0)), np.empty(0)
        return SplitNodes(s, th, du, w, index, kdu, kw)

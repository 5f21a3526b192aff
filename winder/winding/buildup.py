"""A layer's thickness from the bands actually laid, and the mandrel grown by it (docs/math/08-laminate-edges.md).

The station range is cut into cells (uniform within each smooth piece: a vessel's first dome,
cylinder and end dome, so no cell straddles an equator). Each pass puts the composite volume of its
fiber length inside a cell into that cell: with the pass's station S(i) and length l(i) as C2
splines over the vertex index, a cell [e0, e1] holds a (l(i(e1)) - l(i(e0))) exactly (to spline
accuracy). That is the fiber-count law wherever the fiber crosses the cell, finite at a turnaround,
and conserves the volume by construction. A dwell lays its band around the section it stays at:
its volume is spread over one band width of stations there. At a vessel turnaround the volume is
spread over two band widths by the band-spread cubic (laminate.band_spread; docs/math/08 8.6). Mean thickness per station:
V' / A', A'(s) the surface area per unit station (a periodic quadrature in theta).

The shape the next layer winds on (smoothed, grown) is growth.py's.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

import numpy as np

from winder.geometry.interp import interp_spline
from winder.geometry.surface import SweepSurface
from winder.geometry.vessel import VesselMeridian
from winder.winding.laminate import band_spread
from winder.winding.results import FiberPass, PassKind
from winder.geometry.measure import GAUSS_T, GAUSS_W, row_norms

if TYPE_CHECKING:
    from scipy.interpolate import BSpline

CELLS_PER_BAND = 16  # station cells per band width (the law's cell averages, the zone edges)
MAX_CELLS = 4000  # over the whole station range
AREA_THETA_NODES = 96  # periodic rule for A'(s) on non-circular sections
SPACING_JUMP = 4.0  # neighbouring sample spacings further apart than this: a monotone interpolant
NEWTON_STEPS = 4  # index of a station along a pass (from a linear first guess; quadratic)


@dataclasses.dataclass(frozen=True, eq=False)
class StationCells:
    """Cells along the station range: edges (k + 1,) and centres (k,) of the internal station s,
    and the pieces (index ranges into the cells) of the smooth parts: one for open mandrels, three
    (first dome, cylinder, end dome) for vessels."""

    edges: np.ndarray
    centres: np.ndarray
    pieces: tuple[tuple[int, int], ...]

    @property
    def widths(self) -> np.ndarray:
        return np.diff(self.edges)


def station_cells(surface: SweepSurface, band_width: float) -> StationCells:
    """Cells about band_width / CELLS_PER_BAND wide, uniform within each smooth piece."""
    prof = surface.profile
    bounds = [0.0, surface.length]
    if isinstance(prof, VesselMeridian):
        a, b = prof.equator_s
        bounds = [0.0, a, b, surface.length] if b > a else [0.0, a, surface.length]
    step = max(band_width / CELLS_PER_BAND, surface.length / MAX_CELLS)
    edges, pieces, start = [np.array([0.0])], [], 0
    for lo, hi in zip(bounds[:-1], bounds[1:]):
        n = max(2, int(np.ceil((hi - lo) / step)))
        edges.append(np.linspace(lo, hi, n + 1)[1:])
        pieces.append((start, start + n))
        start += n
    e = np.concatenate(edges)
    return StationCells(e, 0.5 * (e[1:] + e[:-1]), tuple(pieces))


def index_of(spline: BSpline, s_vert: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Fractional vertex index where the pass's station spline reaches each target (s monotone)."""
    idx = np.arange(s_vert.size, dtype=float)
    rising = s_vert[-1] >= s_vert[0]
    sv, iv = (s_vert, idx) if rising else (s_vert[::-1], idx[::-1])
    x = np.interp(targets, sv, iv)
    d1 = spline.derivative()
    for _ in range(NEWTON_STEPS):
        slope = d1(x)
        ok = np.abs(slope) > 1e-12 * (abs(s_vert[-1] - s_vert[0]) / s_vert.size + 1e-300)
        x = np.where(ok, x - (spline(x) - targets) / np.where(ok, slope, 1.0), x)
        x = np.clip(x, 0.0, idx[-1])
    return x


def _arc_lengths(surface: SweepSurface, s_spline, th_spline, m: int) -> np.ndarray:
    """Length along the smooth curve through a pass's m vertices (the curve its length is measured
    on) at each vertex, (m,) float. The polyline's chords fall short most where the mandrel curves
    most: scaled to the pass's length as a whole, they moved a dome's shortfall onto the cylinder
    (0.08 % too thick there on a 33-point vessel pass)."""
    u = (np.arange(m - 1, dtype=float)[:, None] + GAUSS_T[None, :]).ravel()
    ev = surface.evaluate(s_spline(u), th_spline(u), order=1)
    speed = row_norms(ev.ps * s_spline(u, 1)[:, None] + ev.pt * th_spline(u, 1)[:, None])
    return np.concatenate([[0.0], np.cumsum(0.5 * speed.reshape(m - 1, -1) @ GAUSS_W)])


def _station_fit(s: np.ndarray):
    """How a pass's samples are interpolated against their index: the not-a-knot cubic, or where the
    samples' spacing jumps by more than SPACING_JUMP between neighbours (a friction-held pass: dense
    dome legs meeting a sparse cylinder) the monotone cubic (PCHIP), which does not overshoot there
    (the cubic did by a cell's width and put the volume of 14 mm of laminate in the equator's cell)."""
    ds = np.abs(np.diff(s))
    ratio = ds[1:] / np.maximum(ds[:-1], 1e-300)
    if ds.size < 2 or (np.max(ratio) <= SPACING_JUMP and np.min(ratio) >= 1.0 / SPACING_JUMP):
        return interp_spline
    from scipy.interpolate import PchipInterpolator  # noqa: PLC0415 - friction-held passes only

    return PchipInterpolator


def pass_volumes(cells: StationCells, p: FiberPass, area: float, surface: SweepSurface) -> np.ndarray:
    """Composite volume (mm^3) of one pass in each cell, (k,) float."""
    out = np.zeros(cells.centres.size)
    if p.kind is PassKind.DWELL or np.ptp(p.s) <= 0.0:
        return out
    idx = np.arange(p.s.size, dtype=float)
    fit = _station_fit(p.s)
    s_spline = fit(idx, p.s)
    ell = _arc_lengths(surface, s_spline, fit(idx, p.theta), p.s.size)
    ell *= p.length / ell[-1] if ell[-1] > 0.0 else 0.0  # the volume of the pass's own length, kept
    l_spline = fit(idx, ell)
    lo, hi = min(p.s[0], p.s[-1]), max(p.s[0], p.s[-1])
    e = np.clip(cells.edges, lo, hi)
    at = l_spline(index_of(s_spline, p.s, e))
    return area * np.abs(np.diff(at))


def ring_volumes(cells: StationCells, s0: float, volume: float, band_width: float) -> np.ndarray:
    """A band laid around one section (a dwell): volume spread over [s0 - B/2, s0 + B/2] (clipped)."""
    lo = max(s0 - 0.5 * band_width, cells.edges[0])
    hi = min(s0 + 0.5 * band_width, cells.edges[-1])
    frac = np.clip(np.minimum(cells.edges[1:], hi) - np.maximum(cells.edges[:-1], lo), 0.0, None)
    return volume * frac / frac.sum()


def layer_density(surface: SweepSurface, cells: StationCells, passes: tuple[FiberPass, ...], area: float,
                  band_width: float, turnarounds: tuple[float, ...] = (), dwells: bool = True,
                  seen: dict[tuple[bytes, float], np.ndarray] | None = None) -> np.ndarray:
    """V'(s) (mm^3 per mm of station) of a layer's passes in each cell, (k,) float.

    turnarounds : stations where the passes turn tangent to a parallel (vessel domes); the volume
    within B/2 of each is spread over the band's width there. dwells : whether the rings the dwells
    lay at an open mandrel's ends count. surface : the mandrel the passes lie on. seen : the passes'
    volumes by (stations, length), to share between the calls of one layer and these cells.
    """
    vol = np.zeros(cells.centres.size)
    seen = {} if seen is None else seen
    for p in passes:
        if p.kind is PassKind.DWELL:
            if dwells:
                vol += ring_volumes(cells, float(p.s[0]), area * p.length, band_width)
            continue
        # circuits on a surface of revolution are rotated copies: the same stations, the same volumes
        key = (p.s.tobytes(), p.length)
        if key not in seen:
            seen[key] = pass_volumes(cells, p, area, surface)
        vol += seen[key]
    density = vol / cells.widths
    r_of_s = None if surface.profile is None else (lambda x: surface.profile.evaluate(x).r)
    for s_c in turnarounds:
        k = int(np.clip(np.searchsorted(cells.edges, s_c) - 1, 0, cells.centres.size - 1))
        i0, i1 = next((a, b) for a, b in cells.pieces if a <= k < b)
        s, d, w = cells.centres[i0:i1], density[i0:i1], cells.widths[i0:i1]
        # the fiber lies on the equator's side: the larger s on the first dome, the smaller on the end one
        toward = 1.0 if (i0, i1) == cells.pieces[0] else -1.0
        density[i0:i1] = band_spread(s, w, d, s_c, band_width, toward, r_of_s)
    return density


def area_rate(surface: SweepSurface, s: np.ndarray) -> np.ndarray:
    """A'(s) = integral |Phi_s x Phi_theta| dtheta (mm^2 per mm of station), (k,) float."""
    s = np.asarray(s, dtype=float)
    if surface.is_revolution:
        ev = surface.evaluate(s, np.zeros_like(s), order=1)
        return 2.0 * np.pi * row_norms(np.cross(ev.ps, ev.pt))
    th = (np.arange(AREA_THETA_NODES) + 0.5) * 2.0 * np.pi / AREA_THETA_NODES
    ss, tt = np.repeat(s, th.size), np.tile(th, s.size)
    ev = surface.evaluate(ss, tt, order=1)
    da = row_norms(np.cross(ev.ps, ev.pt)).reshape(s.size, th.size)
    return da.sum(axis=1) * 2.0 * np.pi / AREA_THETA_NODES


def share_around(surface: SweepSurface, passes: tuple[FiberPass, ...], band_width: float, s: np.ndarray,
                 theta: np.ndarray) -> np.ndarray:
    """How a layer's thickness varies around each section: (k, J) float, the band count over each
    angle theta (J,) at stations s (k,), divided by its mean around the section (arc-length
    weighted), so that thickness(s, theta) = mean thickness(s) x share. 1 where no band crosses.

    A pass crossing a station covers B / sin(beta) of the section (beta between fiber and section
    curve), B / (2 sin(beta) |Phi_theta|) of angle on either side of its crossing (docs/math/05-winding.md).
    """
    s, theta = np.asarray(s, float), np.asarray(theta, float)
    count = np.zeros((s.size, theta.size))
    for p in passes:
        if p.kind is PassKind.DWELL or np.ptp(p.s) <= 0.0:
            continue
        lo, hi = min(p.s[0], p.s[-1]), max(p.s[0], p.s[-1])
        k = np.nonzero((s >= lo) & (s <= hi))[0]
        if k.size == 0:
            continue
        idx = np.arange(p.s.size, dtype=float)
        s_spline, th_spline = interp_spline(idx, p.s), interp_spline(idx, p.theta)
        at = index_of(s_spline, p.s, s[k])
        th_x = th_spline(at)
        ev = surface.evaluate(s[k], th_x, order=1)
        d = ev.ps * s_spline(at, 1)[:, None] + ev.pt * th_spline(at, 1)[:, None]
        d /= row_norms(d)[:, None]
        speed_th = row_norms(ev.pt)
        sin_beta = row_norms(np.cross(d, ev.pt / speed_th[:, None]))
        half = 0.5 * band_width / (np.maximum(sin_beta, 1e-6) * speed_th)
        off = np.angle(np.exp(1j * (theta[None, :] - th_x[:, None])))  # (-pi, pi]
        count[k] += np.abs(off) <= np.minimum(half, np.pi)[:, None]
    ss, tt = np.repeat(s, theta.size), np.tile(theta, s.size)
    weight = row_norms(surface.evaluate(ss, tt, order=1).pt).reshape(count.shape)
    mean = np.sum(count * weight, axis=1) / np.sum(weight, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(mean[:, None] > 0.0, count / mean[:, None], 1.0)

"""The shape the next layer winds on: a layer's thickness made smooth and grown onto the mandrel.

A band cannot follow a shape narrower than itself, and the next layer's geodesics need a smooth (C2)
mandrel, so the grown mandrel takes the mean thickness smoothed over half a band width
(laminate.smooth_density, on V' so the volume is kept). Three things change only this shape, never a
reported thickness:
- open mandrels: the thickness continues at its end values beyond the fibered stretch (the next
  layer winds inside the same region; a laminate edge there would make hoops slip on the ramp);
- vessels: each dome is smoothed on its own (mirrored at its equator, matched to the cylinder's
  constant thickness there by a Gaussian taper one band wide) so the grown meridian stays C1 at the
  equators; a laminate edge falling toward the pole faster than the dome can carry is filled
  (_limit_pole_slope), and the whole stays below the bare dome's boss cone (BossCone, docs/math/08
  8.7: the frame keeps the opening plane, so a pile-up taller than the dome rises there is lowered,
  blended in by a soft minimum); over a concave stretch tighter than the laminate (an isotensoid's end hook)
  the growth is held below the radius of curvature, so the offset does not fold (the next layer
  bridges such a stretch anyway).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.geometry.offset import FOLD_MARGIN, grow_surface
from winder.geometry.surface import SweepSurface
from winder.geometry.vessel import VesselMeridian
from winder.winding.buildup import StationCells, area_rate
from winder.winding.laminate import smooth_density

SOFT_MIN_SHARE = 0.25  # band widths over which the cap and the thickness are blended (no crease)
BOSS_CONE_SHARE = 0.5  # share of the bare dome's angle to the radial at its opening the boss cone keeps
CHORD_SAMPLES = 4001  # stations of a bare dome where the boss cone must pass above it
POLE_SLOPE_SHARE = 0.7  # share of the meridian's angle to the radial a falling laminate edge may use


@dataclasses.dataclass(frozen=True)
class BossCone:
    """The cone through a bare dome's polar opening circle (r0 in its opening plane, H = depth) that
    every grown dome stays below (docs/math/08-laminate-edges.md 8.7): H <= depth - slope (r - r0).

    Fixed from the bare mandrel, so the limit does not shrink layer by layer."""

    r0: float
    depth: float
    slope: float

    @classmethod
    def of(cls, dome) -> BossCone:
        ev = dome.evaluate(np.array([dome.length]))
        angle = float(np.arctan2(abs(ev.h1[0]), abs(ev.r1[0])))  # the meridian's angle to the radial
        r0, depth = float(dome.end_radius), float(dome.depth)
        # Above the whole bare dome: an isotensoid turns axial at its opening (angle 90 deg) but is
        # nearly radial just outside it, where a cone of half that angle would cut it (docs/math 8.7).
        bare = dome.evaluate(np.linspace(0.0, dome.length, CHORD_SAMPLES)[:-1])
        apart = bare.r - r0
        chords = (depth - bare.h[apart > 0.0]) / apart[apart > 0.0]
        flattest = float(chords.min()) if chords.size else np.inf
        return cls(r0, depth, min(float(np.tan(BOSS_CONE_SHARE * angle)), BOSS_CONE_SHARE * flattest))

    def cap(self, dome, sigma: np.ndarray) -> np.ndarray:
        """The largest growth along the normal at sigma ((m,) float) that keeps the grown point below
        the cone (0 where the dome is on or above it already)."""
        ev = dome.evaluate(sigma)
        room = self.depth - ev.h - self.slope * (ev.r - self.r0)
        rate = -ev.r1 + self.slope * ev.h1  # d(H + slope r) / dg along the outward normal (-r1, h1)
        with np.errstate(divide="ignore", invalid="ignore"):
            out = np.where(rate > 0.0, room / rate, np.inf)
        return np.clip(out, 0.0, None)


def boss_cones(surface: SweepSurface) -> tuple[BossCone, BossCone] | None:
    """The boss cones of a bare vessel's two domes (None for other mandrels)."""
    prof = surface.profile
    if not isinstance(prof, VesselMeridian):
        return None
    return BossCone.of(prof.dome), BossCone.of(prof.end_dome)


def smooth_thickness(surface: SweepSurface, cells: StationCells, density: np.ndarray,
                     band_width: float, cones: tuple[BossCone, BossCone] | None = None) -> np.ndarray:
    """The smooth mean thickness (mm) the next layer winds on, per cell centre, (k,) float. cones: the
    bare vessel's boss cones (boss_cones), which the grown domes stay below."""
    rate = area_rate(surface, cells.centres)
    if not isinstance(surface.profile, VesselMeridian) or len(cells.pieces) < 2:
        return _open(cells.centres, density, rate, band_width)
    out = density / rate
    pieces = cells.pieces
    cyl = pieces[1] if len(pieces) == 3 else None
    if cyl is not None:
        t_cyl = float(np.mean(out[cyl[0]:cyl[1]]))
        out[cyl[0]:cyl[1]] = t_cyl
    for j, (i0, i1) in ((0, pieces[0]), (1, pieces[-1])):
        mirror = (False, True) if j == 0 else (True, False)
        s = cells.centres[i0:i1]
        sm = smooth_density(s, density[i0:i1], 0.5 * band_width, mirror) / rate[i0:i1]
        sm = _limit_pole_slope(surface, s, sm, -1.0 if j == 0 else 1.0, 0.5 * band_width)
        cap = np.full(s.size, np.inf)
        if cones is not None:
            dome = (surface.profile.dome, surface.profile.end_dome)[j]
            sigma = cells.edges[i1] - s if j == 0 else s - cells.edges[i0]
            cap = cones[j].cap(dome, sigma)
        sm = _below_concave_radius(surface, s, _soft_min(sm, cap, SOFT_MIN_SHARE * band_width))
        sm = _below_concave_radius(surface, s, smooth_density(s, sm, 0.5 * band_width, mirror))
        sm = _below_concave_radius(surface, s, _soft_min(sm, cap, SOFT_MIN_SHARE * band_width))
        if cyl is None:
            out[i0:i1] = sm
            continue
        eq = cells.edges[i1] if j == 0 else cells.edges[i0]
        at_eq = sm[-1] if j == 0 else sm[0]
        dist = np.abs(cells.centres[i0:i1] - eq)
        out[i0:i1] = sm + (t_cyl - at_eq) * np.exp(-(dist / band_width) ** 2)
    return out


def _soft_min(a: np.ndarray, b: np.ndarray, eps: float) -> np.ndarray:
    """-eps log(exp(-a / eps) + exp(-b / eps)): below both, within eps log 2 of the lesser, smooth where
    they cross (a min would leave a crease the next offset folds over); b may be inf."""
    lo = np.minimum(a, b)
    with np.errstate(invalid="ignore"):
        gap = np.where(np.isfinite(b), np.abs(a - b), np.inf)
    return np.clip(lo - eps * np.log1p(np.exp(-gap / eps)), 0.0, None)


def _open(s: np.ndarray, density: np.ndarray, rate: np.ndarray, band_width: float) -> np.ndarray:
    """Open mandrels: smooth over the fibered stretch (mirrored at its ends), constant beyond."""
    laid = np.nonzero(density > 0.0)[0]
    out = np.zeros_like(density)
    if laid.size == 0:
        return out
    i0, i1 = int(laid[0]), int(laid[-1]) + 1
    out[i0:i1] = smooth_density(s[i0:i1], density[i0:i1], 0.5 * band_width, (True, True)) / rate[i0:i1]
    out[:i0], out[i1:] = out[i0], out[i1 - 1]
    return out


def _below_concave_radius(surface: SweepSurface, s: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Hold the growth below the meridian's concave radius of curvature (with twice the offset's
    fold margin), so the normal offset stays regular."""
    ev = surface.profile.evaluate(s)
    k = ev.z1 * ev.r2 - ev.r1 * ev.z2  # > 0 where the meridian is concave (centre outside)
    with np.errstate(divide="ignore"):
        cap = np.where(k > 0.0, (1.0 - 2.0 * FOLD_MARGIN) / k, np.inf)
    return np.minimum(t, cap)


def _limit_pole_slope(surface: SweepSurface, s: np.ndarray, t: np.ndarray, toward_pole: float,
                      window: float) -> np.ndarray:
    """Raise the thickness where it falls toward the pole faster than the dome can carry it.

    Where a layer piles up at its turnaround its edge drops toward the polar opening; offset along
    the normal of a steep dome, that edge would turn the grown meridian back toward the equator (no
    longer a vessel). The next layer cannot follow such an edge anyway (its fiber bridges it), so the
    grown shape fills it: the thickness may fall toward the pole at most at the slope that uses
    POLE_SLOPE_SHARE of the angle the dome's meridian has left to the radial direction (the least
    dilation of t by a cone of that slope). Filled all the way, a pile-up next to a small opening
    would reach past the opening's plane and hide it (the next layer could not turn around there):
    the bare dome's boss cone (BossCone) holds it down. The slope limit at each station is the least
    over +-window around it, so that the smoothing after it (that half-width), which averages slopes
    there, keeps within it. Only the shape the next layer winds on changes, never a reported
    thickness.
    """
    ev = surface.profile.evaluate(s)
    left = 0.5 * np.pi - np.arctan2(np.abs(ev.r1), np.abs(ev.z1))  # meridian angle to the radial
    slope = np.tan(np.clip(POLE_SLOPE_SHARE * left, 0.0, None))
    k = int(np.ceil(window / max(s[1] - s[0], 1e-12))) if s.size > 1 else 0
    if k:
        padded = np.pad(slope, k, mode="edge")
        slope = np.lib.stride_tricks.sliding_window_view(padded, 2 * k + 1).min(axis=1)
    order = np.argsort(toward_pole * s)  # from the equator toward the pole
    x, y, m = s[order], t[order], slope[order]
    run = np.concatenate([[0.0], np.cumsum(0.5 * (m[1:] + m[:-1]) * np.abs(np.diff(x)))])
    out = np.empty_like(t)
    out[order] = np.maximum.accumulate(y + run) - run
    return out


def grown(surface: SweepSurface, cells: StationCells, thickness: np.ndarray) -> SweepSurface:
    """The mandrel grown by a smooth mean thickness given at the cell centres ((k,) float), extended
    to the range ends so the growth covers [0, length]: by its end values on open mandrels, by zero
    at a vessel's polar openings (the laminate ends at the boss; _limit_pole_slope brought it down
    there already)."""
    vessel = isinstance(surface.profile, VesselMeridian)
    ends = (0.0, 0.0) if vessel else (thickness[0], thickness[-1])
    s = np.concatenate([[cells.edges[0]], cells.centres, [cells.edges[-1]]])
    h = np.concatenate([[ends[0]], thickness, [ends[1]]])
    return grow_surface(surface, s, h)

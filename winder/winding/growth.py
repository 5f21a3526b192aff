"""The shape the next layer winds on: a layer's thickness made smooth and grown onto the mandrel.

A band cannot follow a shape narrower than itself, and the next layer's geodesics need a smooth (C2)
mandrel, so the grown mandrel takes the mean thickness smoothed over half a band width
(laminate.smooth_density, on V' so the volume is kept). Three things change only this shape, never a
reported thickness:
- open mandrels: the thickness continues at its end values beyond the fibered stretch (the next
  layer winds inside the same region; a laminate edge there would make hoops slip on the ramp);
- vessels: each dome is smoothed on its own (mirrored at its equator, matched to the cylinder's
  constant thickness there by a quintic fade EQUATOR_BLEND_BANDS bands long) so the grown meridian stays C1 at the
  equators; a laminate edge falling toward the pole faster than the dome can carry is filled
  (_limit_pole_slope), and a pile-up next to a boss stands as laid, rising past the opening's plane
  (docs/math/17 17.8: the grown vessel's frame follows); over a concave stretch tighter than the
  laminate (an isotensoid's end hook) the growth is held below the radius of curvature, so the offset
  does not fold (the next layer bridges such a stretch anyway).
"""

from __future__ import annotations

import numpy as np

from winder.geometry.offset import FOLD_MARGIN, grow_surface
from winder.geometry.surface import SweepSurface
from winder.geometry.vessel import VesselMeridian
from winder.winding.buildup import StationCells, area_rate
from winder.winding.laminate import smooth_density

POLE_SLOPE_SHARE = 0.7  # share of the meridian's angle to the radial a falling laminate edge may use
# Band widths of dome over which the cylinder's thickness (its hoops' above all, which end on the cylinder)
# fades into the dome's: the grown meridian meets the grown cylinder tangentially, and layer on layer
# the fade's curvature (at most 5.8 times its height over its length squared) adds up at the same place.
EQUATOR_BLEND_BANDS = 4.0


def smooth_thickness(surface: SweepSurface, cells: StationCells, density: np.ndarray,
                     band_width: float) -> np.ndarray:
    """The smooth mean thickness (mm) the next layer winds on, per cell centre, (k,) float."""
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
        sm = _below_concave_radius(surface, s, smooth_density(s, sm, 0.5 * band_width, mirror))
        if cyl is None:
            out[i0:i1] = sm
            continue
        eq = cells.edges[i1] if j == 0 else cells.edges[i0]
        at_eq = sm[-1] if j == 0 else sm[0]
        dist = np.abs(cells.centres[i0:i1] - eq)
        span = min(EQUATOR_BLEND_BANDS * band_width, 0.5 * (cells.edges[i1] - cells.edges[i0]))
        out[i0:i1] = np.maximum(sm + (t_cyl - at_eq) * _fade(dist / span), 0.0)
    return out


def _fade(x: np.ndarray) -> np.ndarray:
    """1 at x = 0 falling to 0 at x >= 1, C2 with zero slope and curvature at both ends (the quintic
    smoothstep): the dome's share of the cylinder's thickness next to the equator."""
    x = np.clip(x, 0.0, 1.0)
    return 1.0 - x * x * x * (10.0 - 15.0 * x + 6.0 * x * x)


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
    dilation of t by a cone of that slope). A pile-up next to a small opening is then carried to the
    boss and rises past the opening's plane, as the laminate does against a boss's neck (the grown
    dome ends there, winder.geometry.offset). The slope limit at each station is the least
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
    to the range ends by its end values so the growth covers [0, length] (on a vessel the laminate
    piled up against a boss stands there; the grown dome ends where its surface turns back,
    winder.geometry.offset)."""
    ends = (thickness[0], thickness[-1])
    s = np.concatenate([[cells.edges[0]], cells.centres, [cells.edges[-1]]])
    h = np.concatenate([[ends[0]], thickness, [ends[1]]])
    return grow_surface(surface, s, h)

"""The payout eye's envelope: the surface of revolution the eye keeps to around a straight-axis
mandrel (the rule is in winder.machine.kinematics' module docstring, which uses it)."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from winder.config.machine import MachineConfig
from winder.geometry.surface import SweepSurface
from winder.machine.dilation import LIFT_TOL, lift_table, polyline_dilation, turn

SECTION_SAMPLES = 3601  # angles scanned for the section's largest radius
ENVELOPE_STEP = 0.25  # mm, station step of the tabulated envelope (finer for small clearances)
ENVELOPE_MAX_SAMPLES = 65537
SKIP_MARGIN = 1e-9  # relative: the dilation's skipped steps are no-ops with this much to spare
HULL_SWEEPS = 64  # vectorized pruning sweeps of the upper hull before the monotone chain finishes it
CAP_CUT = 2  # samples of a dilated end cap the table stops short of (where its continuation clears)
CONTINUATION_SAMPLES = 257  # points between a table's end and its cap's rim its continuation is held at
RIM_EXCESS = 1e-4  # mm: the circumscribed polygon of an end's disc lies at most this far outside it


@dataclasses.dataclass(frozen=True, eq=False)
class EyeEnvelope:
    """The radius the eye keeps from the mandrel axis, as a function of the axial station.

    stations, radius : (k,) float, a uniform table of Z_env; `constant` set in radius mode.
    mandrel_radius : (k,) float, r_max at the same stations (the largest section radius).
    """

    stations: np.ndarray
    radius: np.ndarray
    mandrel_radius: np.ndarray
    constant: float | None
    clearance: float | None
    radius_stations: np.ndarray | None = None  # where `radius` is tabulated (default: stations)
    end_slopes: tuple[float, float] = (0.0, 0.0)  # dZ/dX past the table's first and last station

    @functools.cached_property
    def level(self) -> float | None:
        """The table's one value where it is level with level continuations (a cylinder's clearance):
        then `at` is that value at every finite station and `slope` 0. None otherwise."""
        if self.constant is not None or tuple(self.end_slopes) != (0.0, 0.0) or self.radius.size == 0:
            return None
        v = self.radius[0]
        return float(v) if v > 0.0 and bool(np.all(self.radius == v)) else None

    @property
    def max_radius(self) -> float:
        return float(self.constant if self.constant is not None else np.max(self.radius))

    def at(self, t: np.ndarray) -> np.ndarray:
        """Z_env at stations t; beyond the table it goes on straight with its end slopes (down to 0)."""
        t = np.asarray(t, dtype=float)
        if self.constant is not None:
            return np.full(t.shape, self.constant)
        x = self.stations if self.radius_stations is None else self.radius_stations
        z = self.radius
        lo, hi = self.end_slopes
        if t.ndim == 0:
            return self.at(t[None])[0]
        out = np.interp(t, x, z)
        # Only the few stations past the table are recomputed (a lead search asks for ~10^6 stations).
        before, after = t < x[0], t > x[-1]
        if before.any():
            out[before] = z[0] + lo * (t[before] - x[0])
        if after.any():
            out[after] = z[-1] + hi * (t[after] - x[-1])
        return np.maximum(out, 0.0, out=out)

    def slope(self, t: np.ndarray) -> np.ndarray:
        """dZ_env/dt at stations t (same shape as t): `at` is piecewise linear, so this is the slope of
        the segment holding t (the right one at a table station), the end slopes past the table, 0
        where `at` is clipped to 0 or constant. For Newton steps on the lead (winder.machine.leads)."""
        t = np.asarray(t, dtype=float)
        if self.constant is not None:
            return np.zeros(t.shape)
        x = self.stations if self.radius_stations is None else self.radius_stations
        z = self.radius
        # Segment j + 1 of (before the table, the table's segments, past it), so j = -1 .. k - 1.
        table = np.concatenate([[self.end_slopes[0]], np.diff(z) / np.diff(x), [self.end_slopes[1]]])
        out = table[np.searchsorted(x, t, side="right")]
        past = (t < x[0]) | (t > x[-1])  # the table itself is positive: only its continuations reach 0
        if past.any():
            out[past] = np.where(self.at(t[past]) > 0.0, out[past], 0.0)
        return out

    def mandrel_at(self, t: np.ndarray) -> np.ndarray:
        """r_max at stations t (clamped to the mandrel's ends)."""
        return np.interp(np.asarray(t, dtype=float), self.stations, self.mandrel_radius)


def _largest_section_angle(surface: SweepSurface) -> float:
    """The section angle of the largest radius (the section is the same shape at every station,
    scaled by the profile: R(s, theta) = p(s) q(theta))."""
    th = np.linspace(0.0, 2.0 * np.pi, SECTION_SAMPLES)
    s_mid = np.full(th.shape, 0.5 * surface.length)
    r = surface.radius(s_mid, th)
    k = int(np.argmax(r))
    # One parabola step through the neighbours refines the grid maximum.
    if 0 < k < th.shape[0] - 1:
        r0, r1, r2 = r[k - 1], r[k], r[k + 1]
        den = r0 - 2.0 * r1 + r2
        if den < 0.0:
            return float(th[k] + 0.5 * (r0 - r2) / den * (th[1] - th[0]))
    return float(th[k])


def section_top(surface: SweepSurface, stations: np.ndarray) -> np.ndarray:
    """r_max (k,) at the uniform stations (k,) inside [t_start, T]: the largest section radius, sampled in
    the internal station (arc length on domes) at least as finely, then put on the stations."""
    th_max = _largest_section_angle(surface)
    s = np.linspace(0.0, surface.length, max(stations.size, 2049))
    r_s = surface.radius(s, np.full(s.shape, th_max))
    return np.interp(stations, surface.t_of_s(s), r_s)


def eye_envelope(surface: SweepSurface, machine: MachineConfig, wound=None) -> EyeEnvelope:
    """The eye envelope of a machine around a mandrel (module docstring); computed once per job.
    wound : the part as wound (winder.machine.as_wound.WoundProfile) where its laminate stands
    beyond the surface (past a vessel's opening planes): the envelope clears both."""
    T, t0 = surface.axial_length, surface.t_start
    clearance = machine.eye_clearance if machine.eye_radius is None else None
    step = ENVELOPE_STEP if clearance is None else min(ENVELOPE_STEP, clearance / 16.0)
    lo, hi = (t0, T) if wound is None else wound.span
    n = int(min(ENVELOPE_MAX_SAMPLES, max(257, np.ceil((hi - lo) / step) + 1)))
    stations = np.linspace(lo, hi, n)
    if wound is None:
        r_max = section_top(surface, stations)
    else:
        inside = (stations >= t0) & (stations <= T)
        r_max = np.maximum(wound.beyond(stations), 0.0)
        r_max[inside] = np.maximum(r_max[inside], section_top(surface, stations[inside]))
    if machine.eye_radius is not None:
        zr = float(machine.eye_radius)
        return EyeEnvelope(stations, np.full(n, zr), r_max, zr, None)
    c = float(clearance) + 0.5 * float(machine.eye_size)  # the eye's centre: its body keeps the clearance
    h = stations[1] - stations[0]
    k_max = int(np.floor(c / h))
    # The profile dilated by the disc of radius c; past an end where the profile falls toward it (a
    # dome, a cone's small end) also the dilated end (its cap): there the envelope goes on down with
    # the cap's slope (a convex region: see _concave_majorant), elsewhere it keeps its end value.
    dil, _ = _dilate(stations, r_max, c, h, k_max, (False, False))
    plain = _concave_majorant(stations, dil)
    caps = (plain[1] > plain[0] + 1e-12, plain[-2] > plain[-1] + 1e-12)
    if not any(caps):
        return EyeEnvelope(stations, _lifted(stations, plain, r_max, c), r_max, None, c)
    dil, x = _dilate(stations, r_max, c, h, k_max, caps)
    # The cap's last samples run nearly vertical, where a chord between samples falls inside the circle:
    # stop the table CAP_CUT samples short; the straight continuation (a secant's) stays outside it where
    # the cap's first samples lie on the end's own disc. Where they lie on a neighbour's (a grown
    # vessel's end: its boss corner past the opening plane, low, the pile-up's wall steep behind it,
    # docs/math/17 17.8), the secant runs steeper than the end's disc and cuts into it (0.33 mm of 25 on
    # tank_20): that end's cap is then taken down to its rim along the end disc's circumscribed polygon.
    cut = slice(CAP_CUT if caps[0] else 0, x.size - (CAP_CUT if caps[1] else 0))
    x, dil = x[cut], dil[cut]
    z = _lifted(x, _concave_majorant(x, dil), r_max, c, stations)
    slopes = ((z[1] - z[0]) / h if caps[0] else 0.0, (z[-1] - z[-2]) / h if caps[1] else 0.0)
    short = [end for end in (0, 1) if caps[end] and _continuation_cuts(x, z, slopes, stations, r_max, c, end)]
    if short:
        x, dil = _with_rims(x, dil, stations, r_max, c, short)
        z = _lifted(x, _concave_majorant(x, dil), r_max, c, stations)
        slopes = ((z[1] - z[0]) / (x[1] - x[0]) if 0 in short else slopes[0],
                  (z[-1] - z[-2]) / (x[-1] - x[-2]) if 1 in short else slopes[1])
    return EyeEnvelope(stations, z, r_max, None, c, x, slopes)


def _continuation_cuts(x: np.ndarray, z: np.ndarray, slopes: tuple[float, float], stations: np.ndarray,
                       r_max: np.ndarray, c: float, end: int) -> bool:
    """Whether the table's straight continuation past its end (0: first, 1: last) comes nearer the
    profile's polyline (stations, r_max) than c before the cap's rim, c past the profile's end (the
    polyline's dilation, winder.machine.dilation; an end disc's top is its end vertex's disc)."""
    sign = 1.0 if end == 0 else -1.0
    rim = stations[0] - c if end == 0 else stations[-1] + c
    x0, z0, slope = (x[0], z[0], slopes[0]) if end == 0 else (x[-1], z[-1], slopes[1])
    if (x0 - rim) * sign <= 0.0:
        return False
    q = np.linspace(rim, x0, CONTINUATION_SAMPLES)
    line = np.maximum(z0 + slope * (q - x0), 0.0)
    return bool(np.any(polyline_dilation(q, stations, r_max, c) > line + LIFT_TOL))


def _with_rims(x: np.ndarray, dil: np.ndarray, stations: np.ndarray, r_max: np.ndarray, c: float,
               ends: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """The samples (x, dil) with, at each end of ends, the polygon circumscribing its end vertex's disc
    over the quarter from the rim (the disc's point c past the end, its tangent along the radius) to its
    top: every edge touches the disc, every vertex within RIM_EXCESS of it. The upper hull of a union of
    discs leaves the leftmost (rightmost) one at its rim, whatever its neighbours do: so the table's
    concave majorant, taken over these too, clears the end's disc however steep the cap's samples run,
    and past the rim (the table's new end) nothing of the part lies within c."""
    k = int(np.ceil(0.5 * np.pi / (2.0 * np.arccos(1.0 / (1.0 + RIM_EXCESS / c)))))
    psi = (np.arange(k) + 0.5) * (0.5 * np.pi / k)  # between the tangent points 0, pi/2k, .., pi/2
    reach = c / np.cos(0.25 * np.pi / k)
    for end in ends:
        t0, r0, sign = (stations[0], r_max[0], -1.0) if end == 0 else (stations[-1], r_max[-1], 1.0)
        px, pz = t0 + sign * reach * np.cos(psi), max(r0, 0.0) + reach * np.sin(psi)
        x, dil = np.concatenate([x, px]), np.concatenate([dil, pz])
    order = np.argsort(x, kind="stable")
    x, dil = x[order], dil[order]
    keep = np.concatenate([[True], np.diff(x) > 0.0])  # a station met twice keeps its larger value
    dil = np.maximum.reduceat(dil, np.flatnonzero(keep))
    return x[keep], dil


def _lifted(x: np.ndarray, z: np.ndarray, r_max: np.ndarray, c: float, stations: np.ndarray | None = None) -> np.ndarray:
    """The table z at x kept c from the profile's polyline between its samples too
    (winder.machine.dilation), concave again; z itself where nothing was raised."""
    lifted = lift_table(x, z, x if stations is None else stations, r_max, c)
    if lifted is z or np.array_equal(lifted, z):
        return z
    return _concave_majorant(x, lifted)


def _dilate(stations: np.ndarray, r_max: np.ndarray, c: float, h: float, k_max: int,
            caps: tuple[bool, bool]) -> tuple[np.ndarray, np.ndarray]:
    """(Z, X): the profile r_max (k,) on the uniform stations dilated by a disc of radius c, on the
    stations and, at the ends flagged in caps, c past them."""
    before, after = (k_max if caps[0] else 0), (k_max if caps[1] else 0)
    x = np.concatenate([stations[0] - h * np.arange(before, 0, -1), stations,
                        stations[-1] + h * np.arange(1, after + 1)])
    r_ext = np.concatenate([np.full(before, -np.inf), r_max, np.full(after, -np.inf)])
    dil = r_ext + c
    # A neighbour k stations away lifts a point only where it lies more than c - rise_k above it:
    # with no capped ends (every value finite), once c - rise_k exceeds the profile's spread (by a
    # margin far above the round-off of both) no step changes a value, rise_k only falls with k,
    # and the rest is skipped (a cylinder: every step).
    spread, margin = np.inf, 0.0
    if r_max.size and not any(caps):
        top, low = float(np.max(r_max)), float(np.min(r_max))
        spread, margin = top - low, SKIP_MARGIN * (c + max(abs(top), abs(low)))
    for k in range(1, k_max + 1):
        rise = np.sqrt(max(c * c - (k * h) ** 2, 0.0))
        if c - rise > spread + margin:
            break
        dil[k:] = np.maximum(dil[k:], r_ext[:-k] + rise)
        dil[:-k] = np.maximum(dil[:-k], r_ext[k:] + rise)
    return np.maximum(dil, 0.0), x


def _concave_majorant(x: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The least concave function >= z over the points x (k,) (increasing), at x: the upper convex
    hull of the points (x, z), interpolated.

    Why: the eye sits where the fiber's tangent ray leaves the region inside the envelope; a region
    that is convex (its profile concave, continued straight past the table) is left exactly once, so
    the eye moves continuously with the contact point. Around a dome's polar opening the dilated
    profile is not concave, and a ray grazing it jumped to a crossing far past the pole."""
    keep = np.arange(x.size)
    for _ in range(HULL_SWEEPS):
        # A point on or below the chord of its kept neighbours is no vertex of the upper hull (the
        # chord lies under the hull): all such points go at once. None left: the kept polyline
        # turns one way at every vertex, so it is the hull.
        a, b, c = keep[:-2], keep[1:-1], keep[2:]
        below = turn(x, z, a, b, c) >= 0.0
        if not below.any():
            return np.interp(x, x[keep], z[keep])
        keep = np.concatenate([keep[:1], b[~below], keep[-1:]])
    return np.interp(x, x[keep], z[keep]) if keep.size < 3 else _monotone_chain(x, z, keep)


def _monotone_chain(x: np.ndarray, z: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """The upper hull of the points keep by Andrew's monotone chain, once the sweeps have left few."""
    hull: list[int] = []
    for i in keep.tolist():
        while len(hull) >= 2 and turn(x, z, hull[-2], hull[-1], i) >= 0.0:
            hull.pop()
        hull.append(i)
    return np.interp(x, x[hull], z[hull])

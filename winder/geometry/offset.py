"""The grown mandrel: a sweep surface offset along its normal by a laminate thickness h(s).

The next layer is planned on the mandrel grown by the layers below (docs/math/08-laminate-edges.md), so the grown mandrel
must be a sweep surface of the same kind, with exact, consistent derivatives:

- Axial profiles (constant, cone, table; s = t): the radius grows by g(t) = h(t) sqrt(1 + r'(t)^2),
  the radial rise that puts the surface h away along the normal (exact on cylinders and cones). The
  sum is a new C2 cubic spline, so the grown profile is an AxialProfile again.
- Vessels: each dome meridian (h(sigma), r(sigma)) is offset along its outward normal
  N = (-r', h'): P = B + g N. With the signed curvature k = psi' of the base (psi the tangent angle)
  P' = (1 - g k) T + g' N, so the offset's tangent angle is psi + atan2(g', 1 - g k), its speed
  sqrt((1 - g k)^2 + g'^2), and its curvature the derivative of that angle over the speed. The
  offset is re-parametrized by its own arc length (Gauss-Legendre of the speed) and stored as C2
  quintic Hermite pieces through exact values, unit tangents and curvatures at the knots (as the
  isotensoid is), so it is a DomeMeridian and the grown vessel a VesselMeridian: the planner, Clairaut
  turnarounds and advances work on it unchanged. A constant g on a hemisphere gives the sphere of
  radius R + g. A laminate piled up next to a boss rises past the opening's plane (as it does along the
  boss's neck): the grown dome ends where its surface would turn back toward the equator or fold next
  to the opening (the pile-up's inner edge; an isotensoid's end hook under it), and the grown vessel
  keeps the axial frame (the equators at the same t, hence the same machine coordinates) with its near
  end at t = origin <= 0 (docs/math/17 17.8).
- Non-circular sections scale with the profile (R = p(s) q(theta)), so their mean radius grows by g;
  a uniform offset of a flat side is then approximate, exact on circles.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from winder.geometry.domes import DomeMeridian, _quintic_hermite, table_grid, with_derivatives
from winder.geometry.profiles import AxialProfile, linear
from winder.geometry.surface import SweepSurface
from winder.geometry.vessel import VesselMeridian

# A growth: base station -> (g, g', g''), each (m,) float (mm, per mm, per mm^2).
Growth = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]

FOLD_MARGIN = 0.05  # 1 - g k must stay above this: a layer thicker than a concave radius folds
KNOT_SPACING = 0.25  # mm, the offset dome's knot spacing (plus the base dome's own knots)
AFFINE_TOL = 1e-12  # mm: a growth this close to affine keeps a one-piece profile (Horner path)
END_ZONE_SHARE = 0.15  # of a dome's length next to its opening where the laminate's surface may end early
END_COS = 1e-3  # the grown meridian ends before its tangent turns within this cosine of radial
TRIM_STEPS = 48  # bisections of where it ends


class OffsetError(ValueError):
    """The offset is not a regular surface (the laminate folds over a concave region)."""


def grow_axial(profile: AxialProfile, s: np.ndarray, h: np.ndarray) -> AxialProfile:
    """An axial profile grown by the normal thickness h at stations s ((m,) float, covering [0, T]).

    The radius rises by h sqrt(1 + r'^2); the result is the cubic spline through r + rise at s (one
    piece again where the base and the rise are both affine, keeping the fast evaluation path).
    """
    s = np.asarray(s, dtype=float)
    ev = profile.evaluate(s)
    r_new = ev.r + np.asarray(h, float) * np.sqrt(1.0 + ev.r1 * ev.r1)
    fit = np.polyfit(s, r_new, 1)
    if np.max(np.abs(np.polyval(fit, s) - r_new)) <= AFFINE_TOL:
        r0, r1 = np.polyval(fit, np.array([0.0, profile.length]))
        spline = linear(profile.length, float(r0), float(r1))
    else:
        from scipy.interpolate import CubicSpline  # noqa: PLC0415 - slow to import: only a varying build-up

        spline = CubicSpline(s, r_new, bc_type="not-a-knot")
    return AxialProfile(spline, profile.length, profile.reference_radius)


class OffsetDome(DomeMeridian):
    """A dome meridian offset along its normal by g(sigma) (sigma the base arc length from the
    equator), re-parametrized by its own arc length, ending where the laminate's surface ends next to
    the opening (it may rise past the opening's plane: the grown vessel's frame follows, VesselMeridian
    .origin)."""

    def __init__(self, base: DomeMeridian, growth: Growth):
        L = base.length
        grid = table_grid(0.0, L, min(KNOT_SPACING, L / 64.0), np.union1d(base._tab_sigma, base.joints))
        grid = self._trimmed(base, growth, grid)
        H, R, psi, kap, speed = self._offset(base, growth, grid)
        sig = self._arc_length(base, growth, grid)
        self.kind = base.kind
        # the base's curvature joints are table sites: the offset's own arc length there
        self.joints = tuple(float(sig[np.argmin(np.abs(grid - j))]) for j in base.joints if j < grid[-1])
        self.radius = float(R[0])
        self.semi_axis = None
        self.length = float(sig[-1])
        self.depth = float(H[-1])
        self.end_radius = float(R[-1])
        self.polar_opening = self.end_radius
        k = kap / speed  # curvature in the offset's own arc length
        c, s = np.cos(psi), np.sin(psi)
        hh = _quintic_hermite(sig, H, c, -s * k)
        rr = _quintic_hermite(sig, R, s, c * k)
        self._pp = with_derivatives([hh, rr])  # h, h', h'', r, r', r'' (both pieces share the knots)
        self._tab_sigma, self._tab_h = sig, H

    @classmethod
    def _trimmed(cls, base: DomeMeridian, growth: Growth, grid: np.ndarray) -> np.ndarray:
        """The grid up to where the laminate's surface ends next to the opening: where the offset would
        turn back toward the equator or fold (a pile-up's inner edge against the boss, an isotensoid's
        end hook under the laminate), found by bisection. Anywhere else that is a refusal (_offset)."""
        bad = ~cls._regular(base, growth, grid)
        if not np.any(bad):
            return grid
        i = int(np.argmax(bad))
        if i == 0 or grid[i] < base.length * (1.0 - END_ZONE_SHARE):
            return grid  # _offset refuses it with the reason
        lo, hi = grid[i - 1], grid[i]
        for _ in range(TRIM_STEPS):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if cls._regular(base, growth, np.array([lo, mid]))[-1] else (lo, mid)
        return np.append(grid[:i], lo)

    @staticmethod
    def _regular(base: DomeMeridian, growth: Growth, sigma: np.ndarray) -> np.ndarray:
        """Where the offset is a regular meridian still moving toward the pole (bool per sigma)."""
        ev = base.evaluate(sigma)
        g, g1, _ = growth(sigma)
        k = ev.h1 * ev.r2 - ev.r1 * ev.h2
        a = 1.0 - g * k
        return (a >= FOLD_MARGIN) & (np.cos(np.arctan2(ev.r1, ev.h1) + np.arctan2(g1, a)) > END_COS)

    @staticmethod
    def _offset(base: DomeMeridian, growth: Growth, sigma: np.ndarray):
        """Offset point (H, R), tangent angle psi, d psi / d sigma and speed at base sigma."""
        ev = base.evaluate(sigma)
        g, g1, g2 = growth(sigma)
        psi0 = np.arctan2(ev.r1, ev.h1)
        k = ev.h1 * ev.r2 - ev.r1 * ev.h2  # signed curvature psi0'
        k1 = np.gradient(k, sigma) if sigma.size > 2 else np.zeros_like(k)
        a = 1.0 - g * k
        if np.any(a < FOLD_MARGIN):
            worst = int(np.argmin(a))
            raise OffsetError(f"a laminate {g[worst]:.4g} mm thick folds over the dome's concave radius "
                              f"{1.0 / abs(k[worst]):.4g} mm there (r = {ev.r[worst]:.4g} mm)")
        a1 = -(g1 * k + g * k1)
        psi = psi0 + np.arctan2(g1, a)
        dpsi = k + (a * g2 - g1 * a1) / (a * a + g1 * g1)
        if np.any(np.cos(psi) <= 0.0):
            worst = int(np.argmin(np.cos(psi)))
            raise OffsetError(f"the laminate's edge (slope {g1[worst]:.3g}) turns the grown dome back "
                              f"toward the equator at r = {ev.r[worst]:.4g} mm")
        return ev.h - g * ev.r1, ev.r + g * ev.h1, psi, dpsi, np.hypot(a, g1)

    @classmethod
    def _arc_length(cls, base: DomeMeridian, growth: Growth, grid: np.ndarray, order: int = 8) -> np.ndarray:
        xg, wg = np.polynomial.legendre.leggauss(order)
        half = 0.5 * np.diff(grid)
        pts = (grid[:-1, None] + half[:, None] * (xg + 1.0)).ravel()
        ev = base.evaluate(pts)
        g, g1, _ = growth(pts)
        k = ev.h1 * ev.r2 - ev.r1 * ev.h2
        v = np.hypot(1.0 - g * k, g1).reshape(-1, order)
        return np.concatenate([[0.0], np.cumsum((v * wg).sum(axis=1) * half)])

    def _eval2(self, sigma: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, ...]:
        h, h1, h2, r, r1, r2 = self._pp(np.asarray(sigma, dtype=float)).T
        return (self.depth - h, h, h1, h2, r, r1, r2)


def vessel_growths(vessel: VesselMeridian, s: np.ndarray, h: np.ndarray) -> tuple[float, Growth, Growth]:
    """The cylinder's constant growth and each dome's C2 growth in its own sigma (from its equator),
    from thicknesses h at vessel stations s ((m,) float each).

    Each dome's spline ends at its equator on the cylinder's value with zero slope (clamped), so the
    grown meridian meets the grown cylinder tangentially, and at its polar opening with zero slope
    (a dome's end hook, microns wide, is then offset by about the thickness given at the opening).
    """
    a, b = vessel.equator_s
    s, h = np.asarray(s, float), np.asarray(h, float)
    on_cyl = (s > a) & (s < b)
    g_cyl = float(np.mean(h[on_cyl])) if np.any(on_cyl) else float(np.interp(a, s, h))

    def dome(sigma: np.ndarray, length: float) -> Growth:
        keep = (sigma > 0.0) & (sigma <= length)
        x = np.concatenate([[0.0], sigma[keep]])
        y = np.concatenate([[g_cyl], h[keep]])
        order = np.argsort(x)
        from scipy.interpolate import CubicSpline  # noqa: PLC0415 - slow to import: only vessels

        spline = CubicSpline(x[order], y[order], bc_type=((1, 0.0), (1, 0.0)))
        return lambda q: (spline(q), spline(q, 1), spline(q, 2))

    return g_cyl, dome(a - s, vessel.dome.length), dome(s - b, vessel.end_dome.length)


def grow_vessel(vessel: VesselMeridian, s: np.ndarray, h: np.ndarray) -> VesselMeridian:
    """A vessel meridian offset by the thickness h at vessel stations s ((m,) float each)."""
    g_cyl, first, end = vessel_growths(vessel, s, h)
    near = OffsetDome(vessel.dome, first)
    # the equators keep their t (the machine's frame): the near end moves by the first dome's rise
    origin = vessel.origin + vessel.dome.depth - near.depth
    return VesselMeridian(vessel.radius + g_cyl, vessel.cylinder_length, near, OffsetDome(vessel.end_dome, end),
                          origin)


def grow_surface(surface: SweepSurface, s: np.ndarray, h: np.ndarray) -> SweepSurface:
    """The mandrel grown by the mean normal thickness h at stations s ((m,) float, covering the
    station range [0, surface.length]; h smooth; on a vessel its mean over the cylinder is used there).
    """
    s, h = np.asarray(s, float), np.asarray(h, float)
    prof = surface.profile
    if isinstance(prof, VesselMeridian):
        grown = grow_vessel(prof, s, h)
        return replace(surface, profile=grown, length=grown.length)
    # mean section radius per unit profile: a circle grows by h, other sections scale to grow by h
    per_unit = 2.0 * np.pi / surface._unit_perimeter
    if prof is None:
        base = AxialProfile(linear(surface.length, 1.0, 1.0), surface.length, 1.0)
        return replace(surface, profile=grow_axial(base, s, h * per_unit))
    return replace(surface, profile=grow_axial(prof, s, h * per_unit))

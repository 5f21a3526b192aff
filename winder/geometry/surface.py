"""The mandrel as a sweep surface Phi(s, theta) = x(z(s)) + R(s, theta) n(z(s), theta).

x is the guide curve with its rotation-minimizing frame (e2, e3), n = cos(theta) e2 + sin(theta) e3,
z(s) the axial station of the internal station s (z = s except on vessels, see profiles.py) and
R(s, theta) = p(s) q(theta): the profile radius times the section shape. One code path serves the
paper's three radius cases; a case only changes which derivatives vanish.

Derivatives (docs/math/01-surface.md), with T = x', K = x'', K' = x''' at z and m = dn/dtheta:
  n_z = -(K.n) T,   m_z = -(K.m) T,   n_zz = -(K'.n) T - (K.n) K
  Phi_s   = z1 T + R_s n + R z1 n_z
  Phi_th  = R_th n + R m
  Phi_ss  = z2 T + z1^2 K + R_ss n + 2 R_s z1 n_z + R (z2 n_z + z1^2 n_zz)
  Phi_sth = R_sth n + R_s m + R_th z1 n_z + R z1 m_z
  Phi_thth = (R_thth - R) n + 2 R_th m
"""

from __future__ import annotations

import dataclasses
import functools
from typing import NamedTuple

import numpy as np

from winder.geometry.arc_sweep import ArcFrame, arc_frame, evaluate_arc, is_zero, phi_theta, phi_theta_theta, times
from winder.geometry.curves import GuideCurve, Line
from winder.geometry.profiles import AxialProfile, Profile
from winder.geometry.sections import Circle, Section


# The vanishing-term test and the unit factor of every evaluation, the arc's included (a test replaces
# them to compute every term).
_zero, _times = is_zero, times

class SurfaceEval(NamedTuple):
    """Phi and its derivatives at m parameter points; each field (m, 3) float or None (not asked).

    On a line or an arc the fields share one (k, 3, m) array, their .base (k = 1, 3, 6 for order 0, 1,
    2; p, ps, .., ptt the views base[0].T .. base[5].T; base[0] unset where p is None): see jet_of.
    """

    p: np.ndarray
    ps: np.ndarray | None = None
    pt: np.ndarray | None = None
    pss: np.ndarray | None = None
    pst: np.ndarray | None = None
    ptt: np.ndarray | None = None


def jet_of(ev: SurfaceEval, fields: int) -> np.ndarray | None:
    """The (k, 3, m) array whose rows 1 .. fields - 1 are ev.ps, ev.pt(, ev.pss, ev.pst, ev.ptt), or
    None where the fields are not so stored (a general guide curve's): consumers that reduce over the
    components of several fields at once (the chain energy's Hessian) take it whole."""
    ps = ev.ps
    jet = ps.base
    if not (isinstance(jet, np.ndarray) and jet.ndim == 3 and jet.shape[0] >= fields
            and jet.shape[2] == ps.shape[0] and ps.strides == (jet.strides[2], jet.strides[1])
            and ev.pt.base is jet and (fields < 6 or ev.ptt.base is jet)):
        return None
    return jet


_JET_FIELDS = (1, 3, 6)  # fields stored per order: p; p, ps, pt; p, ps, pt, pss, pst, ptt


@dataclasses.dataclass(frozen=True)
class SweepSurface:
    """A mandrel surface. s in [0, length] is the internal station, theta in radians (unwrapped)."""

    curve: GuideCurve
    profile: Profile | None
    section: Section
    section_scale: float  # q(theta) = rho(theta) / section_scale
    length: float
    name: str = ""

    # -- stations ---------------------------------------------------------------------------------
    @property
    def axial_length(self) -> float:
        """T: the user-facing station t runs over [t_start, T] ([0, T] on every bare mandrel)."""
        return self.profile.axial_length if self.profile is not None else self.length

    @property
    def t_start(self) -> float:
        """t at s = 0: 0, except on a grown vessel whose laminate rises past its first boss's plane."""
        return float(getattr(self.profile, "t_start", 0.0))

    def t_of_s(self, s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=float)
        # z = s unless on a vessel: its profile's z is s itself, not worth the profile's evaluation
        return s if self.is_axial_parameter else self.profile.evaluate(s).z

    def s_of_t(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.profile.s_of_t(t) if self.profile is not None else t

    @property
    def is_revolution(self) -> bool:
        """A straight axis and a circular section: a surface of revolution (Clairaut holds)."""
        return bool(self.curve.is_straight and self.section.is_circle)

    @functools.cached_property
    def cylinder_radius(self) -> float | None:
        """R on a circular cylinder (a straight axis, a circle, one radius everywhere), else None:
        where geodesics are helices and friction paths have a closed form (winder.paths.friction_cylinder)."""
        if not self.is_revolution or self._constant_radius is None:
            return None
        return float(self.radius(np.zeros(1), np.zeros(1))[0])

    @property
    def is_axial_parameter(self) -> bool:
        """Whether s is the axial station itself (everything but vessels)."""
        return self.profile is None or isinstance(self.profile, AxialProfile)

    # -- radius -----------------------------------------------------------------------------------
    def _profile(self, s: np.ndarray):
        if self.profile is None:
            one, zero = np.ones_like(s), np.zeros_like(s)
            return s, one, zero, one, zero, zero
        return self.profile.evaluate(s)

    def radius(self, s: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """R(s, theta): (m,) float, the distance of the surface point from the guide curve."""
        s, theta = np.broadcast_arrays(np.asarray(s, float), np.asarray(theta, float))
        p = self._profile(s)[3]
        return p * self.section.polar(theta)[0] / self.section_scale

    @functools.cached_property
    def _constant_radius(self) -> float | None:
        """p(s) where it is a constant over z = s (None otherwise): evaluate then skips the profile."""
        if self.profile is None:
            return 1.0
        return self.profile.constant_radius if isinstance(self.profile, AxialProfile) else None

    @functools.cached_property
    def _line_frame(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
        """A straight guide line's origin, tangent, e2 and e3 as (3, 1) columns (None for other curves)."""
        if not isinstance(self.curve, Line):
            return None
        line = self.curve
        return line.origin[:, None], line.tangent[:, None], line.e2[:, None], line.e3[:, None]

    @functools.cached_property
    def _arc_frame(self) -> ArcFrame | None:
        """A guide curve that is one circular arc: its constants for evaluate_arc (None for other curves)."""
        curve = self.curve
        if isinstance(curve, Line):
            return None
        from winder.geometry.arcs import Arc, Path  # noqa: PLC0415 - loaded with any curve but the line

        if not (isinstance(curve, Path) and len(curve.pieces) == 1 and isinstance(curve.pieces[0], Arc)):
            return None
        arc = curve.pieces[0]
        b, e2u, e2b, e3u, e3b = arc.frame_components
        return arc_frame(arc.origin, arc.tangent, arc.toward_dir, b, arc.radius, float(e2u), float(e2b),
                         float(e3u), float(e3b))

    # -- evaluation -------------------------------------------------------------------------------
    def evaluate(self, s: np.ndarray, theta: np.ndarray, order: int = 2,
                 with_point: bool = True) -> SurfaceEval:
        """Phi (order 0), with first (order 1) and second (order 2) derivatives.

        s, theta : (m,) float. Returns SurfaceEval of (m, 3) arrays (views of (3, m) storage: the
        arithmetic runs along m, which numpy does several times faster than along the 3 components).
        with_point : False leaves Phi out (p None) where only the derivatives are asked (order >= 1).
        """
        s, theta = np.asarray(s, float), np.asarray(theta, float)
        if s.shape != theta.shape:
            s, theta = np.broadcast_arrays(s, theta)
        radius = self._constant_radius
        if radius is not None:  # z = s and a constant radius: the derivatives are constants
            z, z1, z2, p, p1, p2 = s, 1.0, 0.0, radius, 0.0, 0.0
        elif isinstance(self.profile, AxialProfile):  # z = s: only the radius varies
            _, _, _, p, p1, p2 = self.profile.evaluate(s)
            z, z1, z2 = s, 1.0, 0.0
        else:
            z, z1, z2, p, p1, p2 = self.profile.evaluate(s)
        c, sn = np.cos(theta), np.sin(theta)
        if isinstance(self.section, Circle):
            q, q1, q2 = self.section.radius / self.section_scale, 0.0, 0.0
        else:
            # The section takes the angle's cosine and sine from here, and only the derivatives asked.
            rho = self.section.polar_cs(c, sn, order)
            q, q1, q2 = (a / self.section_scale if a is not None else None for a in rho)
        line, arc = self._line_frame, self._arc_frame
        with_point = with_point or order == 0
        if line is None and arc is None:
            return self._evaluate_curve(z, z1, z2, p, p1, p2, c, sn, q, q1, q2, order, with_point)
        # A line's or an arc's fields are (3, m) rows: written straight into one (k, 3, m) jet.
        jet = np.empty((_JET_FIELDS[order], 3, s.size))
        if arc is not None:
            evaluate_arc(arc, jet, z, z1, z2, p, p1, p2, c, sn, q, q1, q2, order, with_point, _zero, _times)
        else:
            self._evaluate_line(line, jet, z, z1, z2, p, p1, p2, c, sn, q, q1, q2, order, with_point)
        fields = list(jet.transpose(0, 2, 1))  # jet[k].T, each
        if not with_point:
            fields[0] = None
        return SurfaceEval(*fields)

    @staticmethod
    def _evaluate_line(line: tuple, jet: np.ndarray, z, z1, z2, p, p1, p2, c, sn, q, q1, q2, order: int,
                       with_point: bool) -> None:
        """evaluate_arc's work on a straight guide line (its frame constant: (3, 1) columns broadcast,
        nothing tiled per point). K = 0 there, so Phi_s = z1 T + r_s n, Phi_ss = z2 T + p2 q n and
        Phi_st = p1 q1 n + r_s m (the curve's terms with K, K' and K.n, K.m all 0)."""
        origin, tan, e2, e3 = line
        n = c * e2 + sn * e3
        r = p * q
        if with_point:
            np.add(origin + z * tan, r * n, out=jet[0])
        if order == 0:
            return
        m = c * e3 - sn * e2
        # A constant radius (p1 = p2 = 0) or a circle (q1 = 0) makes these exact 0.0: their terms are
        # left out (a constant-radius elliptic tube's Phi_ss and Phi_st are 0, and cost no pass).
        r_s = 0.0 if _zero(p1) else p1 * q
        r_t = 0.0 if _zero(q1) else p * q1
        _pair(jet[1], z1, tan, r_s, n)
        phi_theta(jet, r, r_t, n, m, _zero)
        if order == 1:
            return
        _pair(jet[3], z2, tan, 0.0 if _zero(p2) else p2 * q, n)
        _pair(jet[4], 0.0 if _zero(p1) or _zero(q1) else p1 * q1, n, r_s, m)
        phi_theta_theta(jet, p * q2 - r, r_t, n, m, _zero)

    def _evaluate_curve(self, z, z1, z2, p, p1, p2, c, sn, q, q1, q2, order: int, with_point: bool) -> SurfaceEval:
        """evaluate on a general guide curve (its frame per point): fields in the layout the curve's
        arrays give them, no jet."""
        cv = self.curve.evaluate(z)
        x, tan, kap, d3, e2, e3 = cv.x.T, cv.d1.T, cv.d2.T, cv.d3.T, cv.e2.T, cv.e3.T
        n = c * e2 + sn * e3
        r = p * q
        point = (x + r * n).T if with_point else None
        if order == 0:
            return SurfaceEval(point)
        straight = self.curve.is_straight
        m = c * e3 - sn * e2
        kn = 0.0 if straight else np.einsum("ij,ij->j", kap, n)
        r_s, r_t = p1 * q, p * q1
        stretch = _times(z1, 1.0 - r * kn)
        full = np.ndim(stretch) > 0 or np.ndim(tan) > 1 and tan.shape[1] > 1
        ps = stretch * tan if _zero(r_s) and full else stretch * tan + r_s * n
        pt = r * m if _zero(r_t) else r_t * n + r * m
        if order == 1:
            return SurfaceEval(point, ps.T, pt.T)
        km = 0.0 if straight else np.einsum("ij,ij->j", kap, m)
        kdn = 0.0 if straight else np.einsum("ij,ij->j", d3, n)
        bend = _times(z1, stretch) * kap
        if not (_zero(z2) and _zero(r_s) and _zero(kdn)):
            bend = (z2 * (1.0 - r * kn) - 2.0 * r_s * z1 * kn - r * z1 * z1 * kdn) * tan + bend
        pss = bend + (p2 * q) * n
        twist = _times(z1, r * km if _zero(r_t) else r_t * kn + r * km) * tan
        pst = r_s * m - twist if _zero(p1 * q1) else (p1 * q1) * n + r_s * m - twist
        ptt = (p * q2 - r) * n if _zero(r_t) else (p * q2 - r) * n + (2.0 * r_t) * m
        return SurfaceEval(point, ps.T, pt.T, pss.T, pst.T, ptt.T)

    def points(self, s: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """Phi(s, theta): (m, 3) float."""
        return self.evaluate(s, theta, order=0).p

    def grid_points(self, s: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """Phi on the grid of stations s (a,) by angles theta (b,): (a b, 3) float, row i b + j at (s_i,
        theta_j), the values of points() on the meshgrid (indexing "ij"), to round-off. On a straight
        axis with a constant radius the point splits into x(s_i) + R(theta_j) n(theta_j), so the
        angles' cosines, sines and section radii are taken once per angle, not once per grid point."""
        s, theta = np.asarray(s, float), np.asarray(theta, float)
        radius, line = self._constant_radius, self._line_frame
        if radius is None or line is None:
            ss, tt = np.meshgrid(s, theta, indexing="ij")
            return self.points(ss.ravel(), tt.ravel())
        origin, tan, e2, e3 = line
        c, sn = np.cos(theta), np.sin(theta)
        if isinstance(self.section, Circle):
            q = self.section.radius / self.section_scale
        else:
            q = self.section.polar_cs(c, sn, 0)[0] / self.section_scale
        x = origin + s * tan  # (3, a)
        rn = (radius * q) * (c * e2 + sn * e3)  # (3, b): evaluate's r * n
        return (x[:, :, None] + rn[:, None, :]).reshape(3, -1).T

    def turned(self, v: np.ndarray, dtheta: np.ndarray, point: bool = True) -> np.ndarray:
        """Rows v (m, 3) turned by dtheta (m,) rad about the straight guide line, as theta + dtheta
        turns a surface of revolution's point (point True: about the line through its origin) or
        direction (point False: about its tangent). A turned copy's values without the profile's
        evaluation, equal to it to round-off."""
        origin, _, e2, e3 = self._line_frame
        rel = v - origin[:, 0] if point else v
        a, b = rel @ e2[:, 0], rel @ e3[:, 0]
        c, sn = np.cos(dtheta), np.sin(dtheta)
        return v + np.outer(a * (c - 1.0) - b * sn, e2[:, 0]) + np.outer(a * sn + b * (c - 1.0), e3[:, 0])

    def normals(self, s: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """Outward unit normals: (m, 3) float."""
        ev = self.evaluate(s, theta, order=1)
        nrm = np.cross(ev.pt, ev.ps)
        return nrm / np.linalg.norm(nrm, axis=1)[:, None]

    @functools.cached_property
    def _unit_perimeter(self) -> float:
        # The section's own perimeter needs a quadrature for non-circular shapes: once per surface.
        return self.section.perimeter() / self.section_scale

    def perimeter(self, s: float | np.ndarray) -> float | np.ndarray:
        """Perimeter of the cross-section at station(s) s (mm): float, or (m,) float for an array."""
        arr = np.atleast_1d(np.asarray(s, dtype=float))
        per = self._profile(arr)[3] * self._unit_perimeter
        return float(per[0]) if np.ndim(s) == 0 else per


# -- building from a config -----------------------------------------------------------------------
SELF_INTERSECTION_MARGIN = 1e-6  # 1 - R (K.n) must stay above this (a regular sweep)


def _check_stations(surface: SweepSurface) -> np.ndarray:
    """Internal stations s for the regularity check: a uniform grid, plus each bent piece of a path on
    its own grid (a short tight arc can hide between uniform stations) and a spline's fit grid."""
    s = [np.linspace(0.0, surface.length, 801)]
    curve, z = surface.curve, []
    if isinstance(curve, Line):
        return s[0]
    from winder.geometry.arcs import Path  # noqa: PLC0415 - loaded with any curve but the line

    if isinstance(curve, Path):
        for piece, z0 in zip(curve.pieces, curve.starts):
            if not piece.is_straight:
                z.append(z0 + np.linspace(0.0, piece.length, 65))
    else:
        from winder.geometry.spline_curves import SPLINE_GRID, SplineCurve  # noqa: PLC0415

        if isinstance(curve, SplineCurve):
            z.append(np.linspace(0.0, curve.length, SPLINE_GRID))
    if z:
        t = np.clip(np.concatenate(z), 0.0, surface.axial_length)
        s.append(surface.s_of_t(t))
    return np.concatenate(s)


class Fold(NamedTuple):
    """Where a sweep folds onto itself: station t (mm), section angle (deg), the section radius there,
    the bend radius 1 / kappa, and the section's reach toward the bend's centre (mm)."""

    t: float
    theta_deg: float
    radius: float
    bend_radius: float
    reach: float


def find_fold(surface: SweepSurface) -> Fold | None:
    """The worst place where a sweep's section reaches the centre of curvature of a bend
    (self-intersection), or None: 1 - R(s, theta) (K . n(theta)) must stay positive. The worst theta of each station is found on a
    2.5 deg grid and refined by golden-section search (the inside of a bend need not be on the grid)."""
    if surface.curve.max_curvature() == 0.0:
        return None
    s = _check_stations(surface)
    z = surface.t_of_s(s)
    cv = surface.curve.evaluate(z)

    def reach(tt: np.ndarray) -> np.ndarray:
        n = np.cos(tt)[:, None] * cv.e2 + np.sin(tt)[:, None] * cv.e3
        return surface.radius(s, tt) * np.einsum("ij,ij->i", cv.d2, n)

    th = np.linspace(0.0, 2.0 * np.pi, 145)[:-1]
    grid = np.stack([reach(np.full_like(s, t)) for t in th], axis=1)
    lo = th[np.argmax(grid, axis=1)] - (th[1] - th[0])
    hi = lo + 2.0 * (th[1] - th[0])
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    for _ in range(40):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        left = reach(a) > reach(b)
        lo, hi = np.where(left, lo, a), np.where(left, b, hi)
    tt = 0.5 * (lo + hi)
    r = reach(tt)
    use_grid = grid.max(axis=1) > r
    tt = np.where(use_grid, th[np.argmax(grid, axis=1)], tt)
    r = np.maximum(r, grid.max(axis=1))
    worst = int(np.argmax(r))
    if r[worst] < 1.0 - SELF_INTERSECTION_MARGIN:
        return None
    kappa = float(np.linalg.norm(cv.d2[worst]))
    radius = float(surface.radius(s[worst:worst + 1], tt[worst:worst + 1])[0])
    return Fold(float(z[worst]), float(np.degrees(tt[worst]) % 360), radius, 1.0 / kappa, float(r[worst]) / kappa)


def _pair(out: np.ndarray, a, u: np.ndarray, b, v: np.ndarray) -> None:
    """out (3, m) = a u + b v, a term whose coefficient is an exact 0.0 left out (adding +-0 changes
    no value, at most the sign of an exact zero) and a factor of an exact 1.0 not multiplied."""
    if _zero(b):
        if _zero(a):
            out[...] = 0.0
        else:
            np.multiply(a, u, out=out)
    elif _zero(a):
        np.multiply(b, v, out=out)
    else:
        np.add(_times(a, u), b * v, out=out)

"""Pressure-vessel meridians: hemispherical, ellipsoidal and isotensoid domes on a cylinder.

Every dome meridian is parametrized by its arc length sigma, measured from the equator (where it meets
the cylinder: r = R, meridian parallel to the axis) toward the polar opening. It returns

    h(sigma)  axial distance from the equator plane (0 at the equator, increasing toward the pole),
    r(sigma)  radius,

with their first and second derivatives in sigma. The curve has unit speed (h1^2 + r1^2 = 1) and its
derivatives are the exact derivatives of the (h, r) returned, not separate approximations: the geodesic
solver's Newton iteration needs them consistent. Nothing is singular down to the polar opening.

Each dome can also be evaluated from its opening, by u = length - sigma (evaluate_from_opening,
drop_and_evaluate_from_opening which also returns depth - h): the half of the dome next to the opening
is computed from u, so values there keep relative precision (the vessel's first dome starts at s = 0
there, and the isotensoid's end hook is microns wide).

Representation
- hemisphere: closed form, a circle of radius R.
- ellipsoid: the ellipse angle tau is a C2 piecewise quintic (Hermite, exact value, first and second
  derivative at each knot) of the arc length; h = d sin(tau), r = R cos(tau) are then exact functions of
  tau, so every point lies on the ellipse to rounding, and the derivatives follow by the chain rule.
  Config depth is the ellipsoid's full axial semi-axis d; the dome's depth to the opening plane is
  d sqrt(1 - (r0 / R)^2).
- isotensoid: the meridian is integrated in arc length as an ODE (DOP853, rtol 3e-14) in two pieces
  meeting at the inflection, and h, r are C2 piecewise quintic Hermite interpolants of exact slopes
  and curvatures (from psi and f'(r)) at knots equidistributed in arc length, turning angle and the
  variation of the curvature; positions at the knots are Gauss-Legendre integrals of (cos, sin)(psi),
  so values, slopes and curvatures agree to ~1e-14 (see _Isotensoid).

Accuracy, measured (R = 100): unit speed |h1^2 + r1^2 - 1| <= 1e-11 everywhere; ellipsoid arc length
vs ellipeinc ~1e-15 relative, points on the ellipse to 4e-16; isotensoid depth and length vs quadrature
of dh/dY ~1e-14 relative, end radius vs the closed-form root 1e-15, curvature vs netting theory
(R2/R1 = 2 - tan^2 alpha) 2e-9 of |k| + 1/R for c >= 0.1 R, 7e-8 at c = 0.02 R. Build: hemisphere
0.3 ms, ellipsoid 1 to 4 ms, isotensoid 10 to 70 ms (500 to 2500 knots).

The isotensoid (netting theory, geodesic fibers with Clairaut constant c = polar_opening, so that
sin(alpha) = c / r) satisfies R2 / R1 = 2 - tan^2(alpha), R1 the meridian radius of curvature and
R2 = r / sin(phi), phi the angle between the surface normal and the axis. With f(r) = sin(phi):
R2 / R1 = r f'(r) / f(r) = d ln f / d ln r = (2 r^2 - 3 c^2) / (r^2 - c^2), whose integral with
f(R) = 1 is

    sin(phi) = f(r) = (r / R)^3 sqrt((R^2 - c^2) / (r^2 - c^2)),

and with Y = r / R, Y0 = c / R, the classical geodesic isotensoid
dh/dY = -Y^3 sqrt(1 - Y0^2) / sqrt((1 - Y^2) (Y^2 (1 + Y^2) - Y0^2 (1 + Y^2 + Y^4))). In arc length,
with psi the angle of the meridian tangent from the axis (h1 = cos(psi), r1 = -sin(psi), so
cos(psi) = f(r)), the meridian curvature is psi' = f'(r) = f(r) (2 r^2 - 3 c^2) / (r (r^2 - c^2)),
finite on the whole dome. Starting at the equator (psi = 0) the meridian turns toward the axis, has an
inflection at r = c sqrt(3/2), and turns back to axial (psi = 0 again, sin(phi) = 1) at
r_* = R sqrt(u), u the positive root of (1 - Y0^2) u^2 + (1 - Y0^2) u - Y0^2 = 0, slightly above c
(r_* - c ~ c Y0^4 / 2 for a small opening). The dome ends there: end_radius = r_*, the meridian is
parallel to the axis again (h1 = 1, r1 = 0) and the surface is smooth. Geodesics with Clairaut constant
c therefore never turn around on this dome (r >= r_* > c); a winding plan must use c > end_radius.
For a small opening the last stretch before r_* is a very tight concave hook (radius of curvature about
2 (r_* - c) ~ c Y0^4, i.e. 1e-4 c at Y0 = 0.1) after a nearly radial stretch (h1 down to ~2.6 Y0^2):
the classical shape, but in practice a corner at the scale of a fiber band; a real boss blends it out.
It is integrated relative to the end (e = r - r_*, depth - h) so it keeps full relative precision.
There is no netting isotensoid at all for c >= R sqrt(2/3) (R1 < 0 at the equator); near that limit
the "dome" is a long, barely tapering neck (at c = 0.8 R it only narrows to r_* = 0.96 R over a depth
of 0.89 R), so openings above ISOTENSOID_MAX_OPENING * R are refused, and below
ISOTENSOID_MIN_OPENING * R (a hook narrower than ~3e-9 R).

Vessel: VesselMeridian implements the Profile protocol of winder.geometry.profiles. Its internal station s is
the meridian arc length from the first polar opening: the first dome reversed, then the cylinder, then
the end dome. The axial station t = z(s) is 0 in the plane of the first dome's polar opening
(SPEC.md), so T = depth(dome) + cylinder_length + depth(end_dome).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import PPoly

from winder.errors import ConfigError
from winder.geometry.profiles import ProfileEval

if TYPE_CHECKING:  # the config module is only needed for the type names
    from winder.config.mandrel import Dome, VesselProfile

# Limits of what the dome geometry can represent (see the module docstring).
ISOTENSOID_MAX_OPENING = 0.75  # polar_opening / radius; netting theory ends at sqrt(2/3) = 0.8165
ISOTENSOID_MIN_OPENING = 0.02  # polar_opening / radius; below, the end hook is thinner than ~3e-9 R
ELLIPSOID_MIN_DEPTH = 0.05  # depth / radius; below, the equator is a near-sharp edge (R1 = d^2 / R)
ELLIPSOID_MAX_DEPTH = 20.0  # depth / radius; beyond, a spike rather than a dome

_NEWTON_MAX_ITER = 100


class DomeEval(NamedTuple):
    """A dome meridian evaluated at arc lengths sigma, each array (m,) float."""

    h: np.ndarray
    h1: np.ndarray
    h2: np.ndarray
    r: np.ndarray
    r1: np.ndarray
    r2: np.ndarray


def _quintic_hermite(x: np.ndarray, y: np.ndarray, y1: np.ndarray, y2: np.ndarray) -> PPoly:
    """The C2 piecewise quintic through values, first and second derivatives at the knots x.

    Exact at the knots (value, slope and curvature), O(dx^6) between them; its derivatives are exactly
    those of the returned piecewise polynomial.
    """
    dx = np.diff(x)
    a0, a1, a2 = y[:-1], y1[:-1], 0.5 * y2[:-1]
    d0 = y[1:] - (a0 + a1 * dx + a2 * dx * dx)
    d1 = (y1[1:] - (y1[:-1] + y2[:-1] * dx)) * dx
    d2 = (y2[1:] - y2[:-1]) * dx * dx
    b3 = 10.0 * d0 - 4.0 * d1 + 0.5 * d2
    b4 = -15.0 * d0 + 7.0 * d1 - d2
    b5 = 6.0 * d0 - 3.0 * d1 + 0.5 * d2
    c = np.array([b5 / dx**5, b4 / dx**4, b3 / dx**3, a2, a1, a0])
    return PPoly(c, x, extrapolate=True)


class DomeMeridian:
    """One dome's meridian from its equator (sigma = 0) to its polar opening (sigma = length).

    Attributes
    ----------
    kind : "hemisphere", "ellipsoid" or "isotensoid".
    radius : the cylinder radius R (r at the equator).
    polar_opening : the configured polar opening r0 (for an isotensoid: the Clairaut constant c).
    length : meridian arc length from the equator to the opening.
    depth : axial depth from the equator plane to the plane of the opening.
    end_radius : radius at the opening end (= polar_opening, except isotensoid: r_* > c).
    semi_axis : the ellipsoid's axial semi-axis d (= R for a hemisphere, None for an isotensoid).
    (isotensoid only) clairaut = polar_opening, sigma_inflection: sigma of the inflection r = c sqrt(3/2).

    evaluate(sigma) accepts any shape; sigma_of_h(h) and u_of_drop(depth - h) invert h(sigma).

    Outside [0, length] evaluate() continues the pieces smoothly (closed form or polynomial
    extrapolation); only [0, length] is the dome.
    """

    kind: str
    radius: float
    polar_opening: float
    length: float
    depth: float
    end_radius: float
    semi_axis: float | None
    # Monotone knot table (sigma_k, h_k) bracketing the inversion h -> sigma.
    _tab_sigma: np.ndarray
    _tab_h: np.ndarray

    def evaluate(self, sigma: np.ndarray) -> DomeEval:
        """h, r and their first two sigma-derivatives at arc lengths sigma from the equator (any
        shape; the outputs have the shape of sigma)."""
        return DomeEval(*self._shaped(sigma, from_opening=False)[1:])

    def evaluate_from_opening(self, u: np.ndarray) -> DomeEval:
        """Same as evaluate(length - u), derivatives still in sigma; u is the arc length from the
        opening, which keeps full precision close to the opening (the vessel's first dome)."""
        return DomeEval(*self._shaped(u, from_opening=True)[1:])

    def drop_and_evaluate_from_opening(self, u: np.ndarray) -> tuple[np.ndarray, DomeEval]:
        """(depth - h, evaluate_from_opening(u)): the axial distance from the opening plane computed
        without cancellation (>= 0 for u >= 0), for the vessel's z near t = 0."""
        g, *rest = self._shaped(u, from_opening=True)
        return g, DomeEval(*rest)

    def _shaped(self, x: np.ndarray, from_opening: bool) -> tuple[np.ndarray, ...]:
        x = np.asarray(x, dtype=float)
        flat = x.ravel()
        other = self.length - flat
        out = self._eval2(other, flat) if from_opening else self._eval2(flat, other)
        return tuple(np.reshape(o, x.shape) for o in out)

    def _eval2(self, sigma: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, ...]:
        """(depth - h, h, h1, h2, r, r1, r2) at sigma = length - u; each piece uses the more precise of
        sigma (near the equator) and u (near the opening)."""
        raise NotImplementedError

    def sigma_of_h(self, h: np.ndarray) -> np.ndarray:
        """Arc length sigma at axial distance h from the equator plane (h clipped to [0, depth])."""
        return self._invert(h, from_opening=False)

    def u_of_drop(self, g: np.ndarray) -> np.ndarray:
        """Arc length u from the opening at axial distance g = depth - h from the opening plane (g
        clipped to [0, depth]); full relative precision near the opening."""
        return self._invert(g, from_opening=True)

    def _invert(self, target: np.ndarray, from_opening: bool) -> np.ndarray:
        """Bracketed vectorized Newton on h(sigma) (or g(u) = depth - h(length - u)).

        h is strictly increasing in sigma (h1 = cos(psi) > 0 on every dome with an opening), and
        dg/du = h1 as well. The knot table gives each point its bracket and a linear first guess; a
        Newton step leaving the bracket is replaced by bisection; stops when the step is below
        4 eps * length (about 1e-14 relative in sigma where h1 ~ 1).
        """
        q = np.clip(np.asarray(target, dtype=float), 0.0, self.depth)
        shape = q.shape
        q = q.ravel()
        L = self.length
        if from_opening:
            tx, ty = (L - self._tab_sigma)[::-1], (self.depth - self._tab_h)[::-1]
            tx[0], ty[0] = 0.0, 0.0
        else:
            tx, ty = self._tab_sigma, self._tab_h
        i = np.clip(np.searchsorted(ty, q, side="right") - 1, 0, len(ty) - 2)
        lo, hi = tx[i].copy(), tx[i + 1].copy()
        x = lo + (q - ty[i]) / (ty[i + 1] - ty[i]) * (hi - lo)
        # the table may be off by round-off: open the brackets slightly
        tol = 4.0 * np.finfo(float).eps * max(L, 1.0)
        lo, hi = lo - tol, hi + tol
        k = 0 if from_opening else 1
        for _ in range(_NEWTON_MAX_ITER):
            ev = self._eval2(L - x, x) if from_opening else self._eval2(x, L - x)
            f = ev[k] - q
            hi = np.where(f > 0.0, x, hi)
            lo = np.where(f < 0.0, x, lo)
            with np.errstate(divide="ignore", invalid="ignore"):
                xn = x - f / ev[2]
            bad = ~np.isfinite(xn) | (xn < lo) | (xn > hi)
            xn = np.where(bad, 0.5 * (lo + hi), xn)
            step = np.abs(xn - x)
            x = xn
            if np.all((step <= tol) | (hi - lo <= tol)):
                break
        return np.clip(x, 0.0, L).reshape(shape)


class _Hemisphere(DomeMeridian):
    kind = "hemisphere"

    def __init__(self, radius: float, r0: float):
        self.radius = radius
        self.polar_opening = r0
        self.semi_axis = radius
        self.length = radius * float(np.arccos(r0 / radius))
        self.depth = float(np.sqrt((radius - r0) * (radius + r0)))
        self.end_radius = r0
        self._tab_sigma = np.linspace(0.0, self.length, 65)
        self._tab_h = self.evaluate(self._tab_sigma).h

    def _eval2(self, sigma: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, ...]:
        R, D, r0 = self.radius, self.depth, self.end_radius
        a, b = sigma / R, u / R
        s, c = np.sin(a), np.cos(a)
        # near the opening, from u: sin(L/R) = D/R, cos(L/R) = r0/R and the angle-difference formulas
        near = 2.0 * u < self.length
        sb, cb = np.sin(b[near]), np.cos(b[near])
        s[near] = (D * cb - r0 * sb) / R
        c[near] = (r0 * cb + D * sb) / R
        g = 2.0 * D * np.sin(0.5 * b) ** 2 + r0 * np.sin(b)  # depth - R sin((L - u) / R)
        return (g, R * s, c, -s / R, R * c, -s, -c / R)

    def sigma_of_h(self, h: np.ndarray) -> np.ndarray:
        hq = np.clip(np.asarray(h, dtype=float), 0.0, self.depth)
        return self.radius * np.arcsin(hq / self.radius)


def _gauss_cumulative(fun, a: np.ndarray, order: int = 12) -> np.ndarray:
    """Cumulative integral of fun over the consecutive intervals of the grid a (Gauss-Legendre)."""
    xg, wg = np.polynomial.legendre.leggauss(order)
    lo, hi = a[:-1, None], a[1:, None]
    half = 0.5 * (hi - lo)
    vals = fun(lo + half * (xg + 1.0))
    return np.concatenate([[0.0], np.cumsum((vals * wg).sum(axis=1) * half[:, 0])])


class _Ellipsoid(DomeMeridian):
    """Meridian r = R cos(tau), h = d sin(tau), tau the ellipse angle, tau in [0, arccos(r0 / R)].

    d is the ellipsoid's full axial semi-axis (config key depth); the dome's depth to the opening plane
    is d sqrt(1 - (r0 / R)^2). tau(sigma) is a quintic Hermite spline with exact knot data
    tau' = 1 / v, tau'' = -v_tau / v^3, v = sqrt(R^2 sin^2 tau + d^2 cos^2 tau); sigma(tau) at the knots
    by 12-point Gauss-Legendre per interval. Knots are uniform in tau, which already concentrates them
    in arc length where the curvature is high (equator of an oblate, pole of a prolate ellipsoid).
    The opening half uses the mirrored spline nu(u) = tau_end - tau(length - u) (same knots and data),
    so that values there keep relative precision in u.
    """

    kind = "ellipsoid"

    def __init__(self, radius: float, r0: float, d: float):
        R = radius
        self.radius, self.polar_opening, self.semi_axis = R, r0, d
        tau_end = float(np.arccos(r0 / R))
        ratio = max(R / d, d / R)
        n = int(min(20000, max(256, np.ceil(160.0 * ratio))))
        tau = np.linspace(0.0, tau_end, n + 1)

        def speed(t):
            return np.sqrt((R * np.sin(t)) ** 2 + (d * np.cos(t)) ** 2)

        sig = _gauss_cumulative(speed, tau)
        v = speed(tau)
        v_t = (R - d) * (R + d) * np.sin(tau) * np.cos(tau) / v
        t1, t2 = 1.0 / v, -v_t / v**3
        self._tau = _quintic_hermite(sig, tau, t1, t2)
        arcs = np.diff(sig)
        u = np.concatenate([[0.0], np.cumsum(arcs[::-1])])
        nu = np.concatenate([[0.0], tau_end - tau[-2::-1]])
        self._nu = _quintic_hermite(u, nu, t1[::-1], -t2[::-1])
        self._pp = [p.derivative(j) if j else p for p in (self._tau, self._nu) for j in (0, 1, 2)]
        self.length = float(sig[-1])
        self.depth = d * float(np.sin(tau_end))
        self._tau_end = tau_end
        self.end_radius = r0
        self._tab_sigma = sig
        self._tab_h = d * np.sin(tau)

    def _eval2(self, sigma: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, ...]:
        tau, tau1, tau2, nu, nu1, nu2 = self._pp
        te = self._tau_end
        far = u * 2.0 >= self.length  # equator half: tau(sigma); opening half: nu(u)
        near = ~far
        t, t1, t2, n = (np.empty_like(sigma) for _ in range(4))
        if np.any(far):
            x = sigma[far]
            t[far], t1[far], t2[far] = tau(x), tau1(x), tau2(x)
            n[far] = te - t[far]
        if np.any(near):
            x = u[near]
            n[near], t1[near], t2[near] = nu(x), nu1(x), -nu2(x)
            t[near] = te - n[near]
        s, c = np.sin(t), np.cos(t)
        R, d = self.radius, self.semi_axis
        g = 2.0 * d * np.cos(te - 0.5 * n) * np.sin(0.5 * n)  # d (sin(te) - sin(t))
        return (g, d * s, d * c * t1, d * (c * t2 - s * t1 * t1),
                R * c, -R * s * t1, -R * (s * t2 + c * t1 * t1))


class _Isotensoid(DomeMeridian):
    """Geodesic isotensoid with Clairaut constant c = polar_opening; ends at r_* (module docstring).

    Two pieces meet at the inflection r_i = c sqrt(3/2) (curvature 0 there, psi known exactly from
    cos(psi) = f(r_i)):
    - A, equator to inflection, in sigma: state (r, h, psi), r' = -sin(psi), h' = cos(psi),
      psi' = f'(r);
    - B, opening to inflection, in u = length - sigma, relative to the end: state (e = r - r_*,
      g = depth - h, psi), e' = sin(psi), g' = cos(psi), psi' = -f'(r), from (0, 0, 0).
    B carries the tight end hook in local coordinates, so its slopes and curvatures keep full relative
    precision however small the hook is. Knots of each piece are equidistributed in the monitor
    1 / ds_max + (|k| + |k'|^(1/2) + |k''|^(1/3)) / dpsi_max (k = psi') over a 16-fold sampling of the
    solver's steps: turning per knot, and the scale on which the curvature varies (next to the hook it
    varies on the scale of the distance to the hook while turning little). Knot positions come from
    Gauss-Legendre integrals of (cos, sin)(psi) over each knot interval (see _knots).
    r_* is the closed form (module docstring), computed without cancellation; both pieces end on
    events (r = r_i), and the knot data at the equator, the inflection (psi exact, k = 0) and the
    axial end are set exactly, so the two pieces join C2.
    """

    kind = "isotensoid"
    _DS_MAX = 1.0 / 300.0  # knot spacing limit, fraction of R
    _DPSI_MAX = 0.008  # turning (rad) per knot interval, and the same for the curvature-scale terms

    def __init__(self, radius: float, c: float):
        self.radius, self.polar_opening, self.semi_axis = radius, c, None
        R = radius
        y0 = c / R  # work at R = 1, scale at the end
        a = (1.0 - y0) * (1.0 + y0)
        k = np.sqrt(a)
        sq = np.sqrt(a * a + 4.0 * a * y0 * y0)
        # r_*^2 = u, u the positive root of a u^2 + a u - y0^2 = 0; delta_* = r_* - c, both without
        # cancellation (u - y0^2 = 4 y0^6 / ((a + sq) (1 + y0^2 + sq))).
        ystar = np.sqrt(2.0 * y0 * y0 / (a + sq))
        dstar = 4.0 * y0**6 / ((a + sq) * (1.0 + y0 * y0 + sq)) / (ystar + y0)
        yinf = y0 * np.sqrt(1.5)

        def curvature(delta):  # f'(r), r = c + delta
            r = y0 + delta
            w = delta * (delta + 2.0 * y0)  # r^2 - c^2 without cancellation
            return k * r * r * (2.0 * r * r - 3.0 * y0 * y0) / (w * np.sqrt(w))

        psi_inf = float(np.arccos(k * yinf**3 / np.sqrt((yinf - y0) * (yinf + y0))))

        def rhs_a(_s, y):
            return np.array([-np.sin(y[2]), np.cos(y[2]), curvature(y[0] - y0)])

        def rhs_b(_u, y):
            return np.array([np.sin(y[2]), np.cos(y[2]), -curvature(dstar + y[0])])

        def reach_a(_s, y):
            return y[0] - yinf

        def reach_b(_u, y):
            return y[0] - (yinf - ystar)

        reach_a.terminal = reach_b.terminal = True
        reach_a.direction, reach_b.direction = -1, 1
        tiny = 1e-3 * min(dstar, 1.0)
        with np.errstate(invalid="ignore"):  # a rejected trial step may leave the domain
            sol_a = solve_ivp(rhs_a, (0.0, 10.0), [1.0, 0.0, 0.0], method="DOP853", rtol=3e-14,
                              atol=1e-15, events=reach_a, dense_output=True, first_step=1e-3)
            sol_b = solve_ivp(rhs_b, (0.0, 10.0), [0.0, 0.0, 0.0], method="DOP853", rtol=3e-14,
                              atol=[1e-13 * tiny, 1e-13 * tiny, 1e-15], events=reach_b,
                              dense_output=True, first_step=0.1 * dstar)
        for sol in (sol_a, sol_b):
            if sol.status != 1 or len(sol.t_events[0]) != 1:  # pragma: no cover - guarded by limits
                raise RuntimeError(f"isotensoid meridian integration failed: {sol.message}")
        sig_a, y_a = self._knots(sol_a, lambda y: curvature(y[0] - y0), -1.0, yinf)
        u_b, y_b = self._knots(sol_b, lambda y: curvature(dstar + y[0]), 1.0, yinf - ystar)
        # exact end data: equator, inflection (both sides), axial end
        y_a[:, 0] = (1.0, 0.0, 0.0)
        y_a[0, -1], y_a[2, -1] = yinf, psi_inf
        y_b[:, 0] = (0.0, 0.0, 0.0)
        y_b[0, -1], y_b[2, -1] = yinf - ystar, psi_inf

        kap_a = curvature(y_a[0] - y0)
        kap_a[-1] = 0.0
        sp, cp = np.sin(y_a[2]), np.cos(y_a[2])
        self._ra = _quintic_hermite(sig_a * R, y_a[0] * R, -sp, -cp * kap_a / R)
        self._ha = _quintic_hermite(sig_a * R, y_a[1] * R, cp, -sp * kap_a / R)
        kap_b = -curvature(dstar + y_b[0])  # d psi / du
        kap_b[-1] = 0.0
        sp, cp = np.sin(y_b[2]), np.cos(y_b[2])
        self._eb = _quintic_hermite(u_b * R, y_b[0] * R, sp, cp * kap_b / R)
        self._gb = _quintic_hermite(u_b * R, y_b[1] * R, cp, -sp * kap_b / R)
        self._pp = [p.derivative(j) if j else p for p in (self._ra, self._ha, self._eb, self._gb)
                    for j in (0, 1, 2)]
        self.sigma_inflection = float(sig_a[-1] * R)
        self.length = float((sig_a[-1] + u_b[-1]) * R)
        self.depth = float((y_a[1, -1] + y_b[1, -1]) * R)
        self.end_radius = float(ystar * R)
        self.clairaut = c
        self._tab_sigma = np.concatenate([sig_a * R, self.length - u_b[-2::-1] * R])
        self._tab_h = np.concatenate([y_a[1] * R, self.depth - y_b[1, -2::-1] * R])

    def _knots(self, sol, curvature, sign: float, target: float) -> tuple[np.ndarray, np.ndarray]:
        end = float(sol.t_events[0][0])
        steps = np.append(sol.t[sol.t < end], end)
        fine = steps[:-1, None] + np.diff(steps)[:, None] * np.linspace(0.0, 1.0, 17)[None, :-1]
        fine = np.append(fine.ravel(), end)
        kap = curvature(sol.sol(fine))
        # turning per knot, and the scale on which the curvature itself varies (the graded region
        # next to the end hook turns little but changes on the scale of its distance to the hook)
        kap1 = np.gradient(kap, fine)
        kap2 = np.gradient(kap1, fine)
        scale = np.abs(kap) + np.sqrt(np.abs(kap1)) + np.cbrt(np.abs(kap2))  # 1 / length, each term
        mon = 1.0 / self._DS_MAX + scale / self._DPSI_MAX
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (mon[1:] + mon[:-1]) * np.diff(fine))])
        n = max(32, int(np.ceil(cum[-1])))
        knots = np.interp(np.linspace(0.0, cum[-1], n + 1), cum, fine)
        knots[0], knots[-1] = 0.0, end
        knots = np.unique(knots)
        # Positions by 8-point Gauss-Legendre of (sin, cos)(psi) over each knot interval, psi from the
        # dense output: the increments are then accurate to dx * |psi error| (~1e-14 dx), so values,
        # slopes and curvatures given to the Hermite spline agree to that level. The interpolant's own
        # error (~1e-13 absolute) would, divided by dx^2, spoil the spline's curvature.
        xg, wg = np.polynomial.legendre.leggauss(8)
        half = 0.5 * np.diff(knots)
        psi_g = sol.sol((knots[:-1, None] + half[:, None] * (xg + 1.0)).ravel())[2]
        psi_g = psi_g.reshape(-1, 8)
        y = sol.sol(knots)
        y[0] = y[0, 0] + sign * np.concatenate([[0.0], np.cumsum((np.sin(psi_g) * wg).sum(1) * half)])
        y[1] = y[1, 0] + np.concatenate([[0.0], np.cumsum((np.cos(psi_g) * wg).sum(1) * half)])
        # the end value is known exactly (an event): spread the tiny residual linearly
        y[0] += (target - y[0, -1]) * knots / knots[-1]
        return knots, y

    def _eval2(self, sigma: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, ...]:
        out = np.empty((7,) + sigma.shape)
        m = sigma < self.sigma_inflection
        ra, ra1, ra2, ha, ha1, ha2, eb, eb1, eb2, gb, gb1, gb2 = self._pp
        if np.any(m):
            x = sigma[m]
            h = ha(x)
            out[:, m] = (self.depth - h, h, ha1(x), ha2(x), ra(x), ra1(x), ra2(x))
        m = ~m
        if np.any(m):
            x = u[m]
            g = gb(x)
            out[:, m] = (g, self.depth - g, gb1(x), -gb2(x), self.end_radius + eb(x), -eb1(x), eb2(x))
        return tuple(out)


def _kind(dome: Dome) -> str:
    return str(getattr(dome.type, "value", dome.type)).lower()


def make_dome(dome: Dome, radius: float, source: str, key: str) -> DomeMeridian:
    """One dome's meridian, from its config (key: its key path, e.g. "mandrel.profile.dome").

    Refuses with ConfigError what the geometry cannot do: a polar opening not in (0, R), a missing or
    degenerate ellipsoid depth, an isotensoid opening outside what netting theory can shape.
    """
    R = float(radius)
    kind = _kind(dome)
    r0 = dome.polar_opening
    if not (isinstance(r0, (int, float)) and np.isfinite(r0) and r0 > 0.0):
        raise ConfigError(f"{source}: {key}.polar_opening: must be a number > 0, got {r0}")
    r0 = float(r0)
    if not r0 < R:
        raise ConfigError(f"{source}: {key}.polar_opening: must be smaller than mandrel.profile.radius "
                          f"({R:g}), got {r0:g}")
    depth = dome.depth
    if kind != "ellipsoid" and depth is not None:
        raise ConfigError(f"{source}: {key}.depth: only an ellipsoid dome takes a depth "
                          f"(a {kind} dome's shape follows from radius and polar_opening), got {depth}")
    if kind == "hemisphere":
        return _Hemisphere(R, r0)
    if kind == "ellipsoid":
        if depth is None:
            raise ConfigError(f"{source}: {key}.depth: an ellipsoid dome needs depth, its axial "
                              f"semi-axis (> 0)")
        if not (isinstance(depth, (int, float)) and np.isfinite(depth) and depth > 0.0):
            raise ConfigError(f"{source}: {key}.depth: must be a number > 0, got {depth}")
        d = float(depth)
        if not ELLIPSOID_MIN_DEPTH * R <= d <= ELLIPSOID_MAX_DEPTH * R:
            raise ConfigError(f"{source}: {key}.depth: must be between {ELLIPSOID_MIN_DEPTH:g} and "
                              f"{ELLIPSOID_MAX_DEPTH:g} times mandrel.profile.radius "
                              f"({ELLIPSOID_MIN_DEPTH * R:g} to {ELLIPSOID_MAX_DEPTH * R:g}), got {d:g}")
        return _Ellipsoid(R, r0, d)
    if kind == "isotensoid":
        lo, hi = ISOTENSOID_MIN_OPENING * R, ISOTENSOID_MAX_OPENING * R
        if not lo <= r0 <= hi:
            raise ConfigError(f"{source}: {key}.polar_opening: an isotensoid dome needs polar_opening "
                              f"between {ISOTENSOID_MIN_OPENING:g} and {ISOTENSOID_MAX_OPENING:g} times "
                              f"mandrel.profile.radius ({lo:g} to {hi:g}; netting theory has no dome at "
                              f"or beyond sqrt(2/3) times the radius), got {r0:g}")
        return _Isotensoid(R, r0)
    raise ConfigError(f"{source}: {key}.type: must be hemisphere, ellipsoid or isotensoid, got {kind}")


class VesselRanges(NamedTuple):
    """Intervals of the internal station s covered by each part of a vessel."""

    dome: tuple[float, float]
    cylinder: tuple[float, float]
    end_dome: tuple[float, float]


@dataclass(frozen=True)
class VesselMeridian:
    """A vessel's meridian (z(s), r(s)), s the arc length from the first polar opening.

    s in [0, L1]: the first dome reversed, evaluated from its opening with u = s (z = D1 - h_dome(L1 - s)
    = the dome's drop at u = s); [L1, L1 + C]: the cylinder (r = R, z = s - L1 + D1); [L1 + C, length]:
    the end dome (z = D1 + C + h_end(s - L1 - C)). z(0) = 0 is the first opening's plane;
    z(length) = axial_length; z is clipped to [0, T] against round-off on [0, length]. The meridian is
    C1 (unit speed, tangent-continuous) everywhere; r2 (the meridian curvature) jumps at the two
    equators, as on every real vessel. At a junction itself the cylinder's values are returned.
    Outside [0, length] the end pieces are continued smoothly (not part of the mandrel).

    dome_ranges: the s-intervals of the dome, the cylinder and the end dome; equator_s / equator_t:
    s and t of the two dome/cylinder junctions; dome, end_dome: the DomeMeridian of each end.
    """

    radius: float
    cylinder_length: float
    dome: DomeMeridian
    end_dome: DomeMeridian

    @property
    def length(self) -> float:
        return self.dome.length + self.cylinder_length + self.end_dome.length

    @property
    def axial_length(self) -> float:
        return self.dome.depth + self.cylinder_length + self.end_dome.depth

    @property
    def reference_radius(self) -> float:
        return self.dome.end_radius

    @property
    def equator_s(self) -> tuple[float, float]:
        return (self.dome.length, self.dome.length + self.cylinder_length)

    @property
    def equator_t(self) -> tuple[float, float]:
        return (self.dome.depth, self.dome.depth + self.cylinder_length)

    @property
    def dome_ranges(self) -> VesselRanges:
        a, b = self.equator_s
        return VesselRanges((0.0, a), (a, b), (b, self.length))

    def evaluate(self, s: np.ndarray) -> ProfileEval:
        s = np.asarray(s, dtype=float)
        shape = s.shape
        s = s.ravel()
        a, b = self.equator_s
        d1, C = self.dome.depth, self.cylinder_length
        out = np.empty((6, s.size))
        # cylinder (also the default at the junctions)
        out[0] = d1 + (s - a)
        out[1], out[2] = 1.0, 0.0
        out[3], out[4], out[5] = self.radius, 0.0, 0.0
        m = s < a
        if np.any(m):
            g, e = self.dome.drop_and_evaluate_from_opening(s[m])
            out[:, m] = (g, e.h1, -e.h2, e.r, -e.r1, e.r2)
        m = s > b
        if np.any(m):
            e = self.end_dome.evaluate(s[m] - b)
            out[:, m] = (d1 + C + e.h, e.h1, e.h2, e.r, e.r1, e.r2)
        # round-off guard: t stays within [0, T] on [0, length]
        inside = (s >= 0.0) & (s <= self.length)
        out[0, inside] = np.clip(out[0, inside], 0.0, self.axial_length)
        return ProfileEval(*(o.reshape(shape) for o in out))

    def t_of_s(self, s: np.ndarray) -> np.ndarray:
        return self.evaluate(s).z

    def s_of_t(self, t: np.ndarray) -> np.ndarray:
        """Internal station s of the axial station t (clipped to [0, axial_length])."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.axial_length)
        shape = t.shape
        t = t.ravel()
        a, b = self.equator_s
        ta, tb = self.equator_t
        s = a + (t - ta)
        m = t < ta
        if np.any(m):
            s[m] = self.dome.u_of_drop(t[m])
        m = t > tb
        if np.any(m):
            s[m] = b + self.end_dome.sigma_of_h(t[m] - tb)
        return s.reshape(shape)


def make_vessel(cfg: VesselProfile, source: str) -> VesselMeridian:
    """The vessel meridian of a `vessel` profile config (profiles.make_profile calls this)."""
    R = cfg.radius
    if not (isinstance(R, (int, float)) and np.isfinite(R) and R > 0.0):
        raise ConfigError(f"{source}: mandrel.profile.radius: must be a number > 0, got {R}")
    C = cfg.cylinder_length
    if not (isinstance(C, (int, float)) and np.isfinite(C) and C >= 0.0):
        raise ConfigError(f"{source}: mandrel.profile.cylinder_length: must be a number >= 0, got {C}")
    end = cfg.end_dome if cfg.end_dome is not None else cfg.dome
    d1 = make_dome(cfg.dome, float(R), source, "mandrel.profile.dome")
    d2 = make_dome(end, float(R), source, "mandrel.profile.end_dome")
    return VesselMeridian(float(R), float(C), d1, d2)

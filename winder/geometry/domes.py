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
  so values, slopes and curvatures agree to ~1e-14 (see Isotensoid).

Accuracy, measured (R = 100): unit speed |h1^2 + r1^2 - 1| <= 1e-11 everywhere; ellipsoid arc length
vs ellipeinc ~1e-15 relative, points on the ellipse to 4e-16; isotensoid depth and length vs quadrature
of dh/dY ~1e-14 relative, end radius vs the closed-form root 1e-15, curvature vs netting theory
(R2/R1 = 2 - tan^2 alpha) 2e-9 of |k| + 1/R for c >= 0.1 R, 7e-8 at c = 0.02 R. Build: hemisphere
0.3 ms, ellipsoid 1 to 4 ms, isotensoid 10 to 70 ms (500 to 2500 knots).

The isotensoid's netting theory is in winder.geometry.isotensoid; the vessel built from two domes and
a cylinder in winder.geometry.vessel.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from winder.geometry.interp import jet

if TYPE_CHECKING:
    from scipy.interpolate import PPoly

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
    from scipy.interpolate import PPoly  # noqa: PLC0415 - only vessels have dome tables

    dx = np.diff(x)
    a0, a1, a2 = y[:-1], y1[:-1], 0.5 * y2[:-1]
    d0 = y[1:] - (a0 + a1 * dx + a2 * dx * dx)
    d1 = (y1[1:] - (y1[:-1] + y2[:-1] * dx)) * dx
    d2 = (y2[1:] - y2[:-1]) * dx * dx
    b3 = 10.0 * d0 - 4.0 * d1 + 0.5 * d2
    b4 = -15.0 * d0 + 7.0 * d1 - d2
    b5 = 6.0 * d0 - 3.0 * d1 + 0.5 * d2
    c = np.array([b5 / dx**5, b4 / dx**4, b3 / dx**3, a2, a1, a0])
    return PPoly(c, x)


def with_derivatives(pieces: list[PPoly]) -> PPoly:
    """One piecewise polynomial whose columns are each of `pieces` (sharing their knots, one column
    each) followed by its first and second derivatives: p0, p0', p0'', p1, ... (interp.jet): the
    planner reads domes a few points at a time inside root finders and ODEs (2x on an offset dome)."""
    return jet([(p, 2) for p in pieces])


def table_grid(lo: float, hi: float, step: float, knots: np.ndarray) -> np.ndarray:
    """A Hermite table's sites on [lo, hi]: the knots given (where a base's own pieces join, its higher
    derivatives jumping) and, between them, even sites at most `step` apart. Sites are never added
    next to a knot (two nearly equal sites would amplify the data's last bits by 1 / dx^2 in the
    piece's curvature), and a table built on a table keeps its size (the grown domes, layer on layer)."""
    sites = np.unique(np.concatenate([[lo, hi], np.clip(np.asarray(knots, dtype=float), lo, hi)]))
    gaps = np.diff(sites)
    # knots closer than a thousandth of the step to the one before are dropped (the same site)
    keep = np.concatenate([[True], gaps > 1e-3 * step])
    keep[-1] = True
    sites = sites[keep]
    if sites.size > 2 and sites[-1] - sites[-2] <= 1e-3 * step:
        sites = np.delete(sites, -2)
    gaps = np.diff(sites)
    parts = np.maximum(1, np.ceil(gaps / step - 1e-9)).astype(int)
    frac = np.concatenate([np.arange(m) / m for m in parts])
    start = np.repeat(sites[:-1], parts)
    width = np.repeat(gaps, parts)
    return np.append(start + frac * width, sites[-1])


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
    joints: tuple[float, ...] = ()  # sigma where the meridian's curvature jumps inside the dome
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


class Hemisphere(DomeMeridian):
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


class Ellipsoid(DomeMeridian):
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
        self._tau3, self._nu3 = with_derivatives([self._tau]), with_derivatives([self._nu])
        self.length = float(sig[-1])
        self.depth = d * float(np.sin(tau_end))
        self._tau_end = tau_end
        self.end_radius = r0
        self._tab_sigma = sig
        self._tab_h = d * np.sin(tau)

    def _eval2(self, sigma: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, ...]:
        te = self._tau_end
        far = u * 2.0 >= self.length  # equator half: tau(sigma); opening half: nu(u)
        near = ~far
        t, t1, t2, n = (np.empty_like(sigma) for _ in range(4))
        if np.any(far):
            x = sigma[far]
            t[far], t1[far], t2[far] = self._tau3(x).T
            n[far] = te - t[far]
        if np.any(near):
            x = u[near]
            nu, nu1, nu2 = self._nu3(x).T
            n[near], t1[near], t2[near] = nu, nu1, -nu2
            t[near] = te - n[near]
        s, c = np.sin(t), np.cos(t)
        R, d = self.radius, self.semi_axis
        g = 2.0 * d * np.cos(te - 0.5 * n) * np.sin(0.5 * n)  # d (sin(te) - sin(t))
        return (g, d * s, d * c * t1, d * (c * t2 - s * t1 * t1),
                R * c, -R * s * t1, -R * (s * t2 + c * t1 * t1))

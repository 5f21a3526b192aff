"""The netting isotensoid dome (see winder.geometry.domes for the meridian conventions).

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
"""

from __future__ import annotations

import numpy as np

from winder.geometry.domes import DomeMeridian, _quintic_hermite, with_derivatives


class Isotensoid(DomeMeridian):
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
        from scipy.integrate import solve_ivp  # noqa: PLC0415 - only where a meridian is integrated

        with np.errstate(invalid="ignore"):  # a rejected trial step may leave the domain
            sol_a = solve_ivp(rhs_a, (0.0, 10.0), [1.0, 0.0, 0.0], method="DOP853", rtol=3e-14, atol=1e-15,
                              events=[reach_a], dense_output=True, first_step=1e-3)
            sol_b = solve_ivp(rhs_b, (0.0, 10.0), [0.0, 0.0, 0.0], method="DOP853", rtol=3e-14,
                              atol=np.array([1e-13 * tiny, 1e-13 * tiny, 1e-15]), events=[reach_b],
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
        self._a = with_derivatives([self._ra, self._ha])  # r, r', r'', h, h', h'' before the inflection
        self._b = with_derivatives([self._eb, self._gb])  # e, e', e'', g, g', g'' after it, in u
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
        if np.any(m):
            ra, ra1, ra2, ha, ha1, ha2 = self._a(sigma[m]).T
            out[:, m] = (self.depth - ha, ha, ha1, ha2, ra, ra1, ra2)
        m = ~m
        if np.any(m):
            eb, eb1, eb2, gb, gb1, gb2 = self._b(u[m]).T
            out[:, m] = (gb, self.depth - gb, gb1, -gb2, self.end_radius + eb, -eb1, eb2)
        return tuple(out)

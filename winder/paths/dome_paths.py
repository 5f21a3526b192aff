"""Friction-held turnarounds on vessel domes (docs/math/07-friction.md): the turnaround radius a geodesic cannot reach.

On a surface of revolution, with s the meridian arc length, r(s), z(s), and alpha the heading from
the meridian (toward increasing theta), a fiber of slippage lambda obeys, per unit fiber length l,

    ds/dl = cos(alpha),  dtheta/dl = sin(alpha) / r,  dalpha/dl = lambda k_n - r' sin(alpha) / r,
    k_n = kappa_m cos^2(alpha) + z' sin^2(alpha) / r,  kappa_m = r' z'' - z' r'' (convex: > 0),

(docs/math/07-friction.md's d(alpha)/dz per unit length; lambda = 0 keeps r sin(alpha), Clairaut). It is regular
at the turnaround (cos(alpha) = 0), where it stops. The profile alone is evaluated, never the 3D
surface, so a leg costs a few milliseconds. A leg runs from an equator toward the pole; the pass
leaves the turnaround along its mirror image (the dome is symmetric about the turnaround meridian,
and reflection with reversal keeps lambda), so the turnaround is a smooth, friction-held reversal.

solve_slip: the constant lambda whose leg turns at radius c (Chandrupatla). close_leg: lambda(l) =
lambda0 + lambda1 (l / l0 - 1/2) turning at c and advancing a given theta (Newton), so that a
pattern closes with the cylinder angle and the turnaround radius both kept.
"""

from __future__ import annotations

import bisect
import dataclasses
import functools
import math
from dataclasses import field
from typing import Callable

import numpy as np

from winder.errors import SolverError

# The turnaround radius is the end of a long integration: on a grown dome (whose meridian's curvature
# carries the laminate's growth spline) rtol 1e-9 leaves it noisy by ~1e-5 mm from one lambda to the
# next, ten times RADIUS_TOL, and the root finders below then spend tens of traces inside the noise.
# At 1e-11 the noise is ~2e-7 mm (measured on tank_20's layer 13) for ~1.3x the steps of a trace.
RTOL = 1e-11
SLIP_BOUND = 1.0  # the search for lambda stays within this (a friction coefficient)
RADIUS_TOL = 1e-6  # mm: turnaround radius solves
ADVANCE_TOL = 1e-8  # rad
MAX_NEWTON = 20
FD_STEP = 1e-4  # lambda step of the finite-difference Jacobian of close_leg
# On a grown dome the traced turnaround moves by ~1e-4 mm between lambdas 1e-7 apart (the adaptive
# steps of the trace): past MAX_NEWTON, close_leg keeps its best step if it is within these.
RADIUS_ACCEPT = 1e-3  # mm
ADVANCE_ACCEPT = 1e-6  # rad (1e-4 mm a circuit on a 100 mm dome)


MERIDIAN_SAMPLES = 1201  # per dome: the quintic table's error is far below the integrator's


class DomeMeridian:
    """One dome's meridian as a quintic spline table of (r, z) in s: a leg evaluates it thousands of
    times, and the table costs a tenth of the profile's own evaluation. s in [lo, hi] (clipped).

    The integrator asks for one station at a time, where a scipy spline call costs tens of
    microseconds: each piece of the spline is kept as its Taylor coefficients about the piece's
    middle (plain floats) and read by Horner's rule (the same polynomials, to round-off)."""

    def __init__(self, profile, lo: float, hi: float):
        from scipy.interpolate import make_interp_spline  # noqa: PLC0415

        s = np.linspace(lo, hi, MERIDIAN_SAMPLES)
        pe = profile.evaluate(s)
        spline = make_interp_spline(s, np.column_stack([pe.r, pe.z]), k=5)
        self.lo, self.hi, self.length = lo, hi, profile.length
        breaks = np.unique(spline.t[5:-5])
        mid = 0.5 * (breaks[:-1] + breaks[1:])
        d = [spline(mid, j) for j in range(6)]  # (pieces, 2) each: r and z and their derivatives
        r, z = [[d[j][:, c] for j in range(6)] for c in (0, 1)]
        # per piece: r's Taylor coefficients c0..c5, then those of r' and r'' and of z' and z''
        table = np.column_stack([
            r[0], r[1], r[2] / 2, r[3] / 6, r[4] / 24, r[5] / 120,
            r[1], r[2], r[3] / 2, r[4] / 6, r[5] / 24,
            r[2], r[3], r[4] / 2, r[5] / 6,
            z[1], z[2], z[3] / 2, z[4] / 6, z[5] / 24,
            z[2], z[3], z[4] / 2, z[5] / 6])
        self._inner = breaks[1:-1].tolist()  # a station's piece: bisect in these
        self._mid = mid.tolist()
        self._table = [tuple(row) for row in table.tolist()]

    def at(self, s: float) -> tuple[float, float, float, float, float]:
        """r, r', r'', z', z'' at station s."""
        s = min(max(float(s), self.lo), self.hi)
        i = bisect.bisect_right(self._inner, s)
        h = s - self._mid[i]
        (a0, a1, a2, a3, a4, a5, b0, b1, b2, b3, b4, c0, c1, c2, c3,
         p0, p1, p2, p3, p4, q0, q1, q2, q3) = self._table[i]
        r = a0 + h * (a1 + h * (a2 + h * (a3 + h * (a4 + h * a5))))
        r1 = b0 + h * (b1 + h * (b2 + h * (b3 + h * b4)))
        r2 = c0 + h * (c1 + h * (c2 + h * c3))
        z1 = p0 + h * (p1 + h * (p2 + h * (p3 + h * p4)))
        z2 = q0 + h * (q1 + h * (q2 + h * q3))
        return r, r1, r2, z1, z2


def dome_meridian(profile, end: bool) -> DomeMeridian:
    """The table of the first dome (end False) or of the end dome."""
    e1, e2 = profile.equator_s
    return DomeMeridian(profile, e2, profile.length) if end else DomeMeridian(profile, 0.0, e1)


@dataclasses.dataclass(frozen=True, eq=False)
class Leg:
    """A fiber from an equator to its turnaround (or to the opening, if it does not turn).

    turned : it reached alpha = 90 deg. radius : r there (mm). advance : theta gained (rad).
    length : fiber length (mm). state : dense output l -> (s, theta, alpha). slip : lambda(l).
    """

    turned: bool
    radius: float
    advance: float
    length: float
    state: Callable[[np.ndarray], np.ndarray] = field(repr=False)
    slip: Callable[[np.ndarray], np.ndarray] = field(repr=False)


def trace_leg(meridian: DomeMeridian, s_eq: float, heading: float, slip: Callable[[np.ndarray], np.ndarray]) -> Leg:
    """Trace from the equator station s_eq at heading (rad; toward the pole: cos(heading) points there)."""
    s_max = meridian.length

    def fun(l, y):
        r, r1, r2, z1, z2 = meridian.at(y[0])
        ca, sa = math.cos(y[2]), math.sin(y[2])
        k_n = (r1 * z2 - z1 * r2) * ca * ca + z1 * sa * sa / r
        return [ca, sa / r, float(slip(l)) * k_n - r1 * sa / r]

    def turn(_l, y):
        return math.cos(y[2])

    def opening(_l, y):
        return min(y[0], s_max - y[0])

    turn.terminal = opening.terminal = True
    turn.direction = -math.copysign(1.0, math.cos(heading))
    opening.direction = -1.0
    span = 4.0 * s_max
    from scipy.integrate import solve_ivp  # noqa: PLC0415 - only where a path is traced

    res = solve_ivp(fun, (0.0, span), [s_eq, 0.0, heading], method="DOP853", rtol=RTOL, atol=RTOL,
                    dense_output=True, events=(turn, opening), first_step=1e-3)
    # Turned the way it winds: a fiber pushed across the meridian (alpha through 0) turns the other way.
    turned = bool(res.t_events[0].size) and math.sin(res.y[2, -1]) * math.sin(heading) > 0.0
    s_end = float(np.clip(res.y[0, -1], 0.0, s_max))
    radius = meridian.at(s_end)[0]
    return Leg(turned, radius, float(res.y[1, -1]), float(res.t[-1]), res.sol, slip)


def _constant(lam: float) -> Callable[[np.ndarray], np.ndarray]:
    return lambda l: np.full(np.shape(l), lam) if np.ndim(l) else lam


def solve_slip(meridian: DomeMeridian, s_eq: float, heading: float, c: float,
               bound: float = SLIP_BOUND) -> tuple[float, Leg]:
    """The constant lambda (|lambda| <= bound) whose leg turns at r = c, and that leg. A bound of the
    friction fails fast (three traces) where the friction cannot turn it there."""
    trace = functools.cache(lambda lam: trace_leg(meridian, s_eq, heading, _constant(lam)))

    def miss(lam: float) -> float:
        leg = trace(lam)
        # A leg that does not turn (it reaches the opening, or is pushed across the meridian) counts as
        # turning further in than any radius: the bracket then holds the root.
        return leg.radius - c if leg.turned else -c - 1.0

    f_lo, f_0, f_hi = miss(-bound), miss(0.0), miss(bound)
    no_root = SolverError(f"no slippage |k_g / k_n| <= {bound:g} turns the fiber at r = {c:.4g} mm on this dome")
    if f_lo * f_hi > 0.0:
        raise no_root
    for lam, f in ((0.0, f_0), (-bound, f_lo), (bound, f_hi)):
        if abs(f) < RADIUS_TOL:
            return lam, trace(lam)
    from scipy.optimize.elementwise import find_root  # noqa: PLC0415 - slow to import: only vessels

    # The half of the bracket whose ends differ in sign (each end's trace is kept by the cache). It
    # stops once the radius is within the tolerance: closer, the traces' own error decides.
    bracket = (-bound, 0.0) if f_lo * f_0 < 0.0 else (0.0, bound)
    res = find_root(np.vectorize(miss, otypes=[float]), bracket,
                    tolerances={"xatol": 1e-12, "xrtol": 1e-12, "fatol": 0.25 * RADIUS_TOL})
    lam = float(res.x)
    if not (res.success and math.isfinite(lam)):
        raise no_root
    leg = trace(lam)
    # A bracket closed on a jump (a leg that stops turning) converges too: the leg must turn at c.
    if not leg.turned or abs(leg.radius - c) > RADIUS_TOL:
        raise no_root
    return lam, leg


# |det J| below this times max|J_ij|^2: the Jacobian has no rank 2 (a helical at 89.99 deg turns at
# the equator, its dome leg of no length: lambda moves nothing), and Newton has no step.
SINGULAR_JACOBIAN = 1e-12


def _linear(lam0: float, lam1: float, l0: float) -> Callable[[np.ndarray], np.ndarray]:
    return lambda l: lam0 + lam1 * (np.asarray(l) / l0 - 0.5)


def close_leg(meridian: DomeMeridian, s_eq: float, heading: float, c: float, lam0: float, l0: float,
              advance: float, start: Leg | None = None) -> tuple[float, float, Leg]:
    """lambda0, lambda1 of lambda(l) = lambda0 + lambda1 (l / l0 - 1/2) whose leg turns at r = c after
    advancing `advance` rad; Newton from (lam0, 0) with a finite-difference Jacobian. start: the leg
    of the constant lam0 when the caller has traced it."""
    x = np.array([lam0, 0.0])

    def residual(leg: Leg):
        return (np.array([leg.radius - c, leg.advance - advance]) if leg.turned else None), leg

    def res(v):
        return residual(trace_leg(meridian, s_eq, heading, _linear(v[0], v[1], l0)))

    f, leg = res(x) if start is None else residual(start)
    if f is None:
        raise SolverError("a dome leg stopped turning around while the pattern was closed")
    jac = np.empty((2, 2))
    for k in range(2):
        step = np.zeros(2)
        step[k] = FD_STEP
        fk, _ = res(x + step)
        if fk is None:
            raise SolverError("a dome leg stopped turning around while the pattern was closed")
        jac[:, k] = (fk - f) / FD_STEP
    best = (abs(f[0]) / RADIUS_ACCEPT + abs(f[1]) / ADVANCE_ACCEPT, x, leg)
    for _ in range(MAX_NEWTON):
        if abs(f[0]) < RADIUS_TOL and abs(f[1]) < ADVANCE_TOL:
            return float(x[0]), float(x[1]), leg
        if (score := abs(f[0]) / RADIUS_ACCEPT + abs(f[1]) / ADVANCE_ACCEPT) < best[0]:
            best = (score, x, leg)
        if abs(np.linalg.det(jac)) <= SINGULAR_JACOBIAN * float(np.abs(jac).max()) ** 2:
            break  # lambda moves neither the turnaround nor the advance (a leg of no length): no Newton step
        dx = np.linalg.solve(jac, -f)
        f_new, leg = res(x + dx)
        if f_new is None:
            break
        # Broyden's update: one trace per step after the first Jacobian.
        jac += np.outer(f_new - f - jac @ dx, dx) / float(dx @ dx)
        x, f = x + dx, f_new
    if abs(best[2].radius - c) < RADIUS_ACCEPT and abs(best[2].advance - advance) < ADVANCE_ACCEPT:
        return float(best[1][0]), float(best[1][1]), best[2]
    raise SolverError(f"the dome turnaround at r = {c:.4g} mm could not be fitted to close the pattern")

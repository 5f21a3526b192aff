"""Geodesics on open surfaces of revolution by Clairaut's relation, without a two-point solve.

Along a geodesic sqrt(G) sin(h) = c (h the heading from the meridian, G = |Phi_theta|^2, E = |Phi_s|^2),
so along the travel

    d theta / ds = c sqrt(E) / (sqrt(G) sqrt(G - c^2)),    d sigma / ds = sqrt(E) sqrt(G) / sqrt(G - c^2),

sigma the arc length (docs/math/04-checks.md; docs/math/12-exact-eye.md 12.1). Where the fiber comes close to its
turnaround (G -> c^2 at an end of the stretch) both integrands have a 1/sqrt singularity; a change of
variable s = s0 + D (1 - (1 - u)^2) (at the far end; u^2 at the near one, both together the smoothstep
3u^2 - 2u^3) puts a factor (1 - u) into ds/du that cancels it, so composite Gauss-Legendre converges as
on a smooth integrand whether the turnaround lies just past the end or on it. A pass is then exact to
the quadrature's tolerance: its points on the geodesic, its direction from Clairaut's heading.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from winder.errors import SolverError
from winder.geometry.measure import row_norms
from winder.geometry.surface import SweepSurface

GAUSS_X, GAUSS_W = np.polynomial.legendre.leggauss(8)
TOL = 1e-12  # relative agreement of two subdivisions (of the largest cumulative value)
FIRST_SUB = 16  # sub-panels of a lone interval at the first level (the whole stretch: the turn integral)
MAX_NODES = 1 << 22  # quadrature nodes at the finest subdivision
EPS = float(np.finfo(float).eps)
ROOM_ULPS = 4.0  # G's round-off in units in the last place (a radius squared from the profile and section)
NOISE_MARGIN = 4.0  # two levels agree when they differ by no more than this times their round-off
# An end where G - c^2 is below this share of G (the heading above 71.6 deg) gets the change of variable.
SINGULAR_SHARE = 0.1
DISTRIBUTION_SUB = 8  # Gauss panels per pass interval for the arc length that spaces the points


def turnaround_error(surface: SweepSurface, s_turn: float, heading_deg: float) -> SolverError:
    turn = float(surface.t_of_s(np.array([s_turn]))[0])
    return SolverError(f"the geodesic at {heading_deg:.4g} deg turns around at t = {turn:.4g} mm before "
                       f"reaching the end of the winding region (Clairaut: r sin(alpha) is constant, so "
                       f"it cannot reach a smaller radius)")


def _metric(surface: SweepSurface, s: np.ndarray, c: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(E, G, G - c^2) at stations s (m,) on a surface of revolution (any theta serves)."""
    ev = surface.evaluate(s, np.zeros_like(s), order=1, with_point=False)
    g = np.einsum("ij,ij->i", ev.pt, ev.pt)
    return np.einsum("ij,ij->i", ev.ps, ev.ps), g, g - c * c


def _quartic(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(B(u), B'(u)) of B(u) = 35 u^4 - 84 u^5 + 70 u^6 - 20 u^7, from 0 to 1 with B' = 140 u^3 (1 - u)^3."""
    return u ** 4 * (35.0 + u * (-84.0 + u * (70.0 - 20.0 * u))), 140.0 * (u * (1.0 - u)) ** 3


def substitution(surface: SweepSurface, s0: float, s1: float, c: float) -> Callable[[np.ndarray], tuple]:
    """u in [0, 1] -> (s, |ds/du|) from s0 to s1, with s - s_end ~ (u - u_end)^4 at an end where the fiber
    nears its turnaround: G - c^2 = eps + a (s - s_end) there, so the integrands times ds/du behave as
    x^3 / sqrt(eps + a x^4), smooth at eps = 0 and bent over a width (eps / a)^(1/4) in u otherwise
    (a square law's (eps / a)^(1/2) was 1e-7 wide for a turnaround 1e-13 inside the end)."""
    _, g, room = _metric(surface, np.array([s0, s1]), c)
    near0, near1 = (bool(v) for v in room < SINGULAR_SHARE * g)
    d = s1 - s0

    def of(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if near0 and near1:
            b, b1 = _quartic(u)
            return s0 + d * b, abs(d) * b1
        if near1:
            return s1 - d * (1.0 - u) ** 4, abs(d) * 4.0 * (1.0 - u) ** 3
        if near0:
            return s0 + d * u ** 4, abs(d) * 4.0 * u ** 3
        return s0 + d * u, np.full_like(u, abs(d))

    return of


def _rates(surface: SweepSurface, c: float, s: np.ndarray, heading_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """((m, 2): d theta / ds and d sigma / ds at s (m,), (m,): their relative round-off); a station past
    the turnaround is refused. G - c^2 cancels next to the turnaround: G's last bits over the room left
    are the rates' own error there (1e-4 of them 1e-3 of the stretch from a turnaround on its end)."""
    e, g, room = _metric(surface, s, c)
    if np.any(room <= 0.0):
        raise turnaround_error(surface, _turn_station(surface, c, s, room), heading_deg)
    root = np.sqrt(e / room)
    return np.column_stack([c * root / np.sqrt(g), root * np.sqrt(g)]), ROOM_ULPS * EPS * g / room


def _panels(surface: SweepSurface, c: float, of, lo: np.ndarray, hi: np.ndarray, sub: int,
            heading_deg: float) -> np.ndarray:
    """(k, 3): the turn and the arc length over each interval [lo, hi] (k,) in u, by sub Gauss panels, and
    the turn's round-off (the sum of its terms' own)."""
    cuts = lo[:, None] + (hi - lo)[:, None] * np.linspace(0.0, 1.0, sub + 1)
    half = 0.5 * np.diff(cuts, axis=1)
    nodes = (0.5 * (cuts[:, 1:] + cuts[:, :-1]))[..., None] + half[..., None] * GAUSS_X
    s, rate = of(nodes.reshape(-1))
    f, noise = _rates(surface, c, s, heading_deg)
    f *= rate[:, None]
    f = np.concatenate([f, np.abs(f[:, :1]) * noise[:, None]], axis=1)
    return (np.einsum("ijkl,k->ijl", f.reshape(*nodes.shape, 3), GAUSS_W) * half[..., None]).sum(axis=1)


def _turn_station(surface: SweepSurface, c: float, s: np.ndarray, room: np.ndarray) -> float:
    """Where G = c^2 first along the travel from the stretch's start (the nodes s (m,) with their room
    G - c^2 (m,), some <= 0; the start is the positive node farthest from every non-positive one)."""
    from scipy.optimize import brentq  # noqa: PLC0415 - refusals only

    out, inside = s[room <= 0.0], s[room > 0.0]
    start = float(inside[np.argmax(np.min(np.abs(inside[:, None] - out[None, :]), axis=1))]) if inside.size else s[0]
    past = float(out[np.argmin(np.abs(out - start))])
    if not inside.size:
        return past
    return float(brentq(lambda v: float(_metric(surface, np.array([v]), c)[2][0]), start, past, xtol=1e-9))


def cumulative(surface: SweepSurface, c: float, s0: float, s1: float, u: np.ndarray, heading_deg: float,
               sub: int = 1) -> np.ndarray:
    """The turn and the arc length (rad, mm) from s0 to each u (k,) (u[0] = 0, increasing) along the
    geodesic of Clairaut constant c: (k, 2), both growing along the travel. Each interval's sub panels
    are doubled until two subdivisions agree within TOL of the whole (only the intervals that differ)."""
    of = substitution(surface, s0, s1, c)
    lo, hi = u[:-1], u[1:]
    per = _panels(surface, c, of, lo, hi, sub, heading_deg)
    active = np.arange(lo.size)
    while True:
        sub *= 2
        finer = _panels(surface, c, of, lo[active], hi[active], sub, heading_deg)
        change = np.abs(finer - per[active])[:, :2]
        per[active] = finer
        total = np.abs(per[:, :2].sum(axis=0))
        # agreement within TOL of the whole, or within the two levels' round-off (the turn's, scaled)
        floor = (finer[:, 2] + np.abs(per[active, 2]))[:, None] * np.array([1.0, total[1] / max(total[0], 1e-300)])
        moving = np.any(change > np.maximum(TOL * total, NOISE_MARGIN * floor), axis=1)
        if not np.any(moving):
            return np.concatenate([np.zeros((1, 2)), np.cumsum(per[:, :2], axis=0)])
        active = active[moving]
        if active.size * sub * 2 * GAUSS_X.size > MAX_NODES:
            raise SolverError(f"the geodesic's turn integral did not settle ({float(np.max(change[:, 0])):.2g} rad "
                              f"apart at {sub} panels an interval): the profile is too rough near the turnaround")


def turn(surface: SweepSurface, s0: float, s1: float, c: float, heading_deg: float) -> float:
    """theta(s1) - theta(s0) along the geodesic of Clairaut constant c > 0 from s0 to s1, signed as the
    integral from s0 to s1 (theta grows with s along one helix)."""
    value = float(cumulative(surface, c, s0, s1, np.array([0.0, 1.0]), heading_deg, FIRST_SUB)[-1, 0])
    return value if s1 >= s0 else -value


def revolution_pass(surface: SweepSurface, s0: float, s1: float, theta0: float, c: float, n: int,
                    heading_deg: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """The geodesic pass from (s0, theta0) to station s1 with Clairaut constant c > 0, theta growing
    along the travel: n interior points about evenly spaced in arc length. Returns s, theta (n + 2,)
    float, the unit tangents (n + 2, 3) float (the heading sin(h) = c / sqrt(G)) and the length (mm)."""
    of = substitution(surface, s0, s1, c)
    grid = np.linspace(0.0, 1.0, DISTRIBUTION_SUB * (n + 1) + 1)
    arc = cumulative(surface, c, s0, s1, grid, heading_deg)[:, 1]
    u = np.interp(np.linspace(0.0, arc[-1], n + 2), arc, grid)
    u[0], u[-1] = 0.0, 1.0
    both = cumulative(surface, c, s0, s1, u, heading_deg)
    s = of(u)[0]
    s[-1] = s1
    theta = theta0 + both[:, 0]
    ev = surface.evaluate(s, theta, order=1, with_point=False)
    g = np.einsum("ij,ij->i", ev.pt, ev.pt)
    sin_h = np.minimum(c / np.sqrt(g), 1.0)
    cos_h = np.sqrt(np.maximum(1.0 - sin_h * sin_h, 0.0)) * math.copysign(1.0, s1 - s0)
    d = ev.ps / row_norms(ev.ps)[:, None] * cos_h[:, None] + ev.pt / np.sqrt(g)[:, None] * sin_h[:, None]
    return s, theta, d, float(both[-1, 1])

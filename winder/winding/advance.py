"""Where a geodesic at a given winding angle reaches a station, without integrating the ODE step by step.

On two kinds of open mandrel the metric is diagonal, E ds^2 + G dtheta^2, with E and G each a function
of one variable, and the geodesic's theta at a station is one integral, evaluated in a few vectorized
surface evaluations instead of thousands of single-point ones (docs/math/04-checks.md):

- a surface of revolution (straight axis, circular section, any profile r(s)): Clairaut, sqrt(G) sin(alpha)
  = c along the path, so dtheta/ds = c sqrt(E) / (sqrt(G) sqrt(G - c^2)); composite Gauss-Legendre,
  panels doubled until two levels agree. The path turns around where sqrt(G) = c.
- a general cylinder (straight axis, one section at every station, any shape): developable; unrolled,
  the path is a straight line at the angle alpha to the generators, so the arc run along the section is
  tan(alpha) sqrt(E) (s1 - s0), and theta follows from the section's arc length, tabulated once finely
  (trapezoid, exact inverse of its piecewise-linear speed).

Elsewhere (a bent axis, a section that changes with the station) reach_theta returns None and the caller
traces the geodesic.
"""

from __future__ import annotations

import math

import numpy as np

from winder.winding.clairaut import turn, turnaround_error
from winder.geometry.sections import ArcMap
from winder.geometry.surface import SweepSurface
from winder.geometry.measure import row_norms

ARC_SAMPLES = 1 << 18  # per turn: trapezoid error ~ h^2 w'' / 12, about 1e-10 of the perimeter
CONSTANT_GRID = 257  # stations where a profile must be flat for the section to be the same everywhere
# The relative spread of a section's size over a region within which the mandrel is wound as a cylinder
# (near_cylinder): a laminate's thickness varies by the bands' overlaps, a taper by far more.
NEAR_CYLINDER_SPREAD = 1e-4
# A laminate grown on a straight tube changes its size by a ply or two near a layer's edge: within this
# spread the passes stay unrolled lines, their slip measured exactly (a solve over such an edge on a box
# section stalled), beyond it (a taper) they are solved.
LAMINATE_SPREAD = 1e-2


def is_cylinder(surface: SweepSurface) -> bool:
    """A straight axis and the same section at every station (no profile, or a flat one)."""
    if not surface.curve.is_straight:
        return False
    if surface.profile is None:
        return True
    if not surface.is_axial_parameter:
        return False
    ev = surface.profile.evaluate(np.linspace(0.0, surface.length, CONSTANT_GRID))
    return bool(np.all(ev[4] == 0.0) and np.all(ev[1] == 1.0))


def near_cylinder(surface: SweepSurface, t_a: float, t_b: float, spread: float = NEAR_CYLINDER_SPREAD) -> bool:
    """A straight axis whose section keeps its size over [t_a, t_b] within NEAR_CYLINDER_SPREAD: a
    cylinder, or one grown by a laminate whose thickness varies only by the bands' overlaps (2e-6 of
    the section on a box tube). On such a mandrel the unrolled line (cylinder_pass) is the geodesic, or
    a path whose geodesic curvature is of the order of that spread, held by any friction (the slip
    check measures it)."""
    if is_cylinder(surface):
        return True
    if not (surface.curve.is_straight and surface.is_axial_parameter):
        return False
    p = surface.profile.evaluate(surface.s_of_t(np.linspace(t_a, t_b, CONSTANT_GRID)))[3]
    return bool(np.ptp(p) <= spread * float(np.max(p)))


def _clairaut(surface: SweepSurface, s0: float, s1: float, alpha: float, heading_deg: float) -> float:
    """theta(s1) - theta(s0) along the geodesic leaving station s0 at winding angle alpha (rad, toward s1)."""
    ev0 = surface.evaluate(np.array([s0]), np.array([0.0]), order=1)
    c = float(np.linalg.norm(ev0.pt[0])) * math.sin(alpha)
    if c == 0.0:
        return 0.0
    return math.copysign(1.0, c) * turn(surface, s0, s1, abs(c), heading_deg)


def _cylinder_theta(surface: SweepSurface, s0: float, theta0: np.ndarray, run: float) -> np.ndarray:
    """theta where the arc run (mm, signed: + toward increasing theta) along the section from theta0
    ends, the same at every station. theta0 (k,) float; returns (k,)."""
    grid = np.linspace(0.0, 2.0 * np.pi, ARC_SAMPLES + 1)
    h = grid[1]
    w = row_norms(surface.evaluate(np.full(grid.size, s0), grid, order=1).pt)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * h * (w[1:] + w[:-1]))])
    per = cum[-1]
    # the arc from theta = 0 to theta0, with the speed linear over each interval of the table
    turns = np.floor(theta0 / (2.0 * np.pi))
    phi = theta0 - 2.0 * np.pi * turns
    j = np.minimum((phi / h).astype(int), ARC_SAMPLES - 1)
    u = phi - grid[j]
    dw = w[j + 1] - w[j]
    target = turns * per + cum[j] + w[j] * u + dw * u * u / (2.0 * h) + run
    # and back: w_j u + dw u^2 / (2 h) = r in the interval that holds the target, the root without cancellation
    turns = np.floor(target / per)
    rest = target - turns * per
    j = np.clip(np.searchsorted(cum, rest, side="right") - 1, 0, ARC_SAMPLES - 1)
    r, dw = rest - cum[j], w[j + 1] - w[j]
    u = 2.0 * r / (w[j] + np.sqrt(np.maximum(w[j] * w[j] + 2.0 * dw * r / h, 0.0)))
    return 2.0 * np.pi * turns + grid[j] + u


def reach_theta(surface: SweepSurface, s0: float, theta0: np.ndarray, heading_deg: float,
                s1: float) -> np.ndarray | None:
    """theta where the geodesic from (s0, theta0) at heading_deg reaches station s1, for each start
    theta0 (k,) float; None where the mandrel is of neither kind (trace the geodesic there).

    heading_deg is measured from the direction of increasing s toward increasing theta and must point
    toward s1 (|heading| < 90 deg for s1 > s0, the reverse for s1 < s0).
    """
    theta0 = np.atleast_1d(np.asarray(theta0, dtype=float))
    if s1 == s0:
        return theta0.copy()
    alpha = math.radians(heading_deg)
    forward = s1 > s0
    # the angle from the direction of travel along s: alpha, or alpha - 180 deg going back
    lean = alpha if forward else alpha - math.pi
    lean = math.atan2(math.sin(lean), math.cos(lean))
    if abs(lean) >= 0.5 * math.pi:
        return None
    if surface.is_revolution:
        # theta grows with s on both legs of the same helix: the integral from s0 to s1 carries the sign
        return theta0 + _clairaut(surface, s0, s1, lean, heading_deg)
    if is_cylinder(surface):
        return cylinder_reach(surface, s0, theta0, lean, s1)
    return None


def cylinder_reach(surface: SweepSurface, s0: float, theta0: np.ndarray, lean: float, s1: float) -> np.ndarray:
    """theta where the unrolled line from (s0, theta0) (k,) leaning `lean` (rad, from the direction of
    travel along s toward increasing theta) reaches station s1: the geodesic on a cylinder (near_cylinder)."""
    ev = surface.evaluate(np.array([s0]), theta0[:1], order=1)
    axial = float(np.linalg.norm(ev.ps[0])) * abs(s1 - s0)
    run = math.tan(lean) * axial * (1.0 if s1 > s0 else -1.0)
    return _cylinder_theta(surface, s0, theta0, run)


def cylinder_pass(surface: SweepSurface, arcs: ArcMap, a: tuple[float, float], b: tuple[float, float],
                  n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """The geodesic from a to b ((t, theta) each) on a general cylinder (near_cylinder), exactly: unrolled,
    the surface is a plane in which the station and the section's arc length are Cartesian coordinates,
    so the geodesic is the straight line between the ends and its points at equal steps of the station
    and of the arc-length fraction are equally spaced along it (docs/math/04-checks.md; docs/math/12-exact-eye.md
    12.2). No iteration: the variational solver's answer at any n tends to this.

    n : interior points. Returns s, theta (n + 2,) float, the unit tangents (n + 2, 3) float (the line's
    one direction carried onto the surface at each point) and the length (mm).
    """
    s0, s1 = (float(v) for v in surface.s_of_t(np.array([a[0], b[0]])))
    f0, f1 = (float(v) for v in arcs.fraction(np.array([a[1], b[1]])))
    u = np.linspace(0.0, 1.0, n + 2)
    s, theta = s0 + (s1 - s0) * u, arcs.theta(f0 + (f1 - f0) * u)
    ev = surface.evaluate(s, theta, order=1, with_point=False)
    d = ev.ps * (s1 - s0) + ev.pt * ((f1 - f0) * arcs.dtheta_dfrac(theta))[:, None]
    axial = float(row_norms(ev.ps[:1])[0]) * abs(s1 - s0)
    run = float(np.mean(surface.perimeter(s))) * abs(f1 - f0)  # the section's, constant on a cylinder
    return s, theta, d / row_norms(d)[:, None], math.hypot(axial, run)

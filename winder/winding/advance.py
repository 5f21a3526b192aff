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

from winder.errors import SolverError
from winder.geometry.surface import SweepSurface
from winder.geometry.measure import row_norms

GAUSS_X, GAUSS_W = np.polynomial.legendre.leggauss(8)
CLAIRAUT_PANELS = 16  # first level; doubled until two levels agree
CLAIRAUT_MAX_PANELS = 1 << 15
CLAIRAUT_TOL = 1e-13  # relative agreement of two levels (radians)
ARC_SAMPLES = 1 << 18  # per turn: trapezoid error ~ h^2 w'' / 12, about 1e-10 of the perimeter
CONSTANT_GRID = 257  # stations where a profile must be flat for the section to be the same everywhere


def turnaround_error(surface: SweepSurface, s_turn: float, heading_deg: float) -> SolverError:
    turn = float(surface.t_of_s(np.array([s_turn]))[0])
    return SolverError(f"the geodesic at {heading_deg:.4g} deg turns around at t = {turn:.4g} mm before "
                       f"reaching the end of the winding region (Clairaut: r sin(alpha) is constant, so "
                       f"it cannot reach a smaller radius); lower the angle or shorten the region")


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


def _clairaut(surface: SweepSurface, s0: float, s1: float, alpha: float, heading_deg: float) -> float:
    """theta(s1) - theta(s0) along the geodesic leaving station s0 at winding angle alpha (rad, toward s1)."""
    ev0 = surface.evaluate(np.array([s0]), np.array([0.0]), order=1)
    c = float(np.linalg.norm(ev0.pt[0])) * math.sin(alpha)
    prev = None
    panels = CLAIRAUT_PANELS
    while True:
        edges = np.linspace(s0, s1, panels + 1)
        half = 0.5 * (edges[1:] - edges[:-1])
        nodes = (0.5 * (edges[1:] + edges[:-1]))[:, None] + half[:, None] * GAUSS_X
        s = nodes.reshape(-1)
        ev = surface.evaluate(s, np.zeros_like(s), order=1)
        g = np.einsum("ij,ij->i", ev.pt, ev.pt)
        e = np.einsum("ij,ij->i", ev.ps, ev.ps)
        room = g - c * c
        if np.any(room <= 0.0):
            k = int(np.argmax(room <= 0.0))
            raise turnaround_error(surface, float(s[k]), heading_deg)
        f = c * np.sqrt(e / (g * room))
        value = float(np.sum((f.reshape(panels, -1) * GAUSS_W).sum(axis=1) * half))
        if prev is not None and abs(value - prev) <= CLAIRAUT_TOL * (1.0 + abs(value)):
            return value
        if panels >= CLAIRAUT_MAX_PANELS:
            raise SolverError(f"the geodesic's turn integral did not settle ({abs(value - prev):.2g} rad apart "
                              f"at {panels} panels): the profile is too rough near the turnaround")
        prev = value
        panels *= 2


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
        ev = surface.evaluate(np.array([s0]), theta0[:1], order=1)
        axial = float(np.linalg.norm(ev.ps[0])) * abs(s1 - s0)
        run = math.tan(lean) * axial * (1.0 if forward else -1.0)
        return _cylinder_theta(surface, s0, theta0, run)
    return None

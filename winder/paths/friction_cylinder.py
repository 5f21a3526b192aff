"""The friction-held path on a circular cylinder in closed form (docs/math/07-friction.md 7.4).

On a cylinder of radius R the normal curvature along heading alpha (from the meridian) is
k_n = sin^2(alpha) / R, and unrolled the cylinder is a plane, where the geodesic curvature is the
heading's rate, k_g = d alpha / d l. Holding lambda = k_g / k_n constant gives

    d alpha / d l = lambda sin^2(alpha) / R,   so   u = cot(alpha) = cot(alpha0) - lambda l / R:

u falls linearly with the fiber length l, and with sin(alpha) = 1 / sqrt(1 + u^2),
cos(alpha) = u / sqrt(1 + u^2) (alpha in (0, pi)), dz = cos(alpha) dl and R dtheta = sin(alpha) dl:

    z     = z0 - (R / lambda) (sqrt(1 + u^2) - sqrt(1 + u0^2)),
    theta = theta0 - (asinh(u) - asinh(u0)) / lambda.

The fiber reaches the parallel (u = 0, the turnaround) at l = R u0 / lambda where that is ahead, and
the mandrel's end z = 0 or z = T where sqrt(1 + u^2) = sqrt(1 + u0^2) - lambda (z_end - z0) / R has a
root of u0's sign. With lambda = 0 the path is the helix u = u0. These are the exact paths the general
ODE (winder.paths.friction) integrates; a job on a pipe traces its turnarounds here, with no ODE solver.
"""

from __future__ import annotations

import math

import numpy as np

LAMBDA_TINY = 1e-14  # |lambda| below this is the helix (the closed form divides by lambda)


def _end_length(u0: float, lam: float, radius: float, z0: float, z_end: float) -> float:
    """The fiber length at which the path reaches the station z_end (inf where it never does)."""
    dz = z_end - z0
    if abs(lam) < LAMBDA_TINY:
        c = u0 / math.sqrt(1.0 + u0 * u0)  # cos(alpha0)
        return dz / c if c != 0.0 and dz / c > 0.0 else math.inf
    x = math.sqrt(1.0 + u0 * u0) - lam * dz / radius
    if x < 1.0:
        return math.inf
    u = math.copysign(math.sqrt(x * x - 1.0), u0) if u0 != 0.0 else 0.0
    length = radius * (u0 - u) / lam
    # u must lie between u0 and the turnaround (u = 0) on the way: same sign as u0 and not past it
    return length if length > 0.0 and u * u0 >= 0.0 and abs(u) <= abs(u0) else math.inf


class CylinderFrictionState:
    """The state (s, theta, s', theta') of the closed-form path at fiber lengths l: (4,) or (4, j).

    A path heading toward -theta (sigma = -1) is the mirror image, theta -> 2 theta0 - theta, of the
    path at -heading with -lambda (the mirror turns the other way), which the formulas above give.
    """

    def __init__(self, radius: float, z0: float, th0: float, u0: float, lam: float, sigma: float) -> None:
        self.radius, self.z0, self.th0, self.u0, self.lam, self.sigma = radius, z0, th0, u0, lam, sigma

    def __call__(self, arc: np.ndarray | float) -> np.ndarray:
        l = np.asarray(arc, dtype=float)
        r, u0, lam = self.radius, self.u0, self.lam
        if abs(lam) < LAMBDA_TINY:
            u = np.full_like(l, u0)
            root = np.sqrt(1.0 + u * u)
            z = self.z0 + l * u / root
            th = self.th0 + l / (r * root)
        else:
            u = u0 - lam * l / r
            root = np.sqrt(1.0 + u * u)
            z = self.z0 - (r / lam) * (root - math.sqrt(1.0 + u0 * u0))
            th = self.th0 - (np.arcsinh(u) - math.asinh(u0)) / lam
        return np.stack([z, self.th0 + self.sigma * (th - self.th0), u / root, self.sigma / (r * root)])


def cylinder_path(radius: float, length: float, z0: float, th0: float, heading_deg: float, lam: float,
                  span: float, stop_at_ends: bool, stop_at_turnaround: bool) -> tuple[CylinderFrictionState, float, str]:
    """(state, fiber length reached, event) of the path from (z0, th0) at heading_deg with slip lam, traced
    for at most span mm on a cylinder of `radius` over stations [0, length]; event as FrictionTrace's.

    Examples
    --------
    >>> state, l, event = cylinder_path(50.0, 1000.0, 500.0, 0.0, 60.0, 0.2, 1e4, True, True)
    >>> event, round(l, 6) == round(50.0 / math.tan(math.radians(60.0)) / 0.2, 6)
    ('turnaround', True)
    >>> abs(float(state(l)[2])) < 1e-12  # s' = cos(alpha) = 0 on the parallel
    True
    """
    sigma = 1.0 if math.sin(math.radians(heading_deg)) >= 0.0 else -1.0
    lam *= sigma
    u0 = 1.0 / math.tan(math.radians(sigma * heading_deg))
    state = CylinderFrictionState(radius, z0, th0, u0, lam, sigma)
    reached, event = float(span), "length"
    if stop_at_turnaround and abs(lam) >= LAMBDA_TINY and u0 / lam > 0.0 and radius * u0 / lam <= reached:
        reached, event = radius * u0 / lam, "turnaround"
    if stop_at_ends:
        at_end = min(_end_length(u0, lam, radius, z0, 0.0), _end_length(u0, lam, radius, z0, length))
        if at_end < reached:
            reached, event = at_end, "end"
    return state, reached, event

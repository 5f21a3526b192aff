"""Normal and geodesic curvature of a path on the surface, and the torus closed forms (docs/math/07-friction.md).

A fiber's curvature vector splits in the Darboux frame (T, N, nu = N x T) as dT/dl = k_n N + k_g nu.
N is the unit normal Phi_s x Phi_theta / |Phi_s x Phi_theta|, which points into the mandrel (toward
the axis on a tube), so k_n > 0 where the fiber presses on the mandrel and k_n <= 0 where it bridges.
nu = N x T is the tangent-plane normal to the fiber; k_g > 0 turns the fiber toward larger winding
angle (from the meridian toward increasing theta, as shooting's heading).

Everything here is computed from the path's points alone with the exact surface normal, so it is an
independent check of what the friction ODE was told to do (winder.paths.friction): the slip the path needs,
lambda = k_g / k_n, and its bridging margin, min k_n.
"""

from __future__ import annotations

import numpy as np

from winder.geometry.interp import interp_spline
from winder.geometry.measure import cross, row_norms
from winder.geometry.surface import SweepSurface

SPLINE_DEGREE = 5  # interpolating spline through a sampled path: 2nd derivatives to O(h^4)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("ij,ij->i", a, b)


def inward_normals(surface: SweepSurface, s: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Unit normals Phi_s x Phi_theta / |...| (into the mandrel): (m, 3) float."""
    ev = surface.evaluate(s, theta, order=1)
    nrm = cross(ev.ps, ev.pt)
    return nrm / row_norms(nrm)[:, None]


def curve_curvatures(surface: SweepSurface, s: np.ndarray, theta: np.ndarray, ds: np.ndarray,
                     dtheta: np.ndarray, dds: np.ndarray, ddtheta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(k_n, k_g) in 1/mm of a surface curve u(q) = (s(q), theta(q)) of any parametrization q.

    s, theta, ds, dtheta, dds, ddtheta : (m,) float, the curve and its first two q-derivatives.
    The space curve C = Phi(u) has C' = J u', C'' = J u'' + Phi_ij u'^i u'^j; its curvature vector
    (C'' minus its tangential part) / |C'|^2 is projected on N and on nu = N x T.
    """
    ev = surface.evaluate(s, theta, order=2)
    vel = ev.ps * ds[:, None] + ev.pt * dtheta[:, None]
    acc = (ev.ps * dds[:, None] + ev.pt * ddtheta[:, None] + ev.pss * (ds * ds)[:, None]
           + 2.0 * ev.pst * (ds * dtheta)[:, None] + ev.ptt * (dtheta * dtheta)[:, None])
    nrm = cross(ev.ps, ev.pt)
    nrm /= row_norms(nrm)[:, None]
    speed2 = _dot(vel, vel)
    tan = vel / np.sqrt(speed2)[:, None]
    return _dot(acc, nrm) / speed2, _dot(acc, cross(nrm, tan)) / speed2


def path_curvatures(surface: SweepSurface, arc: np.ndarray, s: np.ndarray,
                    theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(k_n, k_g) at the samples of a path given by points (s, theta) at arc lengths arc (mm).

    A quintic interpolating spline through the samples (against arc) gives the derivatives; the
    arc need not be exact (any smooth parametrization serves). All (m,) float, m >= 6.
    """
    spline = interp_spline(arc, np.column_stack([s, theta]), SPLINE_DEGREE).derivative()
    (ds, dth), (dds, ddth) = spline(arc).T, spline(arc, 1).T
    return curve_curvatures(surface, s, theta, ds, dth, dds, ddth)


def polyline_curvatures(surface: SweepSurface, s: np.ndarray, theta: np.ndarray,
                        points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(k_n, k_g) at the interior vertices of a polyline on the surface (e.g. a job CSV's pass).

    The discrete curvature vector at p_i is (d_i - d_{i-1}) / (mean of the two segment lengths), d the
    unit segment directions; it is projected on the exact normal N(u_i) and on N x T, T the mean
    direction. Second order in the spacing for equally spaced points. Returns two (m - 2,) arrays.
    """
    seg = np.diff(points, axis=0)
    lens = row_norms(seg)
    d = seg / lens[:, None]
    kappa = (d[1:] - d[:-1]) / (0.5 * (lens[:-1] + lens[1:]))[:, None]
    tan = d[1:] + d[:-1]
    tan /= row_norms(tan)[:, None]
    nrm = inward_normals(surface, s[1:-1], theta[1:-1])
    return _dot(kappa, nrm), _dot(kappa, cross(nrm, tan))


def slip_and_margin(k_n: np.ndarray, k_g: np.ndarray) -> tuple[float, float]:
    """(max |k_g / k_n|, min k_n) of a path; the slip is inf where the fiber does not press."""
    k_min = float(np.min(k_n))
    if k_min <= 0.0:
        return float("inf"), k_min
    return float(np.max(np.abs(k_g / k_n))), k_min


# -- torus (an elbow): docs/math/07-friction.md ------------------------------------------------------------------
def torus_normal_curvature(alpha: np.ndarray, phi: np.ndarray, bend_radius: float,
                           tube_radius: float) -> np.ndarray:
    """k_n (1/mm) on a torus, alpha from the pipe axis, phi around the tube from the inside of the bend:
    sin^2(alpha) / a - cos(phi) cos^2(alpha) / (R_b - a cos(phi))."""
    rho = bend_radius - tube_radius * np.cos(phi)
    return np.sin(alpha) ** 2 / tube_radius - np.cos(phi) * np.cos(alpha) ** 2 / rho


def torus_constant_angle_slip(alpha: np.ndarray, phi: np.ndarray, bend_radius: float,
                              tube_radius: float) -> np.ndarray:
    """lambda(phi) a path at constant alpha through a torus needs:
    a cos(alpha) sin(phi) / (rho sin^2(alpha) - a cos(phi) cos^2(alpha)), rho = R_b - a cos(phi)."""
    a = tube_radius
    rho = bend_radius - a * np.cos(phi)
    return a * np.cos(alpha) * np.sin(phi) / (rho * np.sin(alpha) ** 2 - a * np.cos(phi) * np.cos(alpha) ** 2)


def torus_least_pressing_angle(bend_radius: float, tube_radius: float) -> float:
    """The winding angle (rad) below which a fiber bridges at the inside of the bend, whatever the
    friction: tan^2(alpha) = a / (R_b - a)."""
    return float(np.arctan(np.sqrt(tube_radius / (bend_radius - tube_radius))))

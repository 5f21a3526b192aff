"""Measurements of a path given by parameter points: lengths and quality checks (MATH.md 2, 4)."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline

from winder.geometry.surface import SweepSurface

GAUSS_NODES = 5  # Gauss-Legendre nodes per segment: exact to degree 9, far past the spline's order


def polyline_length(points: np.ndarray) -> float:
    """Length of the polyline through points (m, 3)."""
    return float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1)))


def smooth_length(surface: SweepSurface, s: np.ndarray, theta: np.ndarray) -> float:
    """Length of the smooth surface curve through the vertices (the super-convergent length).

    A cubic spline through (s_i, theta_i) against the index i, mapped onto the surface; its speed
    |Phi_s s' + Phi_theta theta'| is integrated by Gauss-Legendre. Because a geodesic's length is
    stationary, vertices within O(h^2) of it give a length within O(h^4).
    s, theta : (m,) float.
    """
    idx = np.arange(s.shape[0], dtype=float)
    cs, ct = CubicSpline(idx, s), CubicSpline(idx, theta)
    x, w = np.polynomial.legendre.leggauss(GAUSS_NODES)
    nodes = (idx[:-1, None] + 0.5 + 0.5 * x[None, :]).ravel()
    ev = surface.evaluate(cs(nodes), ct(nodes), order=1)
    vel = ev.ps * cs(nodes, 1)[:, None] + ev.pt * ct(nodes, 1)[:, None]
    speed = np.linalg.norm(vel, axis=1).reshape(-1, GAUSS_NODES)
    return float(0.5 * np.sum(speed @ w))


def geodesic_curvature(surface: SweepSurface, s: np.ndarray, theta: np.ndarray,
                       points: np.ndarray) -> np.ndarray:
    """Discrete geodesic curvature at the interior vertices (paper 4.4), in 1/mm.

    (d_{i-1} x d_i) . N(p_i) with unit segment directions d, divided by the mean of the two
    segment lengths so that it approximates the curvature. Returns (m - 2,) float.
    """
    seg = np.diff(points, axis=0)
    lens = np.linalg.norm(seg, axis=1)
    d = seg / lens[:, None]
    nrm = surface.normals(s[1:-1], theta[1:-1])
    turn = np.einsum("ij,ij->i", np.cross(d[:-1], d[1:]), nrm)
    return turn / (0.5 * (lens[:-1] + lens[1:]))


def spacing_deviation(points: np.ndarray) -> float:
    """max |segment length / mean - 1|: 0 for an exactly equally spaced polyline."""
    lens = np.linalg.norm(np.diff(points, axis=0), axis=1)
    return float(np.max(np.abs(lens / lens.mean() - 1.0)))


def richardson(l_n: float, l_2n: float) -> tuple[float, float]:
    """Richardson extrapolation of O(1/n^2) polyline lengths at n and 2n + 1 interior points.

    Returns (extrapolated length, error estimate |L_2n - L_n| / 3), both mm.
    """
    return l_2n + (l_2n - l_n) / 3.0, abs(l_2n - l_n) / 3.0

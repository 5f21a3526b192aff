"""A spline axis's bend radius against the mandrel's largest section radius, from numpy alone.

A spline axis bent tighter than the section is wide folds the mandrel onto itself (docs/math/01-surface.md 1.6: the
sweep is regular while 1 - R (K . n) > 0). find_fold (winder.geometry.surface) tells it on the built
surface, but building a spline curve loads scipy.interpolate (over a second on a busy machine) and a
folded mandrel must be refused at once. The chord-length cubic through the points (the interpolant
SplineCurve is refitted from, with the same end conditions) is solved here directly: the n second
derivatives M_i of the C2 cubic satisfy the tridiagonal moment equations

    h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (d_i - d_{i-1}),   d_i = (y_{i+1} - y_i) / h_i,

closed by M_0 = M_{n-1} = 0 (natural, n <= 3) or a continuous third derivative at the second and the
last-but-one point (not-a-knot, n > 3). Its curvature |c' x c''| / |c'|^3 is then evaluated densely.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["SplineBend", "chord_cubic_moments", "spline_bends"]

SAMPLES_PER_PIECE = 256  # curvature samples on each piece of the cubic (a bend peak is found to ~0.2 %)
GAUSS_NODES = 6  # Gauss-Legendre nodes per sample interval for the arc length


class SplineBend(NamedTuple):
    """The spline's curvature along its arc length.

    Attributes
    ----------
    z : ndarray, shape (m,)
        arc length t (mm) of each sample.
    kappa : ndarray, shape (m,)
        curvature 1 / bend radius (1/mm) there.
    piece : ndarray, shape (m,)
        index i of the cubic piece between points[i] and points[i + 1].
    length : float
        the curve's arc length (mm).
    """

    z: np.ndarray
    kappa: np.ndarray
    piece: np.ndarray
    length: float


def chord_cubic_moments(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(u, M): chord-length knots (n,) and second derivatives (n, 3) of the C2 cubic through points (n, 3)."""
    pts = np.asarray(points, dtype=float)
    n = len(pts)
    h = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    u = np.concatenate([[0.0], np.cumsum(h)])
    if n < 3:
        return u, np.zeros_like(pts)
    d = np.diff(pts, axis=0) / h[:, None]
    a = np.zeros((n, n))
    rhs = np.zeros((n, 3))
    i = np.arange(1, n - 1)
    a[i, i - 1], a[i, i], a[i, i + 1] = h[:-1], 2.0 * (h[:-1] + h[1:]), h[1:]
    rhs[i] = 6.0 * (d[1:] - d[:-1])
    if n > 3:  # not-a-knot: h1 (M1 - M0) = h0 (M2 - M1), and the same at the far end
        a[0, :3] = -h[1], h[0] + h[1], -h[0]
        a[-1, -3:] = -h[-1], h[-2] + h[-1], -h[-2]
    else:
        a[0, 0] = a[-1, -1] = 1.0
    return u, np.linalg.solve(a, rhs)


def spline_bends(points: np.ndarray) -> SplineBend:
    """The curvature of the chord-length C2 cubic through points (n, 3) along its arc length."""
    pts = np.asarray(points, dtype=float)
    u, m = chord_cubic_moments(pts)
    h = np.diff(u)
    k = SAMPLES_PER_PIECE
    frac = np.linspace(0.0, 1.0, k + 1)
    piece = np.repeat(np.arange(len(h)), k + 1)
    f = np.tile(frac, len(h))
    gx, gw = np.polynomial.legendre.leggauss(GAUSS_NODES)
    # arc length of each sample interval by Gauss-Legendre in the piece's local fraction
    fg = (0.5 * (frac[:-1] + frac[1:]))[:, None] + (0.5 * np.diff(frac))[:, None] * gx
    pg = np.repeat(np.arange(len(h)), fg.size)
    d1g, _ = _derivatives(pts, m, h, pg, np.tile(fg.ravel(), len(h)))
    speed = np.linalg.norm(d1g, axis=1).reshape(len(h), k, GAUSS_NODES)
    seg = (speed @ gw) * 0.5 * np.diff(frac)[None, :] * h[:, None]
    ell = np.concatenate([np.zeros((len(h), 1)), np.cumsum(seg, axis=1)], axis=1)
    ell += np.concatenate([[0.0], np.cumsum(ell[:, -1])[:-1]])[:, None]
    d1, d2 = _derivatives(pts, m, h, piece, f)
    sp = np.linalg.norm(d1, axis=1)
    kappa = np.linalg.norm(np.cross(d1, d2), axis=1) / np.maximum(sp, 1e-300) ** 3
    return SplineBend(ell.ravel(), kappa, piece, float(ell[-1, -1]))


def _derivatives(pts: np.ndarray, m: np.ndarray, h: np.ndarray, i: np.ndarray,
                 f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """c'(u) and c''(u) (m, 3) on piece i at local fraction f = (u - u_i) / h_i."""
    hi = h[i][:, None]
    a, b = (1.0 - f)[:, None], f[:, None]
    m0, m1 = m[i], m[i + 1]
    d1 = (pts[i + 1] - pts[i]) / hi + hi * (-0.5 * a * a * m0 + 0.5 * b * b * m1 + (m0 - m1) / 6.0)
    d2 = a * m0 + b * m1
    return d1, d2

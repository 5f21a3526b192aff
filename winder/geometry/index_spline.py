"""Cubic splines against the vertex index: uniform knots, not-a-knot ends (docs/math/02-energy.md).

A path's converged vertices are equally spaced in 3D, so the index is a good arc-length proxy; the
spline through (s_i, theta_i) against i resamples a path between solver levels and carries the
super-convergent length. Unit knots make the knot slopes one tridiagonal solve (LAPACK gtsv from
scipy.linalg.lapack, all columns at once) and every evaluation a combination of the cubic Hermite
basis. CubicSpline(i, y) is the same spline, but a solver asks for the slopes at every level: on
configs/elliptic_tube.yaml's plan (438 solves) its construction took 1.8 s under cProfile, these 0.3 s.
"""

from __future__ import annotations

import numpy as np

# Gauss-Lobatto with 4 nodes on [0, 1]: the knots and 1/2 -+ sqrt(5)/10, weights 1/12, 5/12, 5/12,
# 1/12. Exact to degree 5, and the knots are shared with the neighbouring segments.
LOBATTO_T = np.array([0.5 - np.sqrt(5.0) / 10.0, 0.5 + np.sqrt(5.0) / 10.0])
LOBATTO_W_END = 1.0 / 12.0
LOBATTO_W_MID = 5.0 / 12.0


def knot_slopes(y: np.ndarray) -> np.ndarray:
    """dy/di at the knots of the not-a-knot cubic spline through y (m, k) against i = 0..m-1.

    Returns (m, k) float. m = 2 is the line, m = 3 the parabola (as scipy's CubicSpline).
    """
    m = y.shape[0]
    sl = np.diff(y, axis=0)
    if m == 2:
        return np.concatenate([sl, sl])
    if m == 3:
        curv = sl[1] - sl[0]
        return np.stack([sl[0] - 0.5 * curv, 0.5 * (sl[0] + sl[1]), sl[1] + 0.5 * curv])
    from scipy.linalg.lapack import dgtsv  # noqa: PLC0415 - only when a path is measured or resampled

    # On unit knots: s_{i-1} + 4 s_i + s_{i+1} = 3 (y_{i+1} - y_{i-1}) inside; not-a-knot ends (the
    # third derivative continuous at the second and the second-to-last knot) scaled to the same band.
    rhs = np.empty_like(y)
    rhs[0] = 0.5 * (5.0 * sl[0] + sl[1])
    rhs[1:-1] = 3.0 * (sl[:-1] + sl[1:])
    rhs[-1] = 0.5 * (sl[-2] + 5.0 * sl[-1])
    diag, lower, upper = np.full(m, 4.0), np.ones(m - 1), np.ones(m - 1)
    diag[[0, -1]] = 1.0
    upper[0] = lower[-1] = 2.0
    *_, slopes, info = dgtsv(lower, diag, upper, rhs, overwrite_b=True)
    if info != 0:  # strictly diagonally dominant but for the end rows: cannot happen
        raise ArithmeticError(f"the spline's knot system is singular (LAPACK info {info})")
    return slopes


def _hermite(y0: np.ndarray, d0: np.ndarray, y1: np.ndarray, d1: np.ndarray, t,
             derivative: bool = False) -> np.ndarray:
    """The cubic Hermite piece with end values y0, y1 and slopes d0, d1 (per unit t) at fraction t:
    t a float or a (q, 1) array broadcasting against the (q, k) ends."""
    t2 = t * t
    if derivative:
        return 6.0 * (t2 - t) * (y0 - y1) + (3.0 * t2 - 4.0 * t + 1.0) * d0 + (3.0 * t2 - 2.0 * t) * d1
    t3 = t2 * t
    return (2.0 * t3 - 3.0 * t2 + 1.0) * y0 + (t3 - 2.0 * t2 + t) * d0 + (3.0 * t2 - 2.0 * t3) * y1 + (t3 - t2) * d1


def resample_index(y: np.ndarray, count: int) -> np.ndarray:
    """The spline through y (m, k) against the normalized index, at count equally spaced fractions.

    The end values are kept exactly. Returns (count, k) float.
    """
    m = y.shape[0]
    dy = knot_slopes(y)
    x = np.linspace(0.0, m - 1.0, count)
    k = np.minimum(x.astype(int), m - 2)
    yt, dt = y.T, dy.T  # (k, count) rows: numpy's inner loops run over the points
    out = _hermite(yt[:, k], dt[:, k], yt[:, k + 1], dt[:, k + 1], x - k).T
    out[[0, -1]] = y[[0, -1]]
    return out


def segment_nodes(y: np.ndarray, dy: np.ndarray, fractions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values and slopes of the spline at the given fractions (q,) of every segment.

    y, dy : (m, k) knot values and slopes. Returns two ((m - 1) q, k) float arrays, the nodes in
    path order.
    """
    return hermite_nodes(y[:-1], dy[:-1], y[1:], dy[1:], fractions)


def hermite_nodes(y0: np.ndarray, d0: np.ndarray, y1: np.ndarray, d1: np.ndarray,
                  fractions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values and slopes at the fractions (q,) of separate cubic Hermite segments: end values y0, y1
    and slopes d0, d1 per unit fraction, each (S, k). Returns two (S q, k) float arrays, segment by
    segment (segment_nodes for segments of any width, their slopes scaled by it)."""
    ends, t = (y0[:, None], d0[:, None], y1[:, None], d1[:, None]), np.asarray(fractions)[None, :, None]
    k = y0.shape[-1]
    return _hermite(*ends, t).reshape(-1, k), _hermite(*ends, t, derivative=True).reshape(-1, k)

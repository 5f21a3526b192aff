"""Cubic splines against the vertex index: uniform knots, not-a-knot ends (MATH.md 2).

A path's converged vertices are equally spaced in 3D, so the index is a good arc-length proxy; the
spline through (s_i, theta_i) against i resamples a path between solver levels and carries the
super-convergent length. The knot slopes are scipy's CubicSpline(i, y) (not-a-knot) at the knots; on
uniform knots every evaluation is then a fixed combination of the cubic Hermite basis.
"""

from __future__ import annotations

import functools

import numpy as np


# Gauss-Lobatto with 4 nodes on [0, 1]: the knots and 1/2 -+ sqrt(5)/10, weights 1/12, 5/12, 5/12,
# 1/12. Exact to degree 5, and the knots are shared with the neighbouring segments.
LOBATTO_T = np.array([0.5 - np.sqrt(5.0) / 10.0, 0.5 + np.sqrt(5.0) / 10.0])
LOBATTO_W_END = 1.0 / 12.0
LOBATTO_W_MID = 5.0 / 12.0
# Up to this many knots segment_nodes works in path order directly (measured, 5 Gauss fractions: 27 ->
# 19 us at 33 knots, even at about 80, slower beyond: the inner loops are only q long).
DIRECT_SEGMENTS = 64


def knot_slopes(y: np.ndarray) -> np.ndarray:
    """dy/di at the knots of the not-a-knot cubic spline through y (m, k) against i = 0..m-1.

    Returns (m, k) float. m = 2 is the line, m = 3 the parabola (as scipy's CubicSpline).
    """
    from scipy.interpolate import CubicSpline  # noqa: PLC0415 - only when a path is measured or resampled

    i = np.arange(y.shape[0], dtype=float)
    return CubicSpline(i, y, axis=0)(i, 1)


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
    ratio, rest = divmod(count - 1, m - 1)
    if rest == 0 and ratio & (ratio - 1) == 0:
        # A power-of-two refinement (the solver's levels): the fractions j / ratio are exact, the
        # same as linspace's, so every segment takes them from one cached basis, no per-point gather.
        a, b, c, d = _basis(tuple(j / ratio for j in range(ratio)))[:4]
        yt, dt = _columns(y), _columns(dy)
        inner = a * yt[:, None, :-1] + b * dt[:, None, :-1] + c * yt[:, None, 1:] + d * dt[:, None, 1:]
        out = np.concatenate([_path_order(inner), y[-1:]])
    else:
        x = np.linspace(0.0, m - 1.0, count)
        k = np.minimum(x.astype(int), m - 2)
        # Along (k, count) rows: numpy's inner loops then run over the points, not the k columns.
        yt, dt = _columns(y), _columns(dy)
        out = _hermite(yt[:, k], dt[:, k], yt[:, k + 1], dt[:, k + 1], x - k).T
    out[[0, -1]] = y[[0, -1]]
    return out


def segment_nodes(y: np.ndarray, dy: np.ndarray, fractions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values and slopes of the spline at the given fractions (q,) of every segment.

    y, dy : (m, k) knot values and slopes. Returns two ((m - 1) q, k) float arrays, the nodes in
    path order.
    """
    # One broadcast pass over (k, q, m - 1) with the basis weights of the fractions computed once
    # (the arithmetic and its order are _hermite's, so the nodes are bit for bit the same). The
    # segments run along the last axis: over (m - 1, q, k) numpy's inner loop would be k = 2 long,
    # several times slower (measured: 230 -> 40 us at m = 1001, q = 2).
    key = tuple(fractions.tolist())
    yt, dt = _columns(y), _columns(dy)
    if yt.shape[1] <= DIRECT_SEGMENTS:
        # A short path: the per-call cost dominates, so the nodes come out in path order directly
        # ((k, m - 1, q), inner loops q long) instead of through _path_order's copies.
        a, b, c, d, e, f, g = _basis_rows(key)
        y0, y1, d0, d1 = yt[:, :-1, None], yt[:, 1:, None], dt[:, :-1, None], dt[:, 1:, None]
        k = yt.shape[0]
        vals = a * y0 + b * d0 + c * y1 + d * d1
        return vals.reshape(k, -1).T, (e * (y0 - y1) + f * d0 + g * d1).reshape(k, -1).T
    a, b, c, d, e, f, g = _basis(key)
    y0, y1, d0, d1 = yt[:, None, :-1], yt[:, None, 1:], dt[:, None, :-1], dt[:, None, 1:]
    vals = a * y0 + b * d0 + c * y1 + d * d1
    ders = e * (y0 - y1) + f * d0 + g * d1
    return _path_order(vals), _path_order(ders)


def hermite_nodes(y0: np.ndarray, d0: np.ndarray, y1: np.ndarray, d1: np.ndarray,
                  fractions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values and slopes at the fractions (q,) of separate cubic Hermite segments: end values y0, y1
    and slopes d0, d1 per unit fraction, each (S, k). Returns two (S q, k) float arrays, segment by
    segment (segment_nodes for segments of any width, their slopes scaled by it)."""
    ends, t = (y0[:, None], d0[:, None], y1[:, None], d1[:, None]), np.asarray(fractions)[None, :, None]
    k = y0.shape[-1]
    return _hermite(*ends, t).reshape(-1, k), _hermite(*ends, t, derivative=True).reshape(-1, k)


def _columns(y: np.ndarray) -> np.ndarray:
    """y (m, k) as contiguous (k, m) rows."""
    return np.ascontiguousarray(y.T)


def _path_order(v: np.ndarray) -> np.ndarray:
    """(k, q, m - 1) node values as ((m - 1) q, k) rows in path order (segment, then fraction): a view
    of (k, (m - 1) q) storage, filled a fraction at a time (numpy's transposing copy is 4x slower)."""
    k, q, segments = v.shape
    out = np.empty((k, segments, q))
    for j in range(q):
        out[:, :, j] = v[:, j]
    return out.reshape(k, -1).T


@functools.lru_cache(maxsize=16)
def _basis_rows(fractions: tuple[float, ...]) -> tuple[np.ndarray, ...]:
    """_basis's weights as (q,) rows, to broadcast along a last axis of fractions."""
    return tuple(w[:, 0] for w in _basis(fractions))


@functools.lru_cache(maxsize=16)
def _basis(fractions: tuple[float, ...]) -> tuple[np.ndarray, ...]:
    """The cubic Hermite weights at the fractions, each (q, 1): of y0, d0, y1, d1 for the value,
    of y0 - y1, d0, d1 for the slope."""
    t = np.array(fractions)[:, None]
    t2 = t * t
    t3 = t2 * t
    return (2.0 * t3 - 3.0 * t2 + 1.0, t3 - 2.0 * t2 + t, 3.0 * t2 - 2.0 * t3, t3 - t2,
            6.0 * (t2 - t), 3.0 * t2 - 4.0 * t + 1.0, 3.0 * t2 - 2.0 * t)

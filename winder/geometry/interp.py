"""Interpolating splines: scipy's make_interp_spline (the not-a-knot spline of odd degree through a
pass's samples), and the not-a-knot cubics of many passes at once in Hermite form (knot_slopes_runs,
hermite: one tridiagonal solve, LAPACK gtsv from scipy.linalg.lapack, for every pass, where one spline
object per pass would loop in Python), and jets: a function and its derivatives as the columns of one
piecewise polynomial (jet, piecewise)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

import numpy as np

if TYPE_CHECKING:
    from scipy.interpolate import BSpline, PPoly


def interp_spline(x: np.ndarray, y: np.ndarray, k: int = 3) -> BSpline:
    """The not-a-knot interpolating spline of degree min(k, n - 1) through (x (n,), y (n,) or (n, c)):
    scipy's make_interp_spline; a cubic is CubicSpline(x, y)'s, two points give the line and three the
    parabola. Call it as spline(q, nu) for the nu-th derivative; spline.derivative() is a spline."""
    from scipy.interpolate import make_interp_spline  # noqa: PLC0415 - only when a job plans passes

    return make_interp_spline(x, y, k=min(k, np.asarray(x).size - 1))


def knot_slopes_runs(x: np.ndarray, y: np.ndarray, first: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """Knot slopes (N, c) of the not-a-knot cubics through the runs x[first_j : first_j + sizes_j]
    (each >= 4 sites, increasing) of x (N,) with values y (N, c), in one tridiagonal solve: the runs'
    systems stand one after the other with zero couplings, so elimination never mixes them and each
    run gets the slopes it would get alone (CubicSpline(x_run, y_run)'s, to round-off). Many passes'
    splines in one vectorized solve instead of one spline object per pass."""
    from scipy.linalg.lapack import dgtsv  # noqa: PLC0415

    h = np.diff(x)
    with np.errstate(all="ignore"):  # the differences across two passes' junction are not used
        d = np.diff(y, axis=0) / h[:, None]
    n = x.size
    last = first + sizes - 1
    diag = np.empty(n)
    upper = np.empty(n - 1)
    lower = np.empty(n - 1)
    rhs = np.empty_like(y)
    # Every row written as an interior one (slices, not index arrays), then each run's end rows over
    # it, and no coupling across a junction: a junction's own differences are never used.
    diag[1:-1] = 2.0 * (h[:-1] + h[1:])
    upper[1:] = h[:-1]
    lower[:-1] = h[1:]
    with np.errstate(all="ignore"):
        rhs[1:-1] = 3.0 * (h[1:, None] * d[:-1] + h[:-1, None] * d[1:])
    upper[last[last < n - 1]] = 0.0
    lower[first[first > 0] - 1] = 0.0
    # not-a-knot end rows (de Boor: the third derivative continuous at each run's second and
    # second-to-last sites)
    h0, h1, hl, hm = h[first], h[first + 1], h[last - 1], h[last - 2]
    s0, s1 = h0 + h1, hl + hm
    diag[first], upper[first] = h1, s0
    rhs[first] = ((h0 + 2.0 * s0) * h1)[:, None] * d[first] + (h0 * h0)[:, None] * d[first + 1]
    rhs[first] /= s0[:, None]
    diag[last], lower[last - 1] = hm, s1
    rhs[last] = (hl * hl)[:, None] * d[last - 2] + ((2.0 * s1 + hl) * hm)[:, None] * d[last - 1]
    rhs[last] /= s1[:, None]
    *_, slopes, info = dgtsv(lower, diag, upper, rhs, overwrite_b=True)
    if info != 0:
        raise ArithmeticError(f"the spline's slope system is singular (LAPACK info {info})")
    return slopes


def hermite(x: np.ndarray, y: np.ndarray, m: np.ndarray, i: np.ndarray, q: np.ndarray, order: int) -> np.ndarray:
    """The order-th derivative at q (k,) of the cubic Hermite pieces through (x, y (n, c)) with slopes
    m (n, c), q in piece i (k,) (x[i] <= q < x[i + 1], or the end pieces): (k, c)."""
    h = (x[i + 1] - x[i])[:, None]
    t = ((q - x[i]) / h[:, 0])[:, None]
    y0, y1, m0, m1 = y[i], y[i + 1], m[i], m[i + 1]
    if order == 0:
        t2 = t * t
        return ((2.0 * t - 3.0) * t2 + 1.0) * y0 + ((t - 2.0) * t + 1.0) * t * h * m0 \
            + (3.0 - 2.0 * t) * t2 * y1 + (t - 1.0) * t2 * h * m1
    if order == 1:
        return 6.0 * (t - 1.0) * t * (y0 - y1) / h + ((3.0 * t - 4.0) * t + 1.0) * m0 + (3.0 * t - 2.0) * t * m1
    if order == 2:
        return ((12.0 * t - 6.0) * (y0 - y1) / h + (6.0 * t - 4.0) * m0 + (6.0 * t - 2.0) * m1) / h
    if order == 3:
        return (12.0 * (y0 - y1) / h + 6.0 * (m0 + m1)) / (h * h)
    return np.zeros_like(y0)


def piecewise(spline: BSpline) -> PPoly:
    """A B-spline of values (n,) or (n, c) as scipy's PPoly on its distinct knots (the same
    polynomials, to round-off; PPoly.from_spline takes one column at a time)."""
    from scipy.interpolate import BSpline, PPoly  # noqa: PLC0415

    t, c, k = spline.tck
    columns = np.reshape(c, (c.shape[0], -1))
    coefs = np.stack([PPoly.from_spline(BSpline(t, columns[:, j], k)).c for j in range(columns.shape[1])], axis=-1)
    keep = np.diff(t) > 0.0  # the repeated end knots' empty pieces
    return PPoly(coefs[:, keep].reshape((k + 1, int(keep.sum())) + c.shape[1:]),
                 np.append(t[:-1][keep], t[-1]))


def jet(pieces: Sequence[tuple[PPoly, int]]) -> PPoly:
    """One piecewise polynomial whose columns are, for each (p, order) of pieces (sharing their
    breakpoints), p's columns followed by those of its derivatives up to order: p, p', ..., then the
    next. Read in one call (one search, one Horner loop in C) instead of one call each: the planner
    evaluates mandrels a few hundred points at a time inside root finders and ODEs, where separate
    calls cost 2 to 3x more (offset domes, spline guide curves). The derivatives' coefficients are
    padded with leading zeros: the same values as p.derivative(j)'s, bit for bit."""
    from scipy.interpolate import PPoly  # noqa: PLC0415

    degree = max(p.c.shape[0] for p, _ in pieces)
    columns = []
    for p, order in pieces:
        for j in range(order + 1):
            c = p.derivative(j).c if j else p.c
            pad = degree - c.shape[0]
            columns.append(np.concatenate([np.zeros((pad,) + c.shape[1:]), c]).reshape(degree, c.shape[1], -1))
    return PPoly(np.concatenate(columns, axis=-1), pieces[0][0].x)

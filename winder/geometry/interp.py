"""Interpolating B-splines through points, in numpy (one LAPACK banded solve), without scipy.interpolate.

scipy.interpolate takes longer to import than a small job takes to plan, and the planner only ever
needs the interpolating spline of odd degree through a pass's samples and its derivatives. This is
that spline: degree k, the not-a-knot knots of scipy's make_interp_spline (de Boor XIII(12): the data
sites but the (k - 1) / 2 next to each end), coefficients from the collocation system. The cubic is
the spline of CubicSpline(x, y) (not-a-knot); two points give the line and three the parabola, as
there. Basis values by the Cox-de Boor recursion (de Boor's BSPLVB), vectorized over the points;
derivatives by differencing the coefficients (the derivative of a B-spline is a B-spline).
"""

from __future__ import annotations

import numpy as np

from winder.geometry.lapack import lapack


def _knots(x: np.ndarray, k: int) -> np.ndarray:
    """Not-a-knot knots for degree k through sites x (n,): (n + k + 1,) float."""
    if k == x.size - 1:  # one polynomial piece through all the sites
        return np.concatenate([np.full(k + 1, x[0]), np.full(k + 1, x[-1])])
    m = (k - 1) // 2
    return np.concatenate([np.full(k + 1, x[0]), x[m + 1:x.size - m - 1], np.full(k + 1, x[-1])])


def _basis(t: np.ndarray, k: int, n: int, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The k + 1 B-splines that do not vanish at each point of x (q,): their values (k + 1, q) and
    the span index i (q,): the rows are B_{i-k} .. B_i. Points outside extrapolate."""
    i = np.clip(np.searchsorted(t, x, side="right") - 1, k, n - 1)
    vals = [np.ones(x.size)]
    left = [None] + [x - t[i + 1 - j] for j in range(1, k + 1)]
    right = [None] + [t[i + j] - x for j in range(1, k + 1)]
    for j in range(1, k + 1):
        saved = np.zeros(x.size)
        for r in range(j):
            temp = vals[r] / (right[r + 1] + left[j - r])
            vals[r] = saved + right[r + 1] * temp
            saved = left[j - r] * temp
        vals.append(saved)
    return np.array(vals), i


class InterpSpline:
    """The interpolating spline of degree k through (x_i, y_i); x (n,) strictly increasing,
    y (n,) or (n, c). k odd (1, 3, 5) and below n, or k = n - 1 (a single polynomial).

    spline(x, nu=0): the nu-th derivative at x (q,) -> (q,) or (q, c); spline.derivative() the
    derivative as a spline of degree k - 1.
    """

    def __init__(self, x: np.ndarray, y: np.ndarray, k: int = 3, *, _tck=None):
        if _tck is not None:
            self.t, self.c, self.k = _tck
            return
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        n = x.size
        if not (1 <= k < n and (k % 2 == 1 or k == n - 1)):
            raise ValueError(f"an interpolating spline of degree {k} needs an odd degree below {n} points")
        if np.any(np.diff(x) <= 0.0):
            raise ValueError("the sites of an interpolating spline must increase strictly")
        self.k = k
        self.t = _knots(x, k)
        self.c = _solve(self.t, k, x, y)

    def __call__(self, x: np.ndarray, nu: int = 0) -> np.ndarray:
        spline = self
        for _ in range(nu):
            spline = spline.derivative()
        return spline._value(np.asarray(x, dtype=float))

    def _value(self, x: np.ndarray) -> np.ndarray:
        shape = x.shape
        xf = x.reshape(-1)
        n = self.c.shape[0]
        vals, i = _basis(self.t, self.k, n, xf)
        c = self.c.reshape(n, -1)
        out = vals[0][:, None] * c[i - self.k]
        for j in range(1, self.k + 1):
            out += vals[j][:, None] * c[i - self.k + j]
        return out.reshape(shape + self.c.shape[1:])

    def derivative(self) -> InterpSpline:
        """The first derivative: a spline of degree k - 1 on the same pieces."""
        t, c, k = self.t, self.c, self.k
        if k == 0:
            return InterpSpline(None, None, _tck=(t, np.zeros_like(c), 0))
        width = (t[k + 1:k + c.shape[0]] - t[1:c.shape[0]]).reshape((-1,) + (1,) * (c.ndim - 1))
        dc = k * np.diff(c, axis=0) / np.where(width > 0.0, width, 1.0)
        return InterpSpline(None, None, _tck=(t[1:-1], dc, k - 1))


def _solve(t: np.ndarray, k: int, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Coefficients (n,) or (n, c) of the spline on knots t through (x, y): the banded collocation
    system B c = y, B[r, j] = B_j(x_r), in LAPACK's band storage (gbsv)."""
    n = x.size
    vals, i = _basis(t, k, n, x)
    vals = vals.T
    cols = i[:, None] - k + np.arange(k + 1)
    rows = np.broadcast_to(np.arange(n)[:, None], cols.shape)
    kl = int(np.max(rows - cols))
    ku = int(np.max(cols - rows))
    kl, ku = max(kl, 0), max(ku, 0)
    ab = np.zeros((2 * kl + ku + 1, n), order="F")
    ab[kl + ku + rows - cols, cols] = vals
    rhs = y.reshape(n, -1)
    _, _, c, info = lapack().dgbsv(kl, ku, ab, rhs)
    if info != 0:  # Schoenberg-Whitney holds for these knots: a singular system cannot happen
        raise ArithmeticError(f"the spline's collocation system is singular (LAPACK info {info})")
    return c.reshape(y.shape)


class NotAKnotCubic:
    """The not-a-knot cubic spline through (x_i, y_i), n >= 4, in Hermite form: the knot slopes from
    one tridiagonal solve (de Boor's end conditions: the third derivative continuous at x_1 and
    x_{n-2}), each piece the cubic with the end values and slopes. Callable as InterpSpline."""

    def __init__(self, x: np.ndarray, y: np.ndarray, _nu: int = 0, _slopes: np.ndarray | None = None):
        self.x = np.asarray(x, dtype=float)
        self.y = np.asarray(y, dtype=float)
        self._nu = _nu
        if _slopes is not None:
            self.m = _slopes
            return
        if self.x.size < 4 or np.any(np.diff(self.x) <= 0.0):
            raise ValueError("a not-a-knot cubic needs four or more strictly increasing sites")
        self.m = _knot_slopes(self.x, self.y.reshape(self.x.size, -1)).reshape(self.y.shape)

    def derivative(self) -> NotAKnotCubic:
        return NotAKnotCubic(self.x, self.y, self._nu + 1, self.m)

    def __call__(self, q: np.ndarray, nu: int = 0) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        shape = q.shape
        qf = q.reshape(-1)
        x, n = self.x, self.x.size
        i = np.clip(np.searchsorted(x, qf, side="right") - 1, 0, n - 2)
        out = hermite(x, self.y.reshape(n, -1), self.m.reshape(n, -1), i, qf, nu + self._nu)
        return out.reshape(shape + self.y.shape[1:])


def _knot_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """dy/dx at the sites of the not-a-knot cubic through (x, y (n, c)): (n, c); n >= 4."""
    return knot_slopes_runs(x, y, np.array([0]), np.array([x.size]))


def knot_slopes_runs(x: np.ndarray, y: np.ndarray, first: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """Knot slopes (N, c) of the not-a-knot cubics through the runs x[first_j : first_j + sizes_j]
    (each >= 4 sites, increasing) of x (N,) with values y (N, c), in one tridiagonal solve: the runs'
    systems stand one after the other with zero couplings, so elimination never mixes them and each
    run gets the slopes it would get alone, to the bit."""
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
    # h ** 2 of a numpy scalar, as the end rows were always written (its bits, not h * h's).
    h0, h1, hl, hm = h[first], h[first + 1], h[last - 1], h[last - 2]
    s0, s1 = h0 + h1, hl + hm
    diag[first], upper[first] = h1, s0
    sq0 = np.array([v ** 2 for v in h0])[:, None]
    sql = np.array([v ** 2 for v in hl])[:, None]
    rhs[first] = ((h0 + 2.0 * s0) * h1)[:, None] * d[first] + sq0 * d[first + 1]
    rhs[first] /= s0[:, None]
    diag[last], lower[last - 1] = hm, s1
    rhs[last] = sql * d[last - 2] + ((2.0 * s1 + hl) * hm)[:, None] * d[last - 1]
    rhs[last] /= s1[:, None]
    *_, slopes, info = lapack().dgtsv(lower, diag, upper, rhs, overwrite_b=True)
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


def interp_spline(x: np.ndarray, y: np.ndarray, k: int = 3) -> InterpSpline | NotAKnotCubic:
    """The not-a-knot interpolating spline of degree min(k, n - 1) through (x, y) (see InterpSpline);
    a cubic (k = 3) is scipy's CubicSpline(x, y), in Hermite form from four points on."""
    n = np.asarray(x).size
    if k == 3 and n >= 4:
        return NotAKnotCubic(x, y)
    return InterpSpline(x, y, min(k, n - 1))

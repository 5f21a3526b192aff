"""Piecewise polynomials in numpy: what the domes' quintic tables need of scipy's PPoly.

A vessel job otherwise imports scipy.interpolate (about 0.6 s, longer than the job's own planning) to
evaluate six quintic tables. The arithmetic is PPoly's own, term for term (the power sum
c_k s^0 + c_(k-1) s^1 + ..., s^j by repeated products; derivative coefficients times the falling
factorials), so results agree with scipy's bit for bit (tests/geometry/test_ppoly.py).
"""

from __future__ import annotations

import numpy as np


class PiecewisePoly:
    """p(x) = sum_m c[m, i] (x - x_i)^(k - m) on [x_i, x_(i+1)], extrapolated by the end pieces.

    Parameters
    ----------
    c : (k + 1, n) coefficients, highest power first (PPoly's layout).
    x : (n + 1,) increasing breakpoints.
    """

    def __init__(self, c: np.ndarray, x: np.ndarray) -> None:
        self.c = np.ascontiguousarray(c, dtype=float)
        self.x = np.ascontiguousarray(x, dtype=float)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """p at x (any shape; the result has x's shape)."""
        x = np.asarray(x, dtype=float)
        flat = x.ravel()
        i = np.clip(np.searchsorted(self.x, flat, side="right") - 1, 0, self.x.size - 2)
        s = flat - self.x[i]
        terms = self.c[::-1, i]  # (k + 1, m): the constant term first, as the power sum runs
        res = np.zeros_like(s)
        z = np.ones_like(s)
        for m in range(terms.shape[0]):
            res = res + terms[m] * z
            if m < terms.shape[0] - 1:
                z = z * s
        return res.reshape(x.shape)

    def derivative(self, nu: int = 1) -> PiecewisePoly:
        """The nu-th derivative (nu >= 1) as a piecewise polynomial of degree k - nu."""
        k = self.c.shape[0] - 1
        if nu > k:
            return PiecewisePoly(np.zeros((1, self.c.shape[1])), self.x)
        powers = np.arange(k, nu - 1, -1, dtype=float)  # the power of each kept row, highest first
        factor = np.ones_like(powers)
        for j in range(nu):
            factor = factor * (powers - j)
        return PiecewisePoly(self.c[: k + 1 - nu] * factor[:, None], self.x)

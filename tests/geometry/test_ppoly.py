"""winder.geometry.ppoly.PiecewisePoly against scipy's PPoly (to round-off) and closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from winder.geometry.ppoly import PiecewisePoly
from roundoff import assert_roundoff

POLY_TOL = 1e-12  # relative: a cubic's values and derivatives in closed form


@pytest.mark.parametrize("degree", [1, 3, 5])
def test_bit_for_bit_with_scipy_ppoly(degree: int) -> None:
    from scipy.interpolate import PPoly

    rng = np.random.default_rng(degree)
    x = np.cumsum(rng.uniform(0.1, 2.0, 40))
    c = rng.normal(size=(degree + 1, x.size - 1))
    points = np.concatenate([rng.uniform(x[0] - 1.0, x[-1] + 1.0, 2000), x, [x[0] - 5.0, x[-1] + 5.0]])
    ours, theirs = PiecewisePoly(c, x), PPoly(c, x, extrapolate=True)
    for nu in range(degree + 2):
        a = ours.derivative(nu) if nu else ours
        b = theirs.derivative(nu) if nu else theirs
        assert_roundoff(a(points), b(points), err_msg=str(nu))
        assert_roundoff(a(points.reshape(2, -1)), b(points).reshape(2, -1))


def test_a_cubic_and_its_derivatives_in_closed_form() -> None:
    x = np.array([-1.0, 0.5, 2.0])
    f = np.polynomial.Polynomial([1.0, -2.0, 0.5, 3.0])  # one cubic, written piece by piece
    c = np.array([[(f.deriv(3 - m)(xi)) / np.prod(np.arange(1, 4 - m)) for xi in x[:-1]] for m in range(4)])
    pp = PiecewisePoly(c, x)
    t = np.linspace(-2.0, 3.0, 101)
    for nu in range(4):
        got = (pp.derivative(nu) if nu else pp)(t)
        assert np.allclose(got, f.deriv(nu)(t), rtol=POLY_TOL, atol=POLY_TOL)

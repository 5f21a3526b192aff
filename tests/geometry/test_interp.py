"""winder.geometry.interp: the splines reproduce polynomials, and the batched not-a-knot cubics of
many runs are each run's CubicSpline."""

from __future__ import annotations

import numpy as np
import pytest

from winder.geometry.interp import hermite, interp_spline, knot_slopes_runs

EXACT = 1e-9  # a spline of degree k reproduces a polynomial of degree <= k (rounding of the solve only)
SAME_AS_SCIPY = 1e-11  # relative: the same spline from another implementation
CUBIC_REL = 1e-9  # not-a-knot slopes of a cubic's samples: its derivative (conditioning only)


def _sites(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.cumsum(rng.uniform(0.2, 1.5, n))


@pytest.mark.parametrize("k", [1, 3, 5])
@pytest.mark.parametrize("n", [8, 40])
def test_reproduces_polynomials_of_its_degree(k, n):
    x = _sites(n, k)
    poly = np.polynomial.Polynomial(np.arange(1.0, k + 2.0) / 10.0)
    spline = interp_spline(x, poly(x), k)
    q = np.linspace(x[0] - 0.3, x[-1] + 0.3, 301)  # extrapolation too: the end pieces are the polynomial
    scale = np.max(np.abs(poly(q)))
    for nu in range(min(k, 3) + 1):
        assert np.max(np.abs(spline(q, nu) - poly.deriv(nu)(q))) <= EXACT * scale


@pytest.mark.parametrize("n", [2, 3])
def test_few_points_give_the_line_and_the_parabola(n):
    x = np.array([0.0, 1.0, 3.0])[:n]
    poly = np.polynomial.Polynomial([2.0, -1.0, 0.5][:n])
    q = np.linspace(-1.0, 4.0, 11)
    assert np.allclose(interp_spline(x, poly(x))(q), poly(q), atol=EXACT)


def test_knot_slopes_of_a_cubic_are_its_derivative():
    x = np.array([0.0, 0.3, 1.1, 1.5, 2.6, 3.0, 4.2])
    y = np.column_stack([x ** 3 - 2.0 * x, 0.5 * x ** 2 + 1.0])
    got = knot_slopes_runs(np.concatenate([x, x + 10.0]), np.concatenate([y, y]), np.array([0, 7]),
                           np.array([7, 7]))
    want = np.column_stack([3.0 * x ** 2 - 2.0, x])
    assert np.allclose(got, np.concatenate([want, want]), rtol=CUBIC_REL, atol=CUBIC_REL)


def test_runs_are_each_runs_cubic_spline():
    """Runs side by side (one starting where the one before ends, one below it) in one solve: each
    run's slopes and Hermite values are those of scipy's CubicSpline through that run alone."""
    from scipy.interpolate import CubicSpline  # noqa: PLC0415

    rng = np.random.default_rng(11)
    sizes = [4, 5, 9, 300, 4, 6]
    xs = [np.cumsum(rng.uniform(0.1, 2.0, n)) for n in sizes]
    xs[2] = xs[2] - xs[2][0] + xs[1][-1]  # a run starting where the one before ends (h = 0 across)
    xs[4] = xs[4] - 50.0  # and one starting below it
    ys = [rng.normal(size=(n, 2)) * 40.0 for n in sizes]
    first = np.cumsum(sizes) - np.array(sizes)
    x, y = np.concatenate(xs), np.concatenate(ys)
    slopes = knot_slopes_runs(x, y, first, np.array(sizes))
    for j, (xr, yr) in enumerate(zip(xs, ys)):
        ref = CubicSpline(xr, yr, axis=0)
        got = slopes[first[j]:first[j] + sizes[j]]
        assert np.max(np.abs(got - ref(xr, 1))) <= SAME_AS_SCIPY * (1.0 + np.max(np.abs(ref(xr, 1))))
        q = np.sort(rng.uniform(xr[0], xr[-1], 50))
        i = first[j] + np.clip(np.searchsorted(xr, q, side="right") - 1, 0, xr.size - 2)
        for order in (0, 1, 2):
            want = ref(q, order)
            assert np.max(np.abs(hermite(x, y, slopes, i, q, order) - want)) <= SAME_AS_SCIPY * (1.0 + np.max(np.abs(want)))


def test_a_vector_bspline_as_piecewise_polynomials_reads_as_the_bspline():
    """piecewise: a quintic B-spline of three columns as one PPoly, against scipy's BSpline read at
    the same stations (inside the knots, where the repeated end knots' empty pieces are dropped)."""
    from winder.geometry.interp import piecewise  # noqa: PLC0415

    x = _sites(30, 7)
    y = np.column_stack([np.sin(x), np.cos(0.3 * x), x**2 / 50.0])
    spline = interp_spline(x, y, 5)
    pp = piecewise(spline)
    assert np.all(np.diff(pp.x) > 0.0)
    q = np.linspace(x[0], x[-1], 997)
    for nu in range(4):
        want = spline(q, nu)
        np.testing.assert_allclose(pp(q, nu), want, rtol=0.0, atol=SAME_AS_SCIPY * np.abs(want).max())


def test_a_jet_stacks_each_piece_with_its_derivatives():
    """jet: a vector piece with three derivatives and, on the same breakpoints, a scalar one of lower
    degree alone, read in one call, against scipy's derivative of each read alone (past both ends)."""
    from winder.geometry.interp import jet, piecewise  # noqa: PLC0415

    x = _sites(20, 3)
    vector = piecewise(interp_spline(x, np.column_stack([np.sin(x), np.exp(-0.1 * x)]), 5))
    scalar = piecewise(interp_spline(x, np.cos(x), 5)).derivative(2)  # a cubic
    table = jet([(vector, 3), (scalar, 0)])
    q = np.linspace(x[0] - 0.5, x[-1] + 0.5, 301)
    want = np.column_stack([vector.derivative(j)(q) if j else vector(q) for j in range(4)] + [scalar(q)])
    assert table(q).shape == (q.size, 9)
    np.testing.assert_allclose(table(q), want, rtol=0.0, atol=SAME_AS_SCIPY * np.abs(want).max())

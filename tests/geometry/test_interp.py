"""Interpolating splines in numpy (winder.geometry.interp): polynomials reproduced, scipy's splines matched."""

from __future__ import annotations

import numpy as np
import pytest

from winder.geometry.interp import InterpSpline, _knot_slopes, interp_spline, knot_slopes_runs
from roundoff import assert_roundoff

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
    spline = InterpSpline(x, poly(x), k)
    q = np.linspace(x[0] - 0.3, x[-1] + 0.3, 301)  # extrapolation too: the end pieces are the polynomial
    scale = np.max(np.abs(poly(q)))
    for nu in range(min(k, 3) + 1):
        assert np.max(np.abs(spline(q, nu) - poly.deriv(nu)(q))) <= EXACT * scale


@pytest.mark.parametrize("n", [4, 5, 40])
def test_the_hermite_cubic_reproduces_cubics(n):
    x = _sites(n, n + 1)
    poly = np.polynomial.Polynomial([0.5, -1.0, 0.3, 0.02])
    spline = interp_spline(x, poly(x))
    q = np.linspace(x[0] - 0.3, x[-1] + 0.3, 301)
    scale = np.max(np.abs(poly(q)))
    for nu in range(4):
        assert np.max(np.abs(spline(q, nu) - poly.deriv(nu)(q))) <= EXACT * scale
        assert np.max(np.abs(spline.derivative()(q, nu) - poly.deriv(nu + 1)(q))) <= EXACT * scale


@pytest.mark.parametrize("n", [2, 3])
def test_few_points_give_the_line_and_the_parabola(n):
    x = np.array([0.0, 1.0, 3.0])[:n]
    poly = np.polynomial.Polynomial([2.0, -1.0, 0.5][:n])
    q = np.linspace(-1.0, 4.0, 11)
    assert np.allclose(interp_spline(x, poly(x))(q), poly(q), atol=EXACT)


@pytest.mark.parametrize("n", [4, 7, 50, 600])
def test_the_cubic_is_scipys_not_a_knot_cubic_spline(n):
    from scipy.interpolate import CubicSpline  # noqa: PLC0415

    x = _sites(n, n)
    y = np.sin(x) + 0.1 * np.cos(3.0 * x)
    q = np.linspace(x[0], x[-1], 997)
    ref, got = CubicSpline(x, y), interp_spline(x, y)
    for nu in range(3):
        assert np.max(np.abs(got(q, nu) - ref(q, nu))) <= SAME_AS_SCIPY * (1.0 + np.max(np.abs(ref(q, nu))))
    d_ref, d_got = ref.derivative(), got.derivative()
    assert np.max(np.abs(d_got(q) - d_ref(q))) <= SAME_AS_SCIPY * (1.0 + np.max(np.abs(d_ref(q))))


@pytest.mark.parametrize("k", [3, 5])
def test_matches_make_interp_spline_on_columns(k):
    from scipy.interpolate import make_interp_spline  # noqa: PLC0415

    x = _sites(30, 7)
    y = np.column_stack([np.sin(x), np.exp(-0.1 * x)])
    got = InterpSpline(x, y, k)
    for nu in range(3):
        ref = np.column_stack([make_interp_spline(x, y[:, j], k=k)(x, nu) for j in range(2)])
        assert got(x, nu).shape == (30, 2)
        assert np.max(np.abs(got(x, nu) - ref)) <= SAME_AS_SCIPY * (1.0 + np.max(np.abs(ref)))


def test_refuses_even_degrees_and_unsorted_sites():
    with pytest.raises(ValueError, match="odd degree"):
        InterpSpline(np.arange(6.0), np.zeros(6), 4)
    with pytest.raises(ValueError, match="increase strictly"):
        InterpSpline(np.array([0.0, 2.0, 1.0, 3.0]), np.zeros(4), 3)


def test_knot_slopes_of_runs_are_each_runs_alone():
    rng = np.random.default_rng(7)
    sizes = [4, 5, 9, 30, 4]
    xs = [np.cumsum(rng.uniform(0.1, 2.0, n)) for n in sizes]
    ys = [rng.normal(size=(n, 2)) for n in sizes]
    first = np.cumsum(sizes) - np.array(sizes)
    got = knot_slopes_runs(np.concatenate(xs), np.concatenate(ys), first, np.array(sizes))
    want = np.concatenate([_knot_slopes(x, y) for x, y in zip(xs, ys)])
    assert_roundoff(got, want)


def test_knot_slopes_of_a_cubic_are_its_derivative():
    x = np.array([0.0, 0.3, 1.1, 1.5, 2.6, 3.0, 4.2])
    y = np.column_stack([x ** 3 - 2.0 * x, 0.5 * x ** 2 + 1.0])
    got = knot_slopes_runs(np.concatenate([x, x + 10.0]), np.concatenate([y, y]), np.array([0, 7]),
                           np.array([7, 7]))
    want = np.column_stack([3.0 * x ** 2 - 2.0, x])
    assert np.allclose(got, np.concatenate([want, want]), rtol=CUBIC_REL, atol=CUBIC_REL)


def _slopes_by_index(x, y, first, sizes):
    """knot_slopes_runs' system assembled row by row of index arrays (interior rows only, then the
    ends): its reference."""
    from winder.geometry.lapack import lapack  # noqa: PLC0415

    h = np.diff(x)
    with np.errstate(all="ignore"):
        d = np.diff(y, axis=0) / h[:, None]
    n, last = x.size, first + sizes - 1
    inner = np.ones(n, dtype=bool)
    inner[first] = inner[last] = False
    r = np.nonzero(inner)[0]
    diag, upper, lower, rhs = np.empty(n), np.zeros(n - 1), np.zeros(n - 1), np.empty_like(y)
    diag[r] = 2.0 * (h[r - 1] + h[r])
    upper[r] = h[r - 1]
    lower[r - 1] = h[r]
    rhs[r] = 3.0 * (h[r, None] * d[r - 1] + h[r - 1, None] * d[r])
    h0, h1, hl, hm = h[first], h[first + 1], h[last - 1], h[last - 2]
    s0, s1 = h0 + h1, hl + hm
    diag[first], upper[first] = h1, s0
    rhs[first] = ((h0 + 2.0 * s0) * h1)[:, None] * d[first] + np.array([v ** 2 for v in h0])[:, None] * d[first + 1]
    rhs[first] /= s0[:, None]
    diag[last], lower[last - 1] = hm, s1
    rhs[last] = np.array([v ** 2 for v in hl])[:, None] * d[last - 2] + ((2.0 * s1 + hl) * hm)[:, None] * d[last - 1]
    rhs[last] /= s1[:, None]
    return lapack().dgtsv(lower, diag, upper, rhs)[3]


def test_knot_slopes_of_runs_are_the_system_of_index_rows_bit_for_bit():
    rng = np.random.default_rng(11)
    sizes = [4, 5, 9, 300, 4, 6]
    xs = [np.cumsum(rng.uniform(0.1, 2.0, n)) for n in sizes]
    xs[2] = xs[2] - xs[2][0] + xs[1][-1]  # a run starting where the one before ends (h = 0 across)
    xs[4] = xs[4] - 50.0  # and one starting below it
    ys = [rng.normal(size=(n, 2)) * 40.0 for n in sizes]
    first = np.cumsum(sizes) - np.array(sizes)
    x, y = np.concatenate(xs), np.concatenate(ys)
    got = knot_slopes_runs(x, y, first, np.array(sizes))
    assert_roundoff(got, _slopes_by_index(x, y, first, np.array(sizes)))
    one = knot_slopes_runs(xs[3], ys[3], np.array([0]), np.array([300]))
    assert_roundoff(one, _slopes_by_index(xs[3], ys[3], np.array([0]), np.array([300])))

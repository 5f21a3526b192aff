"""The index splines against scipy's CubicSpline(i, y, bc_type="not-a-knot"), the spline they claim to be."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from winder.geometry.index_spline import knot_slopes, resample_index, segment_nodes
from roundoff import assert_roundoff

SPLINE_TOL = 1e-12  # relative to the data's scale: two evaluations of one cubic in double precision


def _data(m: int) -> np.ndarray:
    rng = np.random.default_rng(m)
    return np.cumsum(rng.normal(size=(m, 2)), axis=0) * 10.0


@pytest.mark.parametrize("m", [4, 5, 9, 33])
def test_knot_slopes_are_scipys(m: int) -> None:
    y = _data(m)
    ref = CubicSpline(np.arange(m), y, bc_type="not-a-knot")(np.arange(m), 1)
    assert np.max(np.abs(knot_slopes(y) - ref)) <= SPLINE_TOL * np.max(np.abs(y))


# 2m - 1, 8m - 7 and 32m - 31 are the power-of-two refinements (the solver's levels); the others
# take the general gather
@pytest.mark.parametrize("m", [4, 9, 33])
@pytest.mark.parametrize("factor", [1, 2, 8, 32, 3, None])
def test_resample_is_scipys_spline_at_equal_fractions(m: int, factor: int | None) -> None:
    y = _data(m)
    count = m + 5 if factor is None else factor * (m - 1) + 1
    x = np.linspace(0.0, m - 1.0, count)
    ref = CubicSpline(np.arange(m), y, bc_type="not-a-knot")(x)
    out = resample_index(y, count)
    assert out.shape == (count, 2)
    assert np.max(np.abs(out - ref)) <= SPLINE_TOL * np.max(np.abs(y))
    assert np.array_equal(out[[0, -1]], y[[0, -1]])  # the ends are kept exactly


def test_segment_nodes_values_and_slopes_are_scipys() -> None:
    m, fractions = 17, np.array([0.1, 0.5, 0.9])
    y = _data(m)
    spline = CubicSpline(np.arange(m), y, bc_type="not-a-knot")
    x = (np.arange(m - 1)[:, None] + fractions).ravel()
    vals, ders = segment_nodes(y, knot_slopes(y), fractions)
    scale = np.max(np.abs(y))
    assert np.max(np.abs(vals - spline(x))) <= SPLINE_TOL * scale
    assert np.max(np.abs(ders - spline(x, 1))) <= SPLINE_TOL * scale


@pytest.mark.parametrize("m", [4, 33, 1001])
@pytest.mark.parametrize("factor", [2, 8, None])
def test_resample_and_nodes_are_hermites_bit_for_bit(m: int, factor: int | None) -> None:
    # The component-major layouts compute each node with _hermite's own arithmetic, point by point.
    from winder.geometry.index_spline import _hermite  # noqa: PLC0415

    y = _data(m)
    dy = knot_slopes(y)
    count = 8 * m + 3 if factor is None else factor * (m - 1) + 1
    x = np.linspace(0.0, m - 1.0, count)
    k = np.minimum(x.astype(int), m - 2)
    ref = _hermite(y[k], dy[k], y[k + 1], dy[k + 1], (x - k)[:, None])
    ref[[0, -1]] = y[[0, -1]]
    if factor is not None:  # the refinement's fractions j / factor, each segment from its left knot
        t = np.tile(np.arange(factor) / factor, m - 1)
        k = np.repeat(np.arange(m - 1), factor)
        ref[:-1] = _hermite(y[k], dy[k], y[k + 1], dy[k + 1], t[:, None])
        ref[0] = y[0]
    assert_roundoff(resample_index(y, count), ref)
    fractions = np.array([0.2, 0.5, 0.7])
    t = np.tile(fractions, m - 1)[:, None]
    k = np.repeat(np.arange(m - 1), 3)
    vals, ders = segment_nodes(y, dy, fractions)
    assert_roundoff(vals, _hermite(y[k], dy[k], y[k + 1], dy[k + 1], t))
    assert_roundoff(ders, _hermite(y[k], dy[k], y[k + 1], dy[k + 1], t, derivative=True))

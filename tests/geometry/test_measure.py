"""winder.geometry.measure: its quadrature rule, row norms, lengths and tangent coordinates against
numpy's and LAPACK's, to round-off."""

from __future__ import annotations

import numpy as np

from winder.geometry.measure import GAUSS_NODES, GAUSS_W, GAUSS_X
from roundoff import assert_roundoff

POLY_TOL = 1e-15
NORM_RTOL = 4.0 * np.finfo(float).eps  # a sum of k <= 8 squares in another order, and its square root
LENGTH_RTOL = 1e-13  # ~3,000 positive terms summed in another order (pairwise or in lanes)
SOLVE_RTOL = 1e-12  # a 2 x 2 solve of an exactly consistent system
LSTSQ_RTOL = 1e-8  # normal equations against an SVD: the Gram system squares the (random) condition


def test_gauss_rule_is_leggauss() -> None:
    x, w = np.polynomial.legendre.leggauss(GAUSS_NODES)
    assert_roundoff(GAUSS_X, x, rtol=POLY_TOL)
    assert_roundoff(GAUSS_W, w, rtol=POLY_TOL)


def test_gauss_rule_integrates_degree_2n_minus_1_exactly() -> None:
    for degree in range(2 * GAUSS_NODES):
        exact = 0.0 if degree % 2 else 2.0 / (degree + 1)
        assert abs(GAUSS_W @ GAUSS_X**degree - exact) < POLY_TOL


def test_row_norms_are_numpys() -> None:
    from winder.geometry.measure import row_norms  # noqa: PLC0415

    rng = np.random.default_rng(3)
    for k in (1, 2, 3, 4, 7, 8, 11):
        v = rng.normal(size=(5000, k)) * rng.lognormal(0.0, 8.0, size=(5000, 1))
        assert np.allclose(row_norms(v), np.linalg.norm(v, axis=1), rtol=NORM_RTOL, atol=0.0), k
    w = rng.normal(size=(50, 6))[:, ::2]  # not contiguous
    assert np.allclose(row_norms(w), np.linalg.norm(w, axis=1), rtol=NORM_RTOL, atol=0.0)
    assert row_norms(np.zeros((0, 3))).shape == (0,)


def test_speed_along_rows_is_the_norm_of_the_velocity() -> None:
    from winder.geometry.measure import _speed  # noqa: PLC0415

    rng = np.random.default_rng(3)
    ps, pt, du = rng.normal(size=(3, 2003)), rng.normal(size=(3, 2003)), rng.normal(size=(2, 2003))
    vel = ps * du[0] + pt * du[1]
    assert np.allclose(_speed(ps, pt, du), np.linalg.norm(vel, axis=0), rtol=NORM_RTOL, atol=0.0)


def test_smooth_length_on_the_quarter_bend_is_the_row_wise_formulas(quarter_bend) -> None:
    from winder.geometry.index_spline import LOBATTO_T, LOBATTO_W_END, LOBATTO_W_MID, knot_slopes, segment_nodes  # noqa: PLC0415
    from winder.geometry.measure import smooth_length  # noqa: PLC0415
    from winder.paths.geodesic import geodesic  # noqa: PLC0415

    surface = quarter_bend
    res = geodesic(surface, (10.0, 0.3), (220.0, 2.0), rounds=1, n=1000, estimate=False)
    y = np.stack([res.s, res.theta], axis=1)
    dy = knot_slopes(y)
    u, du = segment_nodes(y, dy, LOBATTO_T)
    ev = surface.evaluate(np.concatenate([res.s, u[:, 0]]), np.concatenate([res.theta, u[:, 1]]), order=1)
    d = np.concatenate([dy, du])
    vel = np.ascontiguousarray(ev.ps) * d[:, :1] + np.ascontiguousarray(ev.pt) * d[:, 1:]
    speed = np.sqrt(np.einsum("ij,ij->i", vel, vel))
    m = res.s.shape[0]
    ref = float(LOBATTO_W_END * (2.0 * np.sum(speed[:m]) - speed[0] - speed[m - 1]) + LOBATTO_W_MID * np.sum(speed[m:]))
    assert abs(smooth_length(surface, res.s, res.theta, gauss_segments=0) - ref) <= LENGTH_RTOL * ref


def test_tangent_coordinates_are_the_least_squares_solution() -> None:
    """Against numpy's least squares (an SVD: another method) of each 3 x 2 system."""
    from winder.geometry.measure import tangent_coordinates  # noqa: PLC0415

    rng = np.random.default_rng(7)
    for n in (1, 2, 3, 7, 500):
        ps = rng.normal(size=(3, n)) * rng.lognormal(0.0, 3.0, size=n)
        pt = rng.normal(size=(3, n)) * rng.lognormal(0.0, 3.0, size=n)
        v = rng.normal(size=(3, n))
        a, b = tangent_coordinates(ps, pt, v)
        ref = np.array([np.linalg.lstsq(np.column_stack([ps[:, j], pt[:, j]]), v[:, j], rcond=None)[0]
                        for j in range(n)])
        # relative to each coordinate's scale: |v| / |Phi| times the system's condition
        scale = np.linalg.norm(v, axis=0) / np.minimum(np.linalg.norm(ps, axis=0), np.linalg.norm(pt, axis=0))
        assert np.all(np.abs(a - ref[:, 0]) <= LSTSQ_RTOL * scale) and np.all(np.abs(b - ref[:, 1]) <= LSTSQ_RTOL * scale)
        # the projection's residual is normal to both tangents
        res = v - ps * a - pt * b
        assert np.max(np.abs(np.sum(res * ps, axis=0)) / np.sum(ps * ps, axis=0) ** 0.5) < 1e-9


def test_tangent_coordinates_of_an_exact_system_and_the_pivot_row() -> None:
    from winder.geometry.measure import tangent_coordinates  # noqa: PLC0415

    # ps = (1, 0, 0), pt = (1, 2, 0): v = 3 ps + 0.5 pt exactly; and the same with the larger entry
    # of G's first column in its second row (ps = (0.5, 0, 0)), where LU swaps the rows.
    for ps0, a0 in ((1.0, 3.0), (0.5, 6.0)):
        ps, pt = np.array([[ps0], [0.0], [0.0]]), np.array([[1.0], [2.0], [0.0]])
        a, b = tangent_coordinates(ps, pt, ps * a0 + pt * 0.5)
        assert abs(a[0] - a0) <= SOLVE_RTOL * a0 and abs(b[0] - 0.5) <= SOLVE_RTOL


def test_tangent_coordinates_refuse_a_singular_system_as_before() -> None:
    import pytest  # noqa: PLC0415

    from winder.geometry.measure import tangent_coordinates  # noqa: PLC0415

    ps = np.array([[1.0, 1.0], [0.0, 0.0], [0.0, 0.0]])
    pt = np.array([[1.0, 2.0], [2.0, 0.0], [0.0, 0.0]])  # the second pair is parallel
    with pytest.raises(np.linalg.LinAlgError):
        tangent_coordinates(ps, pt, np.ones((3, 2)))
    tiny = np.array([[1e-160], [0.0], [0.0]])  # G's entry 1e-320 is subnormal: v = ps + 2 pt still
    a, b = tangent_coordinates(tiny, np.array([[0.0], [1.0], [0.0]]), np.array([[1e-160], [2.0], [0.0]]))
    assert abs(a[0] - 1.0) <= SOLVE_RTOL and abs(b[0] - 2.0) <= SOLVE_RTOL


def test_grid_groups_gather_rows_within_a_cell_and_keep_the_lowest_row() -> None:
    """Rows equal to round-off share a group whose first row is their lowest; rows a grid cell or
    more apart do not; every row lies within the grid of its group's first row, column by column."""
    from winder.geometry.measure import grid_groups  # noqa: PLC0415

    rng = np.random.default_rng(3)
    base = rng.uniform(-500.0, 500.0, (50, 3))
    keys = np.tile(base, (20, 1)) + rng.uniform(-1e-13, 1e-13, (1000, 3))
    keys[::7, 1] += 1e-6  # one column a thousand cells away: another group
    grid = np.array([1e-9, 1e-9, 1e-12])
    first, group = grid_groups(keys, grid)
    assert np.all(np.abs(keys - keys[first][group]) < grid)
    for g in range(first.size):
        assert first[g] == np.flatnonzero(group == g).min()
    apart = np.abs(keys[:, None, 1] - keys[None, :, 1]) > 1e-7
    assert not np.any(apart & (group[:, None] == group[None, :]))
    assert 100 <= first.size <= 200  # base rows in two families, split only at a cell's edge

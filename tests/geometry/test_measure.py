"""winder.geometry.measure: its quadrature rule is numpy's Gauss-Legendre rule, bit for bit."""

from __future__ import annotations

import numpy as np

from winder.geometry.measure import GAUSS_NODES, GAUSS_W, GAUSS_X

POLY_TOL = 1e-15


def test_gauss_rule_is_leggauss_bit_for_bit() -> None:
    x, w = np.polynomial.legendre.leggauss(GAUSS_NODES)
    assert np.array_equal(GAUSS_X, x) and np.array_equal(GAUSS_W, w)


def test_gauss_rule_integrates_degree_2n_minus_1_exactly() -> None:
    for degree in range(2 * GAUSS_NODES):
        exact = 0.0 if degree % 2 else 2.0 / (degree + 1)
        assert abs(GAUSS_W @ GAUSS_X**degree - exact) < POLY_TOL


def test_row_norms_are_numpys_bit_for_bit() -> None:
    from winder.geometry.measure import row_norms  # noqa: PLC0415

    rng = np.random.default_rng(3)
    for k in (1, 2, 3, 4, 7, 8, 11):
        v = rng.normal(size=(5000, k)) * rng.lognormal(0.0, 8.0, size=(5000, 1))
        assert np.array_equal(row_norms(v), np.linalg.norm(v, axis=1)), k
    w = rng.normal(size=(50, 6))[:, ::2]  # not contiguous
    assert np.array_equal(row_norms(w), np.linalg.norm(w, axis=1))
    assert row_norms(np.zeros((0, 3))).shape == (0,)


def test_speed_along_rows_sums_the_components_in_order() -> None:
    # v_x^2 + v_y^2 + v_z^2 left to right, as row_norms; einsum over C-ordered (q, 3) rows may group
    # the three terms otherwise (1 ulp on random data), so the solver's lengths are checked below
    from winder.geometry.measure import _speed  # noqa: PLC0415

    rng = np.random.default_rng(3)
    ps, pt, du = rng.normal(size=(3, 2003)), rng.normal(size=(3, 2003)), rng.normal(size=(2, 2003))
    vel = ps * du[0] + pt * du[1]
    assert np.array_equal(_speed(ps, pt, du), np.sqrt(vel[0] * vel[0] + vel[1] * vel[1] + vel[2] * vel[2]))


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
    assert smooth_length(surface, res.s, res.theta, gauss_segments=0) == ref


def _gram_solve(ps: np.ndarray, pt: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The batched LAPACK solve of the stacked Gram systems: tangent_coordinates' reference."""
    basis = np.stack([ps.T, pt.T], axis=2)
    g = np.einsum("nki,nkj->nij", basis, basis)
    return np.linalg.solve(g, np.einsum("nki,nk->ni", basis, v.T)[..., None])[..., 0]


def test_tangent_coordinates_solve_the_gram_system_as_lapack() -> None:
    from winder.geometry.measure import tangent_coordinates  # noqa: PLC0415

    rng = np.random.default_rng(7)
    for n in (1, 2, 3, 7, 5000):
        ps = rng.normal(size=(3, n)) * rng.lognormal(0.0, 3.0, size=n)
        pt = rng.normal(size=(3, n)) * rng.lognormal(0.0, 3.0, size=n)
        v = rng.normal(size=(3, n))
        a, b = tangent_coordinates(ps, pt, v)
        ref = _gram_solve(ps, pt, v)
        # The same operations as LAPACK's LU (bit for bit on the builds checked); a build whose
        # kernels fuse or reorder them differs in the last bits only.
        assert np.allclose(a, ref[:, 0], rtol=1e-12, atol=0.0) and np.allclose(b, ref[:, 1], rtol=1e-12, atol=0.0)
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
        assert a[0] == a0 and b[0] == 0.5


def test_tangent_coordinates_refuse_a_singular_system_as_before() -> None:
    import pytest  # noqa: PLC0415

    from winder.geometry.measure import tangent_coordinates  # noqa: PLC0415

    ps = np.array([[1.0, 1.0], [0.0, 0.0], [0.0, 0.0]])
    pt = np.array([[1.0, 2.0], [2.0, 0.0], [0.0, 0.0]])  # the second pair is parallel
    with pytest.raises(np.linalg.LinAlgError):
        tangent_coordinates(ps, pt, np.ones((3, 2)))
    tiny = np.array([[1e-160], [0.0], [0.0]])  # G's pivot 1e-320 is subnormal: LAPACK's own solve
    a, b = tangent_coordinates(tiny, np.array([[0.0], [1.0], [0.0]]), np.array([[1e-160], [2.0], [0.0]]))
    ref = _gram_solve(tiny, np.array([[0.0], [1.0], [0.0]]), np.array([[1e-160], [2.0], [0.0]]))
    assert np.array_equal(a, ref[:, 0]) and np.array_equal(b, ref[:, 1])

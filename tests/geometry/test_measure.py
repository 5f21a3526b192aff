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

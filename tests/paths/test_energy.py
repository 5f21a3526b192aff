"""The banded Newton solve against a dense solve of the same block-tridiagonal Hessian."""

from __future__ import annotations

import numpy as np
import pytest

from winder.paths.energy import chain_terms, chord_direction, newton_direction
from winder.paths.geodesic import straight_path
from roundoff import assert_roundoff

SOLVE_REL = 1e-10  # banded Cholesky against numpy's dense LU, relative to the step


def _dense(diag: np.ndarray, off: np.ndarray) -> np.ndarray:
    """The interleaved (s_1, theta_1, s_2, ...) matrix from diag (3, n) [ss, st, tt] and off (4, n - 1)."""
    n = diag.shape[1]
    h = np.zeros((2 * n, 2 * n))
    for i in range(n):
        h[2 * i:2 * i + 2, 2 * i:2 * i + 2] = [[diag[0, i], diag[1, i]], [diag[1, i], diag[2, i]]]
        if i < n - 1:
            block = np.array([[off[0, i], off[1, i]], [off[2, i], off[3, i]]])
            h[2 * i:2 * i + 2, 2 * i + 2:2 * i + 4] = block
            h[2 * i + 2:2 * i + 4, 2 * i:2 * i + 2] = block.T
    return h


@pytest.mark.parametrize("surface_name", ["quarter_bend", "elliptic_tube"])
@pytest.mark.parametrize("n", [1, 2, 17])
def test_newton_and_chord_steps_solve_the_hessian(request, surface_name, n):
    surface = request.getfixturevalue(surface_name)
    s, th = straight_path(0.2 * surface.length, 0.1, 0.8 * surface.length, 4.0, n)
    # Off the minimizer: a wavy path, so the gradient and the curvature term are not small.
    th[1:-1] += 0.05 * np.sin(np.arange(1, n + 1))
    ev = surface.evaluate(s[1:-1], th[1:-1], order=2)
    ends = surface.evaluate(s[[0, -1]], th[[0, -1]], order=0).p
    _, grad, gram, curv, off = chain_terms(ev, ends)
    solved = 0
    for diag in (gram, gram + curv):
        dense = _dense(diag, off)
        if np.linalg.eigvalsh(dense).min() <= 0.0:
            continue  # not positive definite: newton_direction reports it, checked below
        solved += 1
        truth = np.linalg.solve(dense, -grad.ravel()).reshape(-1, 2)
        step, factor = newton_direction(diag, off, grad)
        assert np.abs(step - truth).max() <= SOLVE_REL * np.abs(truth).max()
        again = chord_direction(factor, grad)
        assert np.abs(again - truth).max() <= SOLVE_REL * np.abs(truth).max()
    assert solved >= 1  # the Gauss-Newton matrix at least is positive definite


def test_indefinite_hessian_is_reported():
    diag = np.array([[1.0, 1.0], [2.0, 0.0], [1.0, 1.0]])  # first block [[1, 2], [2, 1]]: indefinite
    off = np.zeros((4, 1))
    step, factor = newton_direction(diag, off, np.ones((2, 2)))
    assert step is None and factor is None


@pytest.mark.parametrize("surface_name", ["quarter_bend", "elliptic_tube"])
def test_hessian_entries_match_the_plain_dot_products(request, surface_name):
    """chain_terms' dot products along the evaluation's contiguous rows: the same sums as the row-wise
    einsum over the (m, 3) fields themselves, to round-off."""
    surface = request.getfixturevalue(surface_name)
    s, th = straight_path(0.0, 0.0, surface.length, 2.0 * np.pi + 1.0, 500)
    ev = surface.evaluate(s[1:-1], th[1:-1], order=2)
    _, _, gram, _, off = chain_terms(ev, surface.points(s[[0, -1]], th[[0, -1]]))
    ps, pt = ev.ps, ev.pt
    dot = lambda a, b: np.einsum("ij,ij->i", a, b)  # noqa: E731
    assert_roundoff(gram, 4.0 * np.array([dot(ps, ps), dot(ps, pt), dot(pt, pt)]))
    assert_roundoff(off, -2.0 * np.array([dot(ps[:-1], ps[1:]), dot(ps[:-1], pt[1:]),
                                          dot(pt[:-1], ps[1:]), dot(pt[:-1], pt[1:])]))

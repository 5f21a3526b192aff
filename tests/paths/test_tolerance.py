"""Tolerance mode's shortcuts against the full solves they replace: the length-settled Newton stop,
the predicted first pair and the Gauss-Lobatto length, each with the bound checked against the truth."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import ellipse_arc
from winder.geometry.measure import smooth_length
from winder.paths.geodesic import _lengths, _predicted_points, geodesic, solve_path, straight_path
from winder.paths.resolution import coarsest_points
from winder.paths.newton import LENGTH_SHARE, StopReason
from roundoff import assert_roundoff

LEVELS = (1e-6, 1e-9, 1e-12)
LOBATTO_SHARE = 1e-2  # Gauss-Lobatto's length against 5-point Gauss, as a share of the length's error


@pytest.fixture(scope="module")
def tube_case(elliptic_tube):
    truth = float(np.hypot(400.0, ellipse_arc(60.0, 35.0, 0.0, np.pi / 2 + 4 * np.pi)))
    return elliptic_tube, (0.0, 0.0), (400.0, np.pi / 2), 2, truth


@pytest.fixture(scope="module")
def cone_case(cone):
    sin_b = 0.1 / np.sqrt(1.01)
    rho = (60.0 - 0.1 * np.array([10.0, 290.0])) / sin_b
    dth = np.radians(250.0) + 2 * np.pi
    truth = float(np.sqrt(rho[0]**2 + rho[1]**2 - 2 * rho[0] * rho[1] * np.cos(dth * sin_b)))
    return cone, (10.0, 0.0), (290.0, np.radians(250.0)), 1, truth


@pytest.fixture(scope="module")
def bend_case(quarter_bend):
    # The truth from a converged fine solve: the bend has no closed form, and shooting's own error
    # (about 1e-13 of the length) would decide the comparison at 1e-12.
    a, b = (0.0, 0.0), (quarter_bend.axial_length, np.pi / 2)
    fine = geodesic(quarter_bend, a, b, rounds=1, n=6000)
    assert fine.smooth_error_estimate < 1e-14 * fine.length
    return quarter_bend, a, b, 1, fine.length


@pytest.mark.parametrize("name", ["tube", "cone", "bend"])
@pytest.mark.parametrize("level", LEVELS)
def test_tolerance_mode_bound_holds(name, level, request):
    """The bound meets the tolerance and bounds the true error, by a factor near 1.9; n is within 2x of
    the least n whose true error meets the tolerance (half of n does not)."""
    surface, a, b, rounds, truth = request.getfixturevalue(f"{name}_case")
    tol = level * truth
    res = geodesic(surface, a, b, rounds=rounds, tolerance=tol)
    err = abs(res.length - truth)
    assert res.converged and res.smooth_error_estimate < tol
    assert err <= res.smooth_error_estimate
    if level > 1e-12:  # at 1e-12 roundoff is part of the error and the ratio varies
        assert res.smooth_error_estimate <= 2.5 * err
        half = geodesic(surface, a, b, rounds=rounds, n=res.n // 2, estimate=False)
        assert abs(half.length - truth) > tol


@pytest.mark.parametrize("n", [54, 165, 929])
@pytest.mark.parametrize("level", LEVELS)
def test_length_settled_stop_moves_the_length_by_a_share_of_the_tolerance(tube_case, n, level):
    """A warm solve that stops on the length tolerance: its length within LENGTH_SHARE of the
    tolerance of the fully converged solve's."""
    surface, a, b, rounds, truth = tube_case
    tol = level * truth
    s0, s1 = (float(v) for v in surface.s_of_t(np.array([a[0], b[0]])))
    s, th = straight_path(s0, a[1], s1, b[1] + 2 * np.pi * rounds, 1)
    coarse = solve_path(surface, s, th, (n - 1) // 2)
    full = solve_path(surface, coarse.s, coarse.theta, n, warm=True)
    quick = solve_path(surface, coarse.s, coarse.theta, n, warm=True, length_tol=tol)
    assert full.reason is StopReason.STEP and quick.converged
    assert quick.iterations <= full.iterations
    assert abs(_lengths(surface, quick) - _lengths(surface, full)) <= LENGTH_SHARE * tol


@pytest.mark.parametrize("n", [54, 109, 165, 255])
def test_lobatto_length_error_is_a_small_share_of_the_lengths(tube_case, n):
    """The tolerance mode's Gauss-Lobatto length against the 5-point Gauss one, from the coarsest n
    (24 points per round) on: its quadrature error is a small share of the length's own error, so the
    pair (n, 2n + 1) still bounds the sum."""
    surface, a, b, rounds, truth = tube_case
    res = geodesic(surface, a, b, rounds=rounds, n=n, estimate=False)
    gauss = smooth_length(surface, res.s, res.theta)
    lobatto = smooth_length(surface, res.s, res.theta, gauss_segments=0)
    assert abs(lobatto - gauss) <= LOBATTO_SHARE * abs(gauss - truth)


def test_prediction_makes_one_pair_after_the_coarsest_solve(tube_case):
    """At 1e-9 the predicted n is met by the first pair: no coarsest pair, no second pair."""
    surface, a, b, rounds, truth = tube_case
    res = geodesic(surface, a, b, rounds=rounds, tolerance=1e-9 * truth)
    n0 = coarsest_points(rounds + 0.25)
    assert [lv.n for lv in res.levels] == [n0, res.n, 2 * res.n + 1]
    s0, s1 = (float(v) for v in surface.s_of_t(np.array([a[0], b[0]])))
    coarse = solve_path(surface, *straight_path(s0, a[1], s1, b[1] + 2 * np.pi * rounds, n0), n0)
    assert _predicted_points(coarse, 1e-9 * truth) == pytest.approx(res.n, rel=0.02)


def test_path_measures_keep_numpys_norms_bit_for_bit():
    """polyline_length, spacing_deviation and geodesic_curvature take row_norms for np.linalg.norm."""
    from winder.geometry.measure import geodesic_curvature, polyline_length, spacing_deviation  # noqa: PLC0415

    rng = np.random.default_rng(5)
    pts = np.cumsum(rng.normal(size=(257, 3)), axis=0)
    lens = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    assert polyline_length(pts) == float(np.sum(lens))
    assert spacing_deviation(pts) == float(np.max(np.abs(lens / lens.mean() - 1.0)))
    jac = (rng.normal(size=(255, 3)), rng.normal(size=(255, 3)))
    seg = np.diff(pts, axis=0)
    d = seg / lens[:, None]
    nrm = np.cross(jac[1], jac[0])
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    turn = np.einsum("ij,ij->i", np.cross(d[:-1], d[1:]), nrm) / (0.5 * (lens[:-1] + lens[1:]))
    assert_roundoff(geodesic_curvature(None, None, None, pts, jac=jac), turn)
    # geodesic()'s one pass over the segments gives both, the same numbers
    from winder.geometry.measure import segment_measures  # noqa: PLC0415

    assert segment_measures(pts) == (polyline_length(pts), spacing_deviation(pts))

"""The smooth length across the joints of a path guide curve (line + arc + line), where Phi_s jumps:
h^4 convergence, never below the polyline, tolerance mode's bound holding, one-piece curves untouched."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import surface_of
from winder.config.axes import ArcAxis, PathAxis
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.geometry.joints import joint_stations
from winder.geometry.measure import smooth_length, smooth_lengths
from winder.paths.geodesic import geodesic
from roundoff import assert_roundoff

TRUTH_POINTS = 6400  # the truth: Richardson on the polyline at n and 2n + 1 (independent of the smooth length)
TRUTH_TOL = 1e-10  # mm: the truth's own error (n = 3200 and 12800 agree to 7e-12)
RATE = 10.0  # least error ratio per 4x n (h^4: 256; the polyline: 16)
ROUNDOFF = 1e-12  # relative


@pytest.fixture(scope="module")
def elbow():
    """Line 100 + arc R150 90 deg + line 100, tube radius 40: the elbow sample's mandrel."""
    return surface_of(PathAxis((LineAxis(100.0), ArcAxis(150.0, 90.0, 0.0), LineAxis(100.0))), ConstantProfile(40.0))


@pytest.fixture(scope="module")
def elbow_case(elbow):
    a, b = (0.0, 0.0), (435.0, np.pi)
    return elbow, a, b, geodesic(elbow, a, b, n=TRUTH_POINTS).length_extrapolated


def test_joint_stations(elbow, quarter_bend, straight_tube) -> None:
    assert_roundoff(joint_stations(elbow), [100.0, 100.0 + 150.0 * np.pi / 2])
    assert joint_stations(quarter_bend).size == 0 and joint_stations(straight_tube).size == 0
    assert joint_stations(surface_of(PathAxis((LineAxis(10.0), LineAxis(20.0))), ConstantProfile(40.0))).size == 0


def test_smooth_length_converges_at_h4_across_joints(elbow_case) -> None:
    surface, a, b, truth = elbow_case
    errors = []
    for n in (50, 200, 800):
        res = geodesic(surface, a, b, n=n)
        err = abs(res.length - truth)
        assert err < abs(res.polyline_length - truth)
        assert res.length >= res.polyline_length - ROUNDOFF * truth
        assert err <= res.smooth_error_estimate
        errors.append(err)
    assert errors[0] / errors[1] > RATE and errors[1] / errors[2] > RATE
    assert errors[2] < 1e-8 * truth


@pytest.mark.parametrize("tolerance", [1e-3, 1e-6])
def test_tolerance_mode_bound_holds_across_joints(elbow_case, tolerance) -> None:
    surface, a, b, truth = elbow_case
    res = geodesic(surface, a, b, tolerance=tolerance)
    err = abs(res.length - truth)
    assert res.converged and res.smooth_error_estimate < tolerance
    assert err + TRUTH_TOL <= res.smooth_error_estimate


@pytest.mark.parametrize("a, b", [((100.0, 0.0), (335.0, 1.0)),  # starts on a joint
                                  ((0.0, 0.0), (101.0, 3.0)),  # ends a mm past one
                                  ((335.7, 0.0), (0.0, 2.0)),  # backwards, from just past one
                                  ((90.0, 0.0), (110.0, 6.0))])  # winds round across one
def test_paths_near_and_on_joints(elbow, a, b) -> None:
    """Error below the polyline's at every n and falling; the batched lengths (Gauss and Lobatto)
    are the lengths alone, and the two rules agree."""
    truth = geodesic(elbow, a, b, n=TRUTH_POINTS).length_extrapolated
    errors = []
    for n in (40, 160):
        res = geodesic(elbow, a, b, n=n, estimate=False)
        errors.append(abs(res.length - truth))
        assert errors[-1] < abs(res.polyline_length - truth)
        for gauss in (0, 256):
            alone = smooth_length(elbow, res.s, res.theta, gauss_segments=gauss)
            assert smooth_lengths(elbow, [(res.s, res.theta, None), (res.s[::-1], res.theta[::-1], None)],
                                  gauss) == [alone, smooth_length(elbow, res.s[::-1], res.theta[::-1],
                                                                  gauss_segments=gauss)]
        assert abs(smooth_length(elbow, res.s, res.theta, gauss_segments=0) - res.length) < 1e-3 * errors[-1] + 1e-12 * truth
    assert errors[1] < errors[0] / RATE or errors[1] < 1e-11 * truth


@pytest.mark.parametrize("n", [50, 200, 400])
def test_a_hoop_on_a_joint_station_is_a_circle(elbow, n: int) -> None:
    # Its vertices sit on the station within roundoff, on one side or the other: no crossing to split.
    for t in joint_stations(elbow):
        res = geodesic(elbow, (float(t), 0.0), (float(t), 2.0 * np.pi), n=n)
        assert res.length == pytest.approx(2.0 * np.pi * 40.0, rel=ROUNDOFF)

"""A hoop over a bent axis's joints (winder.winding.layers.hoop_joints): smooth in space where a leg
meets the bend, and its band closed on every piece."""

from __future__ import annotations

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.geometry.joints import joint_stations
from winder.winding.plan import plan

KINK_TOL = 5e-5  # rad: the one-sided tangents' disagreement at a joint over a piece's own


def _elbow_hoop(toward: float):
    job = parse_config({"name": "e", "mandrel": {
        "axis": {"type": "path", "segments": [{"line": 60}, {"arc": {"radius": 150, "angle": 45, "toward": toward}},
                                              {"line": 60}]},
        "profile": {"type": "constant", "radius": 50}},
        "winding": {"band_width": 10, "region": {"start": 10, "end": 220}, "layers": [{"type": "hoop", "passes": 2}]}},
        "e.yaml")
    return plan(job)


def _kink(points: np.ndarray, at: int) -> float:
    """The angle (rad) between the one-sided second-order tangents of a polyline at point `at`: the
    points' own, so a kink of the fiber shows whatever the plan says its direction is."""
    left = 3.0 * points[at] - 4.0 * points[at - 1] + points[at - 2]
    right = -3.0 * points[at] + 4.0 * points[at + 1] - points[at + 2]
    return float(np.arccos(np.clip(left @ right / np.linalg.norm(left) / np.linalg.norm(right), -1.0, 1.0)))


@pytest.mark.parametrize("toward", [0, 90])
def test_the_fiber_is_smooth_over_a_joint(toward):
    """At a joint the points' one-sided tangents agree as they do anywhere on a piece (their own
    difference error, 3.3e-4 rad here): at one constant pitch in (t, f) they were 2e-3 to 1.1e-2 rad
    apart, the fiber kinked."""
    done = _elbow_hoop(toward)
    surf = done.surface
    joints = surf.t_of_s(joint_stations(surf))
    for fp in done.layers[0].passes:
        if fp.kind.value != "hoop":
            continue
        for j in joints:
            at = int(np.argmin(np.abs(fp.t - j)))
            assert abs(fp.t[at] - j) < 1e-9  # a planned point on the joint
            floor = max(_kink(fp.points, at - 10), _kink(fp.points, at + 10))
            assert _kink(fp.points, at) < floor + KINK_TOL


def test_every_piece_closes_its_band():
    cov = _elbow_hoop(90).layers[0].coverage
    # (the crossings' spline of f against t runs through the pitch's change at a joint: a few
    # hundredths of a millimetre of its gap are the spline's, not the band's)
    assert cov.covered_fraction >= 0.999 and cov.max_gap_mm < 0.1

"""The smooth path's tangents on a rounded-rectangle tube against the closed form (geometry.sections.polar_arcs).

A straight tube of any section unrolls flat, so a geodesic is a straight line in (arc length around the
section, station): its tangent at arc length sigma is unit(T(sigma) + cot(alpha) e_z), T the section's
unit tangent, the same angle alpha everywhere (a line on a flat face, a helix on a corner). The points
here are placed by that closed form, their planned directions come from winder.winding.passes.directions
and the pieces between them from SmoothPaths; both are checked against the closed form where a flat
meets a corner inside an interval (parts/boom_rect.yaml's section and spacing, where a spline in theta
was 0.11 deg off at a point and 0.21 deg between two: an eye 170 mm out, 0.6 mm off the fiber).
"""

from __future__ import annotations

import numpy as np

from conftest import surface_of
from plans import make_pass
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.config.sections import RoundedRectangleSection
from winder.machine.smooth import SmoothPaths
from winder.winding.passes import directions
from winder.winding.results import PassKind

HALF_W, HALF_H, CORNER = 60.0, 40.0, 15.0  # boom_rect's 120 x 80 section, 15 mm corners
STEP = 3.1614  # mm of arc (and of station, at 45 deg) between points: boom_rect's spacing
NODE_TOL_DEG = 0.01  # planned directions: a spline in theta was 0.11 deg off next to a joint
PIECE_TOL_DEG = 0.01  # between the points: 0.21 deg with theta's pieces


def _section_point(sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(point (m, 2), unit tangent (m, 2)) at arc length sigma (m,) counterclockwise from the middle of
    the right face: the right face's upper half, the corner, the top face (sigma below ~140 mm)."""
    quarter = 0.5 * np.pi * CORNER
    flat = HALF_H - CORNER
    ang = np.clip((sigma - flat) / CORNER, 0.0, 0.5 * np.pi)
    on_right, on_top = sigma <= flat, sigma >= flat + quarter
    x = np.where(on_right, HALF_W, np.where(on_top, HALF_W - CORNER - (sigma - flat - quarter),
                                            HALF_W - CORNER + CORNER * np.cos(ang)))
    y = np.where(on_right, sigma, np.where(on_top, HALF_H, flat + CORNER * np.sin(ang)))
    tx = np.where(on_right, 0.0, np.where(on_top, -1.0, -np.sin(ang)))
    ty = np.where(on_right, 1.0, np.where(on_top, 0.0, np.cos(ang)))
    return np.column_stack([x, y]), np.column_stack([tx, ty])


def _angle_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", a, b), -1.0, 1.0)))


def _truth(sigma: np.ndarray) -> np.ndarray:
    _, tangent = _section_point(sigma)
    v = np.column_stack([tangent, np.ones(sigma.size)])  # 45 deg: as much along the axis as around
    return v / np.linalg.norm(v, axis=1)[:, None]


def test_tangents_across_a_flat_meeting_a_corner_follow_the_unrolled_line():
    surface = surface_of(LineAxis(400.0), ConstantProfile(1.0), RoundedRectangleSection(2 * HALF_W, 2 * HALF_H, CORNER))
    sigma = 1.0 + STEP * np.arange(40)  # the joints at 25 and 48.6 mm fall inside intervals
    xy, _ = _section_point(sigma)
    theta = np.unwrap(np.arctan2(xy[:, 1], xy[:, 0]))
    s = surface.s_of_t(100.0 + sigma)
    assert np.allclose(surface.points(s, theta)[:, :2], xy, atol=1e-9)  # theta is the polar angle
    d = directions(surface, s, theta)
    assert np.max(_angle_deg(d, _truth(sigma))) < NODE_TOL_DEG
    paths = SmoothPaths(surface, [make_pass(surface, s, theta, d, layer=1, circuit=1, number=1,
                                            kind=PassKind.FORWARD)])
    u = np.arange(0.0, sigma.size - 1.0, 1.0 / 16.0)[16:-16]  # past the ends' own spline error
    _, _, p, got = paths.point(u)
    # The closed form at the piece's own point: its arc length read from its polar angle (a fine table).
    fine = np.linspace(0.0, 140.0, 1_400_001)
    xy_fine, _ = _section_point(fine)
    at = np.interp(np.arctan2(p[:, 1], p[:, 0]), np.arctan2(xy_fine[:, 1], xy_fine[:, 0]), fine)
    assert np.allclose(surface.t_of_s(paths.point(u)[0]) - 100.0, at, atol=0.01)  # on the unrolled line
    assert np.max(_angle_deg(got, _truth(at))) < PIECE_TOL_DEG

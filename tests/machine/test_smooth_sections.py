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
# A wide section's small corner (a reviewer's 200 x 100 boom, corners 10, fiber at 30 deg): its eyes
# stand 440 mm out along the free fiber, so 1e-4 deg is 0.0008 mm there. The arc map's linear tables
# put the directions 0.025 deg off at a point 0.003 mm past the corner's joint with the long top face
# and 0.028 deg between two (eyes 0.19 and 0.21 mm off the fiber); now 1e-14 and 1e-6 deg.
WIDE = (100.0, 50.0, 10.0)
WIDE_STEP = 1.0  # mm of arc between points: that boom's spacing at 30 deg (1.73 mm of station)
WIDE_TOL_DEG = 1e-4
WIDE_LINE_MM = 1e-6  # the pieces off the unrolled line: 8e-5 mm with the linear tables, now 5e-9


def _section_point(sigma: np.ndarray, dims: tuple[float, float, float] = (HALF_W, HALF_H, CORNER)
                   ) -> tuple[np.ndarray, np.ndarray]:
    """(point (m, 2), unit tangent (m, 2)) at arc length sigma (m,) counterclockwise from the middle of
    the right face: the right face's upper half, the corner, the top face (sigma below ~140 mm);
    dims: half width, half height, corner radius."""
    half_w, half_h, corner = dims
    quarter = 0.5 * np.pi * corner
    flat = half_h - corner
    ang = np.clip((sigma - flat) / corner, 0.0, 0.5 * np.pi)
    on_right, on_top = sigma <= flat, sigma >= flat + quarter
    x = np.where(on_right, half_w, np.where(on_top, half_w - corner - (sigma - flat - quarter),
                                            half_w - corner + corner * np.cos(ang)))
    y = np.where(on_right, sigma, np.where(on_top, half_h, flat + corner * np.sin(ang)))
    tx = np.where(on_right, 0.0, np.where(on_top, -1.0, -np.sin(ang)))
    ty = np.where(on_right, 1.0, np.where(on_top, 0.0, np.cos(ang)))
    return np.column_stack([x, y]), np.column_stack([tx, ty])


def _angle_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", a, b), -1.0, 1.0)))


def _truth(sigma: np.ndarray, dims: tuple[float, float, float] = (HALF_W, HALF_H, CORNER),
           cot_alpha: float = 1.0) -> np.ndarray:
    """The unrolled line's unit tangent at sigma: cot(alpha) along the axis a mm around (45 deg: 1)."""
    _, tangent = _section_point(sigma, dims)
    v = np.column_stack([tangent, np.full(sigma.size, cot_alpha)])
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


def test_a_small_corner_on_a_wide_section_keeps_the_unrolled_line():
    """Across the joints of a 10 mm corner between a 100 mm face and a 200 mm one, at 30 deg: the
    planned directions and the pieces within WIDE_TOL_DEG of the closed form (geometry.sections.ArcMap:
    its rate from the section, its fraction a cubic with the joints among its nodes)."""
    half_w, half_h, corner = WIDE
    surface = surface_of(LineAxis(400.0), ConstantProfile(1.0), RoundedRectangleSection(2 * half_w, 2 * half_h, corner))
    cot = 1.0 / np.tan(np.radians(30.0))
    # The joints at 40 and 55.708 mm inside intervals, a point 0.003 mm past the second (as on that boom).
    sigma = 30.705 + WIDE_STEP * np.arange(40)
    xy, _ = _section_point(sigma, WIDE)
    theta = np.unwrap(np.arctan2(xy[:, 1], xy[:, 0]))
    s = surface.s_of_t(100.0 + cot * sigma)
    d = directions(surface, s, theta)
    assert np.max(_angle_deg(d, _truth(sigma, WIDE, cot))) < WIDE_TOL_DEG
    paths = SmoothPaths(surface, [make_pass(surface, s, theta, d, layer=1, circuit=1, number=1,
                                            kind=PassKind.FORWARD)])
    u = np.arange(0.0, sigma.size - 1.0, 1.0 / 64.0)[128:-128]  # past the ends' own spline error
    _, _, p, got = paths.point(u)
    fine = np.linspace(0.0, 140.0, 1_400_001)
    xy_fine, _ = _section_point(fine, WIDE)
    at = np.interp(np.arctan2(p[:, 1], p[:, 0]), np.arctan2(xy_fine[:, 1], xy_fine[:, 0]), fine)
    assert np.allclose((surface.t_of_s(paths.point(u)[0]) - 100.0) / cot, at, atol=WIDE_LINE_MM)  # on the line
    assert np.max(_angle_deg(got, _truth(at, WIDE, cot))) < WIDE_TOL_DEG

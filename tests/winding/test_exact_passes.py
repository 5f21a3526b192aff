"""Geodesic passes known before any iteration (issue 41 item 4): on a straight tube of any section the
unrolled line, on an open surface of revolution Clairaut's quadrature. Parts across the range shops wind
plan without a solve that could fail; truths independent of the planner: the section's arc length summed
from its own outline (a fine polyline), and the cone's closed form theta(r) = sqrt(1 + k^2) / k
(acos(c / r) - acos(c / r0)) (the cone unrolls to a plane; Clairaut r sin(alpha) = c)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.winding.results import PassKind

OUTLINE_SAMPLES = 200_001  # polyline vertices of a section's outline (arc length to ~1e-9 of it)
LINE_TOL = 1e-6  # of the perimeter: a pass's arc-length position off the straight line
ANGLE_TOL_DEG = 1e-5  # a pass's laid angle off the unrolled line's (the arc table sums the perimeter to ~4e-8)
CONE_THETA_TOL = 1e-8  # rad: a pass's angle against the cone's closed form
CLAIRAUT_REL = 1e-9  # r sin(alpha) along a pass, relative
TURN_CLEAR = 1e-6  # of c: points closer to their turnaround than this are held to TURN_THETA_TOL
TURN_THETA_TOL = 1e-5  # rad: sqrt(2 eps) times the cone's sqrt(1 + k^2) / k of 60, with a margin


def _job(mandrel: dict, winding: dict):
    return parse_config({"name": "part", "mandrel": mandrel, "winding": winding}, "part.yaml")


def _plan(job):
    from winder.winding.plan import plan  # noqa: PLC0415

    return plan(job)


def _wound(layer):
    return [p for p in layer.passes if p.kind in (PassKind.FORWARD, PassKind.RETURN)]


def _outline_arc(section, theta: np.ndarray) -> tuple[np.ndarray, float]:
    """Arc length from theta = 0 to each theta (in [0, 2 pi)) and the perimeter, from a fine polyline
    of the section's points rho(theta) (cos, sin)."""
    grid = np.linspace(0.0, 2.0 * np.pi, OUTLINE_SAMPLES)
    rho = section.polar(grid)[0]
    xy = np.column_stack([rho * np.cos(grid), rho * np.sin(grid)])
    cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))])
    return np.interp(np.mod(theta, 2.0 * np.pi), grid, cum), float(cum[-1])


SECTIONS = [
    {"type": "rounded_rectangle", "width": 200, "height": 100, "corner_radius": 20},   # issue 41's tube
    {"type": "rounded_rectangle", "width": 160, "height": 40, "corner_radius": 2},     # aspect 4, 5 % corners
    {"type": "rounded_rectangle", "width": 60, "height": 60, "corner_radius": 9},
    {"type": "ellipse", "a": 120, "b": 30},
    {"type": "superellipse", "a": 50, "b": 35, "exponent": 4},
]


@pytest.mark.parametrize("section", SECTIONS, ids=lambda s: s["type"] + str(s.get("width", s.get("a"))))
@pytest.mark.parametrize("length,angle", [(3000, 45), (400, 15), (800, 80)])
def test_straight_tubes_wind_on_the_unrolled_line(section, length, angle):
    job = _job({"axis": {"type": "line", "length": length}, "section": section},
               {"band_width": 12, "region": {"start": 20, "end": length - 20},
                "layers": [{"type": "helical", "angle": angle}]})
    layer = _plan(job).layers[0]
    from winder.geometry.build import build_surface  # noqa: PLC0415

    surface = build_surface(job.mandrel, job.source, job.name)
    for p in _wound(layer)[:6]:
        along, per = _outline_arc(surface.section, p.theta)
        # unwrapped arc-length position against the station: a straight line
        turns = np.floor(p.theta / (2.0 * np.pi))
        run = along + turns * per
        line = np.polyfit(p.t, run, 1)
        assert np.max(np.abs(np.polyval(line, p.t) - run)) < LINE_TOL * per
        lean = math.degrees(math.atan(abs(line[0])))
        assert np.max(np.abs(np.abs(p.alpha_deg) - lean)) < ANGLE_TOL_DEG
    assert layer.coverage.covered_fraction >= 0.999
    assert layer.max_slip <= job.winding.friction


@pytest.mark.parametrize("r0,r1,length,angle", [(150, 60, 10_000, 20), (100, 50, 3000, 30), (90, 45, 3000, 28),
                                                 (400, 300, 12_000, 45)])
def test_cones_wind_on_the_closed_form_geodesic(r0, r1, length, angle):
    """Up to a turnaround on or just past the narrow end (100 -> 50 at 30 deg: r sin(alpha) = 50 there)."""
    job = _job({"axis": {"type": "line", "length": length},
                "profile": {"type": "cone", "start_radius": r0, "end_radius": r1}},
               {"band_width": 16, "layers": [{"type": "helical", "angle": angle}]})
    layer = _plan(job).layers[0]
    k = (r1 - r0) / length
    c = r0 * math.sin(math.radians(angle))
    for p in _wound(layer)[:2]:
        r = r0 + k * p.t
        wide = int(np.argmin(p.t))
        exact = math.sqrt(1.0 + k * k) / k * (np.arccos(np.minimum(c / r, 1.0)) - math.acos(min(c / r[wide], 1.0)))
        # acos(c / r) near r = c turns the radius's last bits into sqrt(2 eps) of an angle: compared from
        # the wide end, away from a turnaround, and at it within what that allows
        off = np.abs(np.abs(p.theta - p.theta[wide]) - np.abs(exact))
        clear = r - c > TURN_CLEAR * c
        assert np.max(off[clear]) < CONE_THETA_TOL
        assert np.max(off) < TURN_THETA_TOL
        clairaut = r * np.sin(np.radians(np.abs(p.alpha_deg)))
        assert np.max(np.abs(clairaut / c - 1.0)) < CLAIRAUT_REL
    assert layer.coverage.covered_fraction >= 0.999


def test_a_long_thin_pipe_gets_the_points_its_rounds_need():
    """3 m of a 10 mm tube at 55 deg is 68 rounds: the default 200 points were refused as too few."""
    job = _job({"axis": {"type": "line", "length": 3000}, "profile": {"type": "constant", "radius": 10}},
               {"band_width": 3, "layers": [{"type": "helical", "angle": 55}]})
    layer = _plan(job).layers[0]
    assert min(p.s.size for p in _wound(layer)) >= 24 * 68
    assert layer.coverage.covered_fraction >= 0.999


def test_a_pass_on_one_flat_face_does_not_slip():
    """At 15 deg over 500 mm a pass runs 134 mm round a 200 x 100 box: some lie on one flat face, where
    k_n is round-off; their round-off k_g read as a slip of 1.8e3."""
    job = _job({"axis": {"type": "line", "length": 600},
                "section": {"type": "rounded_rectangle", "width": 200, "height": 100, "corner_radius": 20}},
               {"band_width": 6, "region": {"start": 50, "end": 550}, "layers": [{"type": "helical", "angle": 15}]})
    assert _plan(job).layers[0].max_slip <= job.winding.friction


def test_a_hoop_on_a_flattish_section_is_measured_on_its_own_curve():
    """A hoop is the unrolled line too: its slip read from theta interpolated linearly between its
    points bent at every corner of a superellipse of exponent 4.5 (1.32 on a geodesic: refused)."""
    job = _job({"axis": {"type": "line", "length": 380},
                "section": {"type": "superellipse", "a": 34.5, "b": 13.5, "exponent": 4.5}},
               {"band_width": 11.5, "friction": 0.21, "region": {"start": 8, "end": 372},
                "layers": [{"type": "helical", "angle": 29.5}, {"type": "hoop"}]})
    plan = _plan(job)
    assert all(layer.max_slip <= job.winding.friction for layer in plan.layers)

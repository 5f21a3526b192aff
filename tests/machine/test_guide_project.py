"""The robot mode's closest guide point (kinematics.Guide.project) against the circle's closed form.

A point outside the bend circle, within the arc's sector, has its closest guide point on the arc at
its own polar angle about the bend's centre: station L1 + R phi, distance sqrt((rho - R)^2 + h^2)
(rho its distance from the centre in the bend's plane, h its height off the plane).
"""

from __future__ import annotations

import types

import numpy as np

from winder.geometry.arcs import ArcSpec, chain
from winder.machine.kinematics import Guide

STATION_TOL = 1e-6  # mm
DIST_TOL = 1e-8  # mm
LEG, BEND, ANGLE = 300.0, 450.0, 90.0  # mm, mm, deg: an elbow's guide, DN300-like


def _guide() -> Guide:
    curve = chain((LEG, ArcSpec(BEND, ANGLE), LEG))
    return Guide(types.SimpleNamespace(curve=curve, axial_length=curve.length), 2500.0)


def _points(n: int, far: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """n points in the arc's sector, 5 to `far` mm outside the circle, up to 100 mm off its plane; with
    their closed-form stations and distances. The chain bends from +z toward +x: centre (R, 0, L1)."""
    rng = np.random.default_rng(7)
    phi = rng.uniform(0.02, np.radians(ANGLE) - 0.02, n)
    rho = BEND + rng.uniform(5.0, far, n)
    h = rng.uniform(-100.0, 100.0, n)
    centre = np.array([BEND, 0.0, LEG])
    radial = np.column_stack([-np.cos(phi), np.zeros(n), np.sin(phi)])  # from the centre to the arc
    e = centre + rho[:, None] * radial + h[:, None] * np.array([0.0, 1.0, 0.0])
    return e, LEG + BEND * phi, np.hypot(rho - BEND, h)


def test_closest_point_on_the_arc_near_and_far():
    guide = _guide()
    for far in (300.0, 2500.0):  # an eye's usual lead, and the longest one
        e, station, dist = _points(2000, far)
        z, d = guide.project(e)
        assert np.max(np.abs(z - station)) < STATION_TOL
        assert np.max(np.abs(d - dist)) < DIST_TOL


def test_warm_start_from_a_neighbouring_station():
    guide = _guide()
    e, station, dist = _points(500, 300.0)
    z, d, rel, tan, _ = guide.project(e, full=True, start=station + 0.8)
    assert np.max(np.abs(z - station)) < STATION_TOL
    assert np.max(np.abs(d - dist)) < DIST_TOL
    assert np.max(np.abs(np.einsum("ij,ij->i", rel, tan))) < DIST_TOL  # e - x(t*) is normal to the guide

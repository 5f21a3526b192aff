"""The grown mandrel against exact offsets: cylinder R -> R + h, cone, sphere -> sphere, a varying
offset on an ellipsoid at distance h along the normal, a fold refused."""

import math

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from winder.config.job import parse_config
from winder.geometry.build import build_surface
from winder.geometry.domes import Ellipsoid, Hemisphere
from winder.geometry.isotensoid import Isotensoid
from winder.geometry.offset import OffsetDome, OffsetError, grow_surface

EXACT = 1e-10  # mm: offsets whose result is a closed form
UNIT_SPEED = 1e-7  # |h1^2 + r1^2 - 1| of the re-parametrized offset (quintic Hermite between knots)
DISTANCE = 1e-6  # mm: a varying offset's distance from the base along the normal


def _const(h):
    return lambda x: (np.full_like(x, h), np.zeros_like(x), np.zeros_like(x))


def _surface(mandrel):
    return build_surface(parse_config({"name": "x", "mandrel": mandrel}, "x.yaml").mandrel)


def test_hemisphere_grows_to_a_sphere():
    base = Hemisphere(100.0, 30.0)
    dome = OffsetDome(base, _const(2.5))
    sig = np.linspace(0.0, dome.length, 2001)
    e = dome.evaluate(sig)
    np.testing.assert_allclose(np.hypot(e.h, e.r), 102.5, atol=EXACT)
    assert np.max(np.abs(e.h1**2 + e.r1**2 - 1.0)) < UNIT_SPEED
    np.testing.assert_allclose(e.h1 * e.r2 - e.r1 * e.h2, -1.0 / 102.5, atol=1e-8)
    # the laminate stands past the opening's plane: it ends on the big sphere's ray through the opening
    assert dome.depth == pytest.approx(base.depth * 1.025, abs=EXACT)
    assert dome.end_radius == pytest.approx(30.0 * 1.025, abs=EXACT)
    assert dome.length == pytest.approx(base.length * 1.025, abs=1e-9)


def test_grown_vessel_keeps_the_axial_frame():
    surf = _surface({"profile": {"type": "vessel", "radius": 100, "cylinder_length": 200,
                                 "dome": {"type": "hemisphere", "polar_opening": 30}}})
    s = np.linspace(0.0, surf.length, 400)
    g = grow_surface(surf, s, np.full_like(s, 1.5))
    rise = 0.015 * surf.profile.dome.depth  # each dome's laminate past its opening's plane
    assert g.profile.radius == 101.5 and g.axial_length == pytest.approx(surf.axial_length + rise, abs=EXACT)
    assert g.profile.equator_t == pytest.approx(surf.profile.equator_t, abs=EXACT)
    assert g.t_start == pytest.approx(-rise, abs=EXACT)
    ss = np.linspace(0.0, g.length, 3001)
    th = np.linspace(0.0, 6.0, ss.size)
    p = g.points(ss, th)
    t1, t2 = surf.profile.equator_t
    centre = np.where(p[:, 2] < t1, t1, np.where(p[:, 2] > t2, t2, p[:, 2]))
    dist = np.hypot(np.hypot(p[:, 0], p[:, 1]), p[:, 2] - centre)
    np.testing.assert_allclose(dist, 101.5, atol=EXACT)
    assert np.isclose(g.t_of_s(np.array([0.0]))[0], -rise, atol=EXACT)
    assert g.s_of_t(np.array([-rise, 0.0]))[0] == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("profile", [{"type": "constant", "radius": 50},
                                     {"type": "cone", "start_radius": 60, "end_radius": 40}])
def test_cylinder_and_cone_grow_along_the_normal(profile):
    surf = _surface({"axis": {"type": "line", "length": 300}, "profile": profile})
    s = np.linspace(0.0, 300.0, 61)
    g = grow_surface(surf, s, np.full_like(s, 2.0))
    assert g.profile.spline.c.shape[1] == 1  # still one piece
    z = np.linspace(0.0, 300.0, 7)
    r0, r1 = profile.get("start_radius", profile.get("radius")), profile.get("end_radius", profile.get("radius"))
    slope = (r1 - r0) / 300.0
    expect = r0 + slope * z + 2.0 * math.sqrt(1 + slope**2)
    np.testing.assert_allclose(g.radius(z, np.zeros_like(z)), expect, atol=EXACT)
    # the normal distance between the two lines (z, r) is 2
    dist = (g.radius(z, 0 * z) - (r0 + slope * z)) / math.sqrt(1 + slope**2)
    np.testing.assert_allclose(dist, 2.0, atol=EXACT)


def test_varying_offset_on_an_ellipsoid_is_normal_distance():
    base = Ellipsoid(100.0, 30.0, 60.0)
    x = np.linspace(0.0, base.length, 40)
    spline = CubicSpline(x, 1.0 + 0.8 * np.sin(x / 25.0), bc_type=((1, 0.032), "not-a-knot"))
    dome = OffsetDome(base, lambda q: (spline(q), spline(q, 1), spline(q, 2)))
    e = dome.evaluate(np.linspace(0.0, dome.length, 1501))
    assert np.max(np.abs(e.h1**2 + e.r1**2 - 1.0)) < UNIT_SPEED
    # each base point sits at distance g(sigma) below the offset, along its normal
    sig = np.linspace(0.0, base.length * 0.9, 50)
    b = base.evaluate(sig)
    g = spline(sig)
    ph, pr = b.h - g * b.r1, b.r + g * b.h1
    k = dome._invert(ph, from_opening=False)
    got = dome.evaluate(k)
    np.testing.assert_allclose(got.r, pr, atol=DISTANCE)


def test_a_laminate_thicker_than_a_concave_radius_is_refused():
    base = Isotensoid(100.0, 20.0)
    sig = np.linspace(0.0, base.length, 4001)
    e = base.evaluate(sig)
    k = e.h1 * e.r2 - e.r1 * e.h2
    mid = int(np.argmax(np.where(sig < 0.8 * base.length, k, -np.inf)))  # concave, off the end hook
    s0, w, big = sig[mid], 5.0, 1.5 / k[mid]

    def bump(x):
        u = (x - s0) / w
        g = big * np.exp(-u * u)
        return g, -2.0 * u / w * g, (4.0 * u * u - 2.0) / (w * w) * g

    with pytest.raises(OffsetError, match="folds"):
        OffsetDome(base, bump)
    # a laminate over the end hook ends where its surface would fold next to the opening: no fold
    dome = OffsetDome(base, _const(5.0))
    assert dome.depth > base.depth and dome.end_radius > base.end_radius
    e = dome.evaluate(np.linspace(0.0, dome.length, 4001))
    assert np.all(e.h1 > 0.0) and np.all(np.diff(e.r) < 0.0)

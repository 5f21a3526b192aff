"""Geodesic shooting (winder.paths.shooting) against closed forms, Clairaut, and the variational solver.

Every truth here is independent of winder: helices on a cylinder, the unrolled cone sector, the
unrolled (developable) elliptic tube with the section's arc length by quadrature, great circles on a
hemisphere, and Clairaut's relation. On the bent tube, which has no closed form, the shot length is
compared with the variational solver's super-convergent length (docs/math/02-energy.md), a different method.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import ellipe, ellipeinc

from winder.config.axes import ArcAxis
from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.config.profiles import ConeProfile
from winder.config.sections import EllipseSection
from winder.config.vessel import Dome, DomeType, VesselProfile
from winder.errors import ConfigError, SolverError
from winder.paths.geodesic import geodesic
from winder.paths.headings import clairaut_constant
from winder.paths.ode import trace, trace_fan
from winder.paths.shooting import shoot
from winder.geometry.build import build_surface

HELIX_TOL = 1e-9  # mm: traced helix vs closed form (s, and R * theta)
SPEED_TOL = 1e-10  # | |J u'| - 1 |: the arc-length parametrization holds along a trace
CLAIRAUT_TOL = 1e-9  # relative drift of r sin(alpha) along a trace
LENGTH_TOL = 1e-9  # relative: shot length vs a closed form or the variational smooth length
# How far a converged shot misses its end point, relative to its length: the integrator's own global
# error at rtol = atol = 1e-12 is ~3e-12 of the length on the bent tube with one round (the end of
# the nominal ray moves by that much when its fan neighbours change the step sequence).
RESIDUAL_TOL = 1e-10
GREAT_CIRCLE_TOL = 1e-9  # relative to R: dome points off the great circle's plane
# Vertices of the variational polyline lie O(h^2) off the geodesic (docs/math/02-energy.md); measured on the bent
# tube: 5.7e-4 mm (no round) and 1.5e-3 mm (one round) at n = 200, i.e. about 6e-4 h^2 and 4e-4 h^2.
VERTEX_H2_COEF = 1e-3  # 1/mm: vertex distance <= this * h^2 (h the segment length)
VERTEX_ORDER = (3.5, 4.5)  # the distance ratio from n to 2n + 1 points (4 for second order)


# -- mandrels (helpers, not shared fixtures) ------------------------------------------------------
R_TUBE = 40.0


def tube():
    return build_surface(MandrelConfig(LineAxis(300.0), ConstantProfile(R_TUBE), CircleSection()))


def cone():
    return build_surface(MandrelConfig(LineAxis(300.0), ConeProfile(60.0, 30.0), CircleSection()))


def bent_tube():
    return build_surface(MandrelConfig(ArcAxis(radius=150.0, angle_deg=90.0), ConstantProfile(40.0),
                                       CircleSection()))


def ellipse_tube():
    return build_surface(MandrelConfig(LineAxis(400.0), None, EllipseSection(60.0, 35.0)))


def vessel(radius=100.0, cylinder=200.0, opening=30.0):
    dome = Dome(DomeType.HEMISPHERE, opening)
    return build_surface(MandrelConfig(None, VesselProfile(radius, cylinder, dome, dome), CircleSection()))


def param_velocity(result, arc):
    """(s, theta, s', theta') of a trace or shot at arc lengths: (4, m)."""
    return result.state(np.asarray(arc, dtype=float))


# -- straight circular tube: helices --------------------------------------------------------------
@pytest.mark.parametrize("heading", [35.0, -60.0, 80.0, 0.0])
def test_trace_on_a_cylinder_is_the_helix(heading):
    surf = tube()
    s0, th0, length = 20.0, 0.4, 250.0
    tr = trace(surf, (s0, th0), heading, length)
    a = np.radians(heading)
    arc = np.linspace(0.0, min(length, (surf.length - s0) / max(np.cos(a), 1e-300)), 301)
    s, th = tr.sol(arc)
    assert not tr.left_mandrel, tr.status
    assert tr.length == pytest.approx(length, abs=1e-12)
    assert np.max(np.abs(s - (s0 + arc * np.cos(a)))) < HELIX_TOL
    assert np.max(np.abs(R_TUBE * (th - th0) - arc * np.sin(a))) < HELIX_TOL
    assert tr.speed_error < SPEED_TOL


def test_trace_stops_where_the_path_leaves_the_mandrel():
    surf = tube()
    up = trace(surf, (250.0, 0.0), 60.0, 500.0)  # reaches s = 300 after 50 / cos(60) = 100 mm
    assert up.left_mandrel and up.length == pytest.approx(100.0, abs=1e-9)
    assert up.s[-1] == pytest.approx(surf.length, abs=1e-9)
    down = trace(surf, (30.0, 1.0), 180.0, 100.0)
    assert down.left_mandrel and down.length == pytest.approx(30.0, abs=1e-9)
    with pytest.raises(ConfigError):
        trace(surf, (301.0, 0.0), 10.0, 10.0)


def test_fan_traces_many_helices_at_once():
    surf = tube()
    heads = np.array([-70.0, -20.0, 0.0, 45.0, 85.0])
    s0, th0, length = 100.0, -0.5, 240.0
    fan = trace_fan(surf, (s0, th0), heads, length, samples=101)
    a = np.radians(heads)[:, None]
    assert np.max(np.abs(fan.theta - th0 - fan.arc * np.sin(a) / R_TUBE)) * R_TUBE < 10 * HELIX_TOL
    inside = np.isnan(fan.left_at)
    # s = 100 + l cos(a) reaches 300 at l = 200 / cos(a) < 240 for |a| < 33.6 deg.
    expected_left = np.abs(heads) < np.degrees(np.arccos(200.0 / 240.0))
    assert np.array_equal(~inside, expected_left)
    np.testing.assert_allclose(fan.left_at[~inside], 200.0 / np.cos(np.radians(heads[~inside])), atol=1e-8)
    on = fan.arc[None, :] < np.where(inside, np.inf, fan.left_at)[:, None]
    err = np.abs(fan.s - s0 - fan.arc * np.cos(a))
    assert np.max(err[on]) < 10 * HELIX_TOL


# -- cone: Clairaut and the unrolled sector ---------------------------------------------------------
def test_clairaut_on_a_cone_through_a_turnaround():
    surf = cone()
    # c = r sin(alpha) = 58 sin(40 deg) = 37.3 > 30: the path turns around where r = c (t = 227,
    # after ~447 mm) and comes back toward the large end (which it would reach after ~919 mm).
    tr = trace(surf, (20.0, 0.5), 40.0, 800.0)
    assert not tr.left_mandrel, tr.status
    st = tr.state(np.linspace(0.0, tr.length, 1001))
    c = clairaut_constant(surf, st[0], st[1], st[2], st[3])
    c0 = 58.0 * np.sin(np.radians(40.0))
    assert np.max(np.abs(c / c0 - 1.0)) < CLAIRAUT_TOL
    # It turned around (s' = 0) where alpha = 90 deg, i.e. on the parallel r = c.
    arc = np.linspace(0.0, tr.length, 1001)
    k = int(np.argmax(st[2] < 0.0))
    assert k > 0 and np.all(st[2, k:] < 0.0)
    turn = brentq(lambda l: tr.state(l)[2], arc[k - 1], arc[k], xtol=1e-13)
    assert 60.0 - 0.1 * tr.state(turn)[0] == pytest.approx(c0, rel=CLAIRAUT_TOL)
    assert tr.speed_error < SPEED_TOL


def cone_sector_length(r0, r1, dtheta, tan_b):
    """Geodesic length on a cone by unrolling it: L^2 = rho0^2 + rho1^2 - 2 rho0 rho1 cos(dtheta sin b)."""
    sin_b = tan_b / np.hypot(1.0, tan_b)
    rho0, rho1 = r0 / sin_b, r1 / sin_b
    return np.sqrt(rho0**2 + rho1**2 - 2.0 * rho0 * rho1 * np.cos(dtheta * sin_b))


@pytest.mark.parametrize("rounds", [0, 1])
def test_shoot_on_a_cone_matches_the_unrolled_sector(rounds):
    surf = cone()
    t0, th0, t1, th1 = 20.0, 0.2, 280.0, 2.7
    r = shoot(surf, (t0, th0), (t1, th1), rounds=rounds)
    assert r.converged and r.residual < RESIDUAL_TOL * r.length, r.status
    exact = cone_sector_length(60.0 - 0.1 * t0, 60.0 - 0.1 * t1, th1 - th0 + 2.0 * np.pi * rounds, 0.1)
    assert abs(r.length / exact - 1.0) < LENGTH_TOL
    st = param_velocity(r, r.arc)
    c = clairaut_constant(surf, *st)
    assert np.max(np.abs(c / c[0] - 1.0)) < CLAIRAUT_TOL


# -- straight elliptic tube: developable --------------------------------------------------------------
A_ELL, B_ELL = 60.0, 35.0


def ellipse_arc(theta0, theta1):
    """Arc length of the section from polar angle theta0 to theta1: quadrature of |d/dtheta rho (cos, sin)|.

    rho = a b q^-1/2 with q = (b cos)^2 + (a sin)^2, rho' = -a b q' / (2 q^3/2), |.| = sqrt(rho^2 + rho'^2).
    """

    def speed(th):
        c, s = np.cos(th), np.sin(th)
        q = (B_ELL * c) ** 2 + (A_ELL * s) ** 2
        dq = 2.0 * (A_ELL**2 - B_ELL**2) * s * c
        rho = A_ELL * B_ELL / np.sqrt(q)
        drho = -0.5 * A_ELL * B_ELL * dq / q**1.5
        return np.hypot(rho, drho)

    edges = np.linspace(theta0, theta1, 2 + int(abs(theta1 - theta0) / 0.5))
    return sum(quad(speed, a, b, epsabs=0.0, epsrel=1e-13, limit=200)[0]
               for a, b in zip(edges[:-1], edges[1:]))


def test_ellipse_arc_quadrature_against_elliptic_integrals():
    # The same arc by Legendre's incomplete integral of the second kind, in the eccentric angle E.
    m = 1.0 - (B_ELL / A_ELL) ** 2

    def from_zero(theta):  # arc from E = 0 to E(theta), 0 <= theta < pi / 2
        e = np.arctan2(A_ELL * np.sin(theta), B_ELL * np.cos(theta))
        return A_ELL * (ellipe(m) - ellipeinc(np.pi / 2 - e, m))

    assert ellipse_arc(0.3, 1.2) == pytest.approx(from_zero(1.2) - from_zero(0.3), rel=1e-13)
    assert ellipse_arc(0.0, 2.0 * np.pi) == pytest.approx(4.0 * A_ELL * ellipe(m), rel=1e-13)


@pytest.mark.parametrize("rounds", [0, 2])
def test_shoot_on_an_elliptic_tube_matches_the_developed_length(rounds):
    surf = ellipse_tube()
    t0, th0, t1, th1 = 30.0, 0.3, 370.0, 2.0
    r = shoot(surf, (t0, th0), (t1, th1), rounds=rounds)
    assert r.converged and r.residual < RESIDUAL_TOL * r.length, r.status
    arc = ellipse_arc(th0, th1) + rounds * ellipse_arc(0.0, 2.0 * np.pi)
    exact = np.hypot(t1 - t0, arc)
    assert abs(r.length / exact - 1.0) < LENGTH_TOL
    assert r.speed_error < SPEED_TOL


def test_clairaut_needs_a_surface_of_revolution():
    with pytest.raises(SolverError):
        clairaut_constant(ellipse_tube(), np.array([10.0]), np.array([0.0]), np.array([1.0]), np.array([0.0]))


# -- bent tube: against the variational solver ---------------------------------------------------------
def closest_distance(surf, shot, points, arc0):
    """Distance of each point (m, 3) from the shot curve: Newton on the arc length from arc0 (m,)."""
    arc = np.array(arc0, dtype=float)
    for _ in range(10):
        st = shot.state(arc)
        ev = surf.evaluate(st[0], st[1], order=1)
        vel = ev.ps * st[2][:, None] + ev.pt * st[3][:, None]  # unit tangent
        arc = np.clip(arc + np.einsum("ij,ij->i", points - ev.p, vel), 0.0, shot.length)
    return np.linalg.norm(surf.points(*shot.sol(arc)) - points, axis=1)


@pytest.mark.parametrize("rounds", [0, 1])
def test_shoot_on_a_bent_tube_agrees_with_the_variational_solver(rounds):
    surf = bent_tube()
    big_t = surf.axial_length
    shot = shoot(surf, (0.0, 0.0), (big_t, np.pi / 2), rounds=rounds)
    assert shot.converged and shot.residual < RESIDUAL_TOL * shot.length, shot.message
    assert shot.speed_error < SPEED_TOL
    dist = []
    for n in (200, 401):
        var = geodesic(surf, (0.0, 0.0), (big_t, np.pi / 2), rounds=rounds, n=n, estimate=False)
        if n == 200:
            assert abs(shot.length / var.length - 1.0) < LENGTH_TOL
        frac = np.linspace(0.0, 1.0, var.s.size)
        d = closest_distance(surf, shot, var.points, frac * shot.length)
        h = shot.length / (n + 1)
        assert d.max() < VERTEX_H2_COEF * h**2
        dist.append(d.max())
    assert VERTEX_ORDER[0] < dist[0] / dist[1] < VERTEX_ORDER[1]


# -- vessel: hemispherical dome -------------------------------------------------------------------------
def test_clairaut_and_great_circles_over_a_hemispherical_dome():
    radius = 100.0
    surf = vessel(radius=radius)
    mer = surf.profile
    s_start = 0.5 * (mer.equator_s[0] + mer.equator_s[1])  # middle of the cylinder
    alpha = 25.0  # c = R sin(alpha) = 42.3 > the opening 30: the path turns around on the end dome
    # 100 / cos(alpha) on the cylinder, a half great circle (pi R) over the dome, some cylinder back.
    tr = trace(surf, (s_start, 0.0), alpha, 500.0)
    assert not tr.left_mandrel, tr.status
    st = tr.state(np.linspace(0.0, tr.length, 2001))
    c = clairaut_constant(surf, *st)
    assert np.max(np.abs(c / (radius * np.sin(np.radians(alpha))) - 1.0)) < CLAIRAUT_TOL
    assert tr.speed_error < SPEED_TOL
    on_dome = st[0] > mer.equator_s[1]
    assert on_dome.sum() > 500 and st[0, -1] < mer.equator_s[1]  # over the dome and back
    p = surf.points(st[0][on_dome], st[1][on_dome])
    centre = np.array([0.0, 0.0, mer.equator_t[1]])  # the straight axis runs along +z from the origin
    q = p - centre
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), radius, rtol=1e-12)  # on the sphere
    normal = np.cross(q[0], q[len(q) // 2])
    normal /= np.linalg.norm(normal)
    assert np.max(np.abs(q @ normal)) < GREAT_CIRCLE_TOL * radius


# -- robustness and conventions -------------------------------------------------------------------
def test_shoot_reports_a_geodesic_that_leaves_the_mandrel():
    # Three extra rounds on the cone: unrolled, the straight segment passes within 234.5 mm of the
    # apex, i.e. through r = 23.3 < 30 (the small end): no geodesic on the mandrel joins the points.
    r = shoot(cone(), (20.0, 0.0), (290.0, 0.0), rounds=3)
    assert r.left_mandrel and not r.converged
    assert np.max(r.s) > 300.0


def test_shoot_falls_back_to_minpack(monkeypatch):
    import winder.paths.shooting as shooting

    monkeypatch.setattr(shooting, "MAX_NEWTON", 0)
    r = shooting.shoot(tube(), (20.0, 0.0), (180.0, 3.0), guess=(60.0, 250.0))
    assert "hybr" in r.message and r.converged, r.message
    exact = np.hypot(160.0, R_TUBE * 3.0)
    assert abs(r.length / exact - 1.0) < LENGTH_TOL


def test_heading_convention_on_a_non_orthogonal_parametrization():
    # A cone with an elliptic section: R(s, theta) depends on both, so Phi_s . Phi_theta != 0.
    from winder.paths.headings import heading_of_velocity, velocity_of_heading

    surf = build_surface(MandrelConfig(LineAxis(200.0), ConeProfile(50.0, 30.0), EllipseSection(60.0, 35.0)))
    s = np.array([10.0, 80.0, 150.0, 190.0])
    th = np.array([0.3, 1.0, 2.2, 4.0])
    ev = surf.evaluate(s, th, order=1)
    cosine = (np.einsum("ij,ij->i", ev.ps, ev.pt)
              / (np.linalg.norm(ev.ps, axis=1) * np.linalg.norm(ev.pt, axis=1)))
    assert np.min(np.abs(cosine)) > 0.01  # really not orthogonal
    heads = np.radians(np.array([0.0, 90.0, -35.0, 150.0]))
    ds, dth = velocity_of_heading(surf, s, th, heads)
    vel = ev.ps * ds[:, None] + ev.pt * dth[:, None]
    np.testing.assert_allclose(np.linalg.norm(vel, axis=1), 1.0, rtol=1e-14)
    meridian = ev.ps / np.linalg.norm(ev.ps, axis=1)[:, None]
    np.testing.assert_allclose(np.einsum("ij,ij->i", vel, meridian), np.cos(heads), atol=1e-14)
    # Positive headings turn toward increasing theta: the side of Phi_theta's part across the meridian.
    across = ev.pt - np.einsum("ij,ij->i", ev.pt, meridian)[:, None] * meridian
    across /= np.linalg.norm(across, axis=1)[:, None]
    np.testing.assert_allclose(np.einsum("ij,ij->i", vel, across), np.sin(heads), atol=1e-14)
    back, speed = heading_of_velocity(surf, s, th, ds, dth)
    np.testing.assert_allclose(back, heads, atol=1e-14)
    np.testing.assert_allclose(speed, 1.0, rtol=1e-14)
    assert not surf.is_revolution

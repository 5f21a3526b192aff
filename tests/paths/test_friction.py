"""Friction-held paths (paths.friction, paths.friction_path, geometry.curvature) against independent truths.

Truths: the cylinder's closed form sin(alpha(z)) = sin(alpha0) / (1 - lambda z sin(alpha0) / R); the
variational geodesic solver (a different method) for lambda = 0; on a hemispherical dome an independent
integration of docs/math/07-friction.md's surface-of-revolution ODE, written in z(alpha) so the turnaround is regular;
on a torus docs/math/07-friction.md's k_n and constant-angle lambda(phi) closed forms.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from winder.config.axes import ArcAxis
from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.config.sections import EllipseSection
from winder.config.vessel import Dome, DomeType, VesselProfile
from winder.geometry.curvature import (path_curvatures, polyline_curvatures, torus_constant_angle_slip,
                              torus_least_pressing_angle, torus_normal_curvature)
from winder.paths.friction import trace_friction
from winder.paths.friction_path import Status, friction_path
from winder.paths.geodesic import geodesic
from winder.paths.headings import heading_of_velocity
from winder.paths.ode import trace
from winder.geometry.build import build_surface

CLOSED_FORM_TOL = 1e-10  # sin(alpha) on the cylinder: traced vs closed form
SPEED_TOL = 1e-10  # | |J u'| - 1 | along a trace: the forcing is normal to the fiber
GEODESIC_LENGTH_TOL = 1e-9  # relative: lambda = 0 two-point path vs the variational solver
GEODESIC_END_TOL = 1e-9  # mm: end points of both
TURNAROUND_TOL = 1e-6  # mm: turnaround radius, traced vs the independent z(alpha) integration
KN_TOL = 1e-9  # 1/mm: measured k_n vs the torus closed form
CONSTANT_ANGLE_TOL = 1e-8  # rad: alpha drift of a path steered by the closed-form lambda(phi)
SLIP_TOL = 1e-6  # measured k_g / k_n vs the prescribed lambda (spline measurement error)
POLYLINE_SLIP_TOL = 1e-3  # the same from a 2001-point polyline (second order in the spacing)
END_TOL = 1e-8  # mm: a two-point path's end vs the target (re-traced independently)

R_TUBE, R_BEND = 40.0, 150.0


def tube():
    return build_surface(MandrelConfig(LineAxis(300.0), ConstantProfile(R_TUBE), CircleSection()))


def bend():
    return build_surface(MandrelConfig(ArcAxis(R_BEND, 90.0), ConstantProfile(R_TUBE), CircleSection()))


def vessel(radius=100.0, cylinder=200.0, opening=15.0):
    dome = Dome(DomeType.HEMISPHERE, opening)
    return build_surface(MandrelConfig(None, VesselProfile(radius, cylinder, dome, dome), CircleSection()))


def alpha_along(surface, tr, arc):
    st = tr.state(arc)
    return heading_of_velocity(surface, st[0], st[1], st[2], st[3])[0]


# -- tracing ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("alpha0, lam", [(30.0, 0.1), (55.0, -0.15), (20.0, 0.25)])
def test_cylinder_closed_form(alpha0, lam):
    surf = tube()
    tr = trace_friction(surf, (0.0, 0.4), alpha0, lam, 2000.0)
    arc = np.linspace(0.0, tr.length, 101)
    z = tr.state(arc)[0]
    a0 = np.radians(alpha0)
    exact = np.sin(a0) / (1.0 - lam * z * np.sin(a0) / R_TUBE)
    assert np.max(np.abs(np.sin(alpha_along(surf, tr, arc)) - exact)) < CLOSED_FORM_TOL
    assert tr.speed_error < SPEED_TOL


def test_cylinder_turnaround_where_the_closed_form_reaches_90_deg():
    """sin(alpha) = 1 at z = R (1 - sin(alpha0)) / (lambda sin(alpha0))."""
    surf, a0, lam = tube(), np.radians(40.0), 0.2
    tr = trace_friction(surf, (0.0, 0.0), 40.0, lam, 5000.0, stop_at_turnaround=True)
    assert tr.event == "turnaround"
    z_turn = R_TUBE * (1.0 - np.sin(a0)) / (lam * np.sin(a0))
    assert abs(tr.s[-1] - z_turn) < 1e-6
    assert tr.turnaround_radius == pytest.approx(R_TUBE, abs=1e-9)


def test_zero_slip_is_the_geodesic_trace():
    surf = bend()
    fr = trace_friction(surf, (10.0, 0.3), 50.0, 0.0, 300.0)
    ge = trace(surf, (10.0, 0.3), 50.0, 300.0)
    assert fr.length == pytest.approx(ge.length, abs=1e-9)
    assert np.allclose(fr.state(fr.length)[:2], ge.sol(ge.length), atol=1e-9)


@pytest.mark.parametrize("make", [
    lambda: build_surface(MandrelConfig(LineAxis(300.0), None, EllipseSection(60.0, 35.0))),
    lambda: build_surface(MandrelConfig(ArcAxis(200.0, 60.0), None, EllipseSection(40.0, 30.0))),
], ids=["elliptic tube", "elliptic bend"])
def test_measured_slip_is_the_prescribed_lambda_on_any_sweep(make):
    """On surfaces without a closed form: the path's own k_g / k_n is the lambda(l) it was traced with."""
    surf = make()

    def lam(arc):
        return 0.1 * np.sin(arc / 60.0)

    tr = trace_friction(surf, (5.0, 0.2), 55.0, lam, 250.0)
    arc = np.linspace(0.0, tr.length, 2001)
    st = tr.state(arc)
    k_n, k_g = path_curvatures(surf, arc, st[0], st[1])
    assert k_n.min() > 0.0
    assert np.max(np.abs(k_g / k_n - lam(arc))) < SLIP_TOL
    assert tr.speed_error < SPEED_TOL
    pts = surf.points(st[0], st[1])
    kn_p, kg_p = polyline_curvatures(surf, st[0], st[1], pts)
    assert np.max(np.abs(kg_p / kn_p - lam(arc[1:-1]))) < POLYLINE_SLIP_TOL


# -- vessel dome: the turnaround moves with lambda ---------------------------------------------------------
def dome_turnaround_radius(radius, half_cylinder, alpha0, lam):
    """Independent: docs/math/07-friction.md's d(alpha)/dz on the cylinder (closed form), then on the hemisphere
    r = sqrt(R^2 - z^2) (z from the equator; there r r'' / (1 + r'^2) = -1 and r' = -z / r):
    d(alpha)/dz = lambda / (r cos(alpha)) + z tan(alpha) / r^2, integrated in the polar angle psi
    (z = R sin psi) up to 80 deg, then as dz/d(alpha) (regular at the turnaround, alpha = 90 deg)."""
    a_eq = np.arcsin(np.sin(alpha0) / (1.0 - lam * half_cylinder * np.sin(alpha0) / radius))

    def dalpha_dz(z, alpha):
        r2 = radius**2 - z**2
        return lam / (np.sqrt(r2) * np.cos(alpha)) + z * np.tan(alpha) / r2

    def in_psi(psi, y):
        return [dalpha_dz(radius * np.sin(psi), y[0]) * radius * np.cos(psi)]

    def steep(_psi, y):
        return y[0] - np.radians(80.0)

    steep.terminal = True
    first = solve_ivp(in_psi, (0.0, np.pi / 2), [a_eq], method="DOP853", rtol=1e-13, atol=1e-13, events=steep)
    z80 = radius * np.sin(first.t[-1])
    second = solve_ivp(lambda a, z: [1.0 / dalpha_dz(z[0], a)], (np.radians(80.0), np.pi / 2), [z80],
                       method="DOP853", rtol=1e-13, atol=1e-13)
    return float(np.sqrt(radius**2 - second.y[0, -1] ** 2))


@pytest.mark.parametrize("lam", [0.05, 0.15, -0.03])
def test_vessel_turnaround_radius(lam):
    surf = vessel()
    t_mid = surf.axial_length / 2.0
    s_mid = float(surf.s_of_t(np.array([t_mid]))[0])
    tr = trace_friction(surf, (s_mid, 0.0), 12.0, lam, 2000.0, stop_at_turnaround=True)
    assert tr.event == "turnaround"
    assert tr.turnaround_radius == pytest.approx(
        dome_turnaround_radius(100.0, 100.0, np.radians(12.0), lam), abs=TURNAROUND_TOL)


def test_vessel_zero_slip_turns_at_clairaut():
    surf = vessel()
    s_mid = float(surf.s_of_t(np.array([surf.axial_length / 2.0]))[0])
    tr = trace_friction(surf, (s_mid, 0.0), 12.0, 0.0, 2000.0, stop_at_turnaround=True)
    assert tr.turnaround_radius == pytest.approx(100.0 * np.sin(np.radians(12.0)), abs=TURNAROUND_TOL)


# -- torus ------------------------------------------------------------------------------------------------
def test_torus_normal_curvature():
    surf = bend()
    tr = trace_friction(surf, (5.0, 1.0), 50.0, 0.08, 400.0)
    arc = np.linspace(0.0, tr.length, 2001)
    st = tr.state(arc)
    k_n, _ = path_curvatures(surf, arc, st[0], st[1])
    alpha = alpha_along(surf, tr, arc)
    assert np.max(np.abs(k_n - torus_normal_curvature(alpha, st[1], R_BEND, R_TUBE))) < KN_TOL


def test_torus_constant_angle_slip_closed_form():
    """Steered by lambda(phi(l)) with phi = phi0 + l sin(alpha) / a, the path keeps its angle.

    The closed form is the magnitude for a fiber running toward increasing phi; in the heading
    convention (k_g > 0 turns toward larger alpha) it holds the fiber back: lambda = -closed form."""
    surf, a0, phi0 = bend(), np.radians(60.0), 0.2

    def lam(arc):
        return -torus_constant_angle_slip(a0, phi0 + arc * np.sin(a0) / R_TUBE, R_BEND, R_TUBE)

    tr = trace_friction(surf, (1.0, phi0), 60.0, lam, 200.0)
    arc = np.linspace(0.0, tr.length, 401)
    assert np.max(np.abs(alpha_along(surf, tr, arc) - a0)) < CONSTANT_ANGLE_TOL
    assert np.max(np.abs(lam(np.linspace(0, 2 * np.pi * R_TUBE / np.sin(a0), 2000)))) == pytest.approx(0.19, abs=0.01)


def test_torus_least_pressing_angle():
    assert np.degrees(torus_least_pressing_angle(R_BEND, R_TUBE)) == pytest.approx(31.1, abs=0.05)
    below = np.radians(30.0)
    assert torus_normal_curvature(below, 0.0, R_BEND, R_TUBE) < 0.0


# -- two-point paths ----------------------------------------------------------------------------------------
def test_two_point_zero_slip_reproduces_the_geodesic_solver():
    surf = bend()
    end_t = surf.axial_length
    fr = friction_path(surf, (0.0, 0.3), (end_t, 2.0), rounds=1, mu=0.2)
    geo = geodesic(surf, (0.0, 0.3), (end_t, 2.0), rounds=1, n=400)
    assert fr.success and fr.geodesic and fr.status == Status.OK
    assert np.all(fr.slip == 0.0)
    assert abs(fr.length - geo.length) < GEODESIC_LENGTH_TOL * geo.length
    assert np.linalg.norm(fr.points[-1] - geo.points[-1]) < GEODESIC_END_TOL
    assert fr.max_slip < SLIP_TOL


@pytest.mark.parametrize("extra_deg, degree", [(4.0, 0), (-3.0, 2)])
def test_two_point_with_a_prescribed_heading(extra_deg, degree):
    """The start angle is not the geodesic's: friction holds the path; re-traced, it hits the end."""
    surf, mu = bend(), 0.2
    end_t = surf.axial_length
    geo = friction_path(surf, (0.0, 0.3), (end_t, 2.0), rounds=1)
    fr = friction_path(surf, (0.0, 0.3), (end_t, 2.0), rounds=1, mu=mu, heading_deg=geo.heading_deg + extra_deg,
                       degree=degree)
    assert fr.success, fr.message
    assert fr.heading_deg == pytest.approx(geo.heading_deg + extra_deg, abs=1e-12)
    assert np.abs(fr.slip).max() <= mu and fr.max_slip <= mu + SLIP_TOL
    assert fr.max_slip == pytest.approx(np.abs(fr.slip).max(), abs=SLIP_TOL)
    assert fr.min_normal_curvature > 0.0
    coefs = fr.slip_coefficients

    def lam(arc):
        return np.polynomial.legendre.legval(2.0 * arc / fr.length - 1.0, coefs)

    tr = trace_friction(surf, (fr.s[0], fr.theta[0]), fr.heading_deg, lam, fr.length, stop_at_ends=False)
    end = surf.points(*tr.state(fr.length)[:2, None])[0]
    target = surf.points(np.array([surf.s_of_t(np.array([end_t]))[0]]), np.array([2.0 + 2 * np.pi]))[0]
    assert np.linalg.norm(end - target) < END_TOL


def test_two_point_with_a_prescribed_slip():
    surf = bend()
    fr = friction_path(surf, (0.0, 0.3), (surf.axial_length, 2.0), rounds=1, mu=0.2, slip=0.05)
    assert fr.success and not fr.geodesic
    assert fr.max_slip == pytest.approx(0.05, abs=SLIP_TOL)


def test_two_point_refuses_what_friction_cannot_hold():
    surf = bend()
    geo = friction_path(surf, (0.0, 0.3), (surf.axial_length, 2.0), rounds=1)
    fr = friction_path(surf, (0.0, 0.3), (surf.axial_length, 2.0), rounds=1, mu=0.01,
                       heading_deg=geo.heading_deg + 8.0)
    assert not fr.success and fr.status == Status.SLIPS
    assert "above the friction 0.01" in fr.message

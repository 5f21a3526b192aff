"""winder.geometry.rk on fiber paths: the friction path on a cylinder in closed form (cot(alpha) falls
linearly with the fiber length), and scipy's DOP853 (the same pair, another code) on the traces the
samples make and on dome legs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.config.vessel import Dome, DomeType, VesselProfile
from winder.geometry.build import build_surface
from winder.paths import dome_paths, friction
from winder.paths.dome_paths import close_leg, dome_meridian, solve_slip
from winder.paths.friction import trace_friction
from winder.paths.headings import heading_of_velocity

CLOSED_FORM_TOL = 1e-10  # cylinder friction path at rtol 1e-12: cot(alpha), theta (rad), the turnaround (mm)
STATION_REL_TOL = 1e-11  # the same path's station z, relative to |z| (~1000 mm: rtol times the steps)
SCIPY_TOL = 1e-10  # mm and rad: state agreement with scipy's DOP853 (both at the traces' 1e-10)
SCIPY_LENGTH_TOL = 1e-10  # mm: where the trace stops (the located event)
DOME_TOL = 1e-7  # mm and rad: dome legs, both at their rtol 1e-9 (about 1e-11 apart where the steps coincide)
DOME_SLIP_TOL = 1e-8  # the lambdas those solves find


def cylinder(radius=50.0, length=2000.0):
    return build_surface(MandrelConfig(LineAxis(length), ConstantProfile(radius), CircleSection()))


@pytest.mark.parametrize("alpha0, lam", [(55.0, 0.18), (125.0, -0.18), (30.0, -0.1)])
def test_cylinder_friction_path_closed_form(alpha0, lam):
    """With dalpha/dl = lambda k_n = lambda sin^2(alpha) / R (a positive lambda turns toward larger heading):
    cot(alpha) = cot(alpha0) - lambda l / R, z = -(R / lambda) sqrt(1 + cot^2) + C, theta = -asinh(cot) / lambda + C."""
    big_r, z0, th0 = 50.0, 1000.0, 0.3
    surf = cylinder(big_r)
    tr = trace_friction(surf, (z0, th0), alpha0, lam, 1000.0, stop_at_turnaround=True)
    arc = np.linspace(0.0, tr.length, 301)
    s, th, ds, dth = tr.state(arc)
    alpha = heading_of_velocity(surf, s, th, ds, dth)[0]
    cot0 = 1.0 / math.tan(math.radians(alpha0))
    cot = cot0 - lam * arc / big_r
    assert np.max(np.abs(1.0 / np.tan(alpha) - cot)) < CLOSED_FORM_TOL
    z = z0 - big_r / lam * (np.sqrt(1.0 + cot**2) - math.sqrt(1.0 + cot0**2))
    assert np.max(np.abs(s - z)) < STATION_REL_TOL * np.max(np.abs(z))
    assert np.max(np.abs(th - (th0 - (np.arcsinh(cot) - math.asinh(cot0)) / lam))) < CLOSED_FORM_TOL
    if tr.event == "turnaround":  # cot = 0
        assert abs(tr.length - cot0 * big_r / lam) < CLOSED_FORM_TOL


def scipy_dop853(fun, t_span, y0, *, rtol, atol, dense_output=False, events=None, first_step=None):
    """solve_rk's call served by scipy's DOP853: winder's tracing as it was before it had its own integrator."""
    from scipy.integrate import solve_ivp

    return solve_ivp(fun, t_span, y0, method="DOP853", rtol=rtol, atol=atol, dense_output=dense_output,
                     events=events or None, first_step=first_step)


def vessel():
    dome = Dome(DomeType.HEMISPHERE, 30.0)
    return build_surface(MandrelConfig(None, VesselProfile(100.0, 300.0, dome, dome), CircleSection()))


# (surface, start, heading, slip, length): the turnaround legs of samples/pipe.yaml and samples/vessel_hemi.yaml
SAMPLE_TRACES = {
    "pipe start": (lambda: cylinder(50.0, 500.0), (20.0, 0.0), 125.0, -0.18, 6102.06),
    "pipe end": (lambda: cylinder(50.0, 500.0), (480.0, 0.0), 55.0, 0.18, 6102.06),
    "pipe hoop": (lambda: cylinder(50.0, 500.0), (480.0, 0.0), 88.17591057446326, 0.18, 109955.7),
    "vessel": (vessel, (426.6, 0.0), 89.08807084539677, 0.18, 711917.5),
}


@pytest.mark.parametrize("name", list(SAMPLE_TRACES))
def test_agrees_with_scipy_dop853_on_the_samples_traces(name, monkeypatch):
    make, start, heading, slip, length = SAMPLE_TRACES[name]
    surf, tol = make(), 1e-10
    tr = trace_friction(surf, start, heading, slip, length, rtol=tol, atol=tol, stop_at_turnaround=True)
    monkeypatch.setattr(friction, "solve_rk", scipy_dop853)
    ref = trace_friction(surf, start, heading, slip, length, rtol=tol, atol=tol, stop_at_turnaround=True)
    assert tr.event == ref.event and tr.event in ("turnaround", "end")
    assert abs(tr.length - ref.length) < SCIPY_LENGTH_TOL
    arc = np.linspace(0.0, tr.length, 401)
    assert np.max(np.abs(tr.state(arc) - ref.state(arc))) < SCIPY_TOL


@pytest.mark.parametrize("dome", [0, 1])
def test_dome_legs_agree_with_scipy_dop853(dome, monkeypatch):
    """The turnaround-radius solve and the pattern-closing fit of a vessel dome (dome_paths), both ways."""
    prof = vessel().profile
    s_eq = prof.equator_s[dome]
    heading = math.radians(15.0) if dome == 1 else math.pi - math.radians(15.0)
    meridian = dome_meridian(prof, dome == 1)
    results = []
    for integrator in (dome_paths.solve_rk, scipy_dop853):
        monkeypatch.setattr(dome_paths, "solve_rk", integrator)
        lam, leg = solve_slip(meridian, s_eq, heading, 45.0)
        lam0, lam1, closed = close_leg(meridian, s_eq, heading, 45.0, lam, leg.length, leg.advance + 0.01)
        results.append((lam, leg, lam0, lam1, closed))
    (lam, leg, lam0, lam1, closed), (lam_r, leg_r, lam0_r, lam1_r, closed_r) = results
    assert leg.turned and closed.turned
    assert max(abs(lam - lam_r), abs(lam0 - lam0_r), abs(lam1 - lam1_r)) < DOME_SLIP_TOL
    for a, b in ((leg, leg_r), (closed, closed_r)):
        assert abs(a.length - b.length) < DOME_TOL and abs(a.radius - b.radius) < DOME_TOL
        assert abs(a.advance - b.advance) < DOME_TOL
        arc = np.linspace(0.0, a.length, 201)
        assert np.max(np.abs(a.state(arc) - b.state(arc))) < DOME_TOL

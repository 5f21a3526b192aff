"""The closed-form friction path on a cylinder (winder.paths.friction_cylinder) against scipy's
integration of the general friction ODE (winder.paths.friction) on the same surface: the two share no
code but the surface."""

from __future__ import annotations

import numpy as np
import pytest

from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.geometry.build import build_surface
from winder.paths.friction import _integrated_trace, trace_friction

ODE_TOL = 1e-8  # mm and rad: DOP853 at rtol 1e-12 over about a metre of fiber, against the closed form
LENGTH_TOL = 1e-6  # mm: where the integrator's event and the closed form find the turnaround or the end


def cylinder(radius: float = 60.0, length: float = 900.0):
    return build_surface(MandrelConfig(LineAxis(length), ConstantProfile(radius), CircleSection()))


# heading (deg, signed: toward -theta below 0), slip, start station: turnarounds, both mirror images,
# the mandrel's end reached first, and a helix (slip 0)
CASES = [(55.0, 0.2, 450.0), (125.0, -0.2, 450.0), (-55.0, -0.2, 450.0), (-125.0, 0.2, 450.0),
         (20.0, 0.05, 800.0), (160.0, -0.05, 100.0), (40.0, 0.0, 450.0), (70.0, 0.3, 890.0)]


@pytest.mark.parametrize("heading, lam, z0", CASES)
def test_closed_form_matches_the_integrated_ode(heading, lam, z0):
    surf = cylinder()
    assert surf.cylinder_radius == pytest.approx(60.0)
    exact = trace_friction(surf, (z0, 0.4), heading, lam, 5000.0, stop_at_turnaround=True)
    assert exact.nfev == 0  # the closed form, not the integrator
    ode = _integrated_trace(surf, z0, 0.4, heading, lam, 5000.0, 1e-12, 1e-12, True, True)
    assert exact.event == ode.event
    assert exact.length == pytest.approx(ode.length, abs=LENGTH_TOL)
    arc = np.linspace(0.0, min(exact.length, ode.length), 97)
    assert np.max(np.abs(exact.state(arc) - ode.state(arc))) < ODE_TOL


def test_a_cone_is_not_a_cylinder():
    from winder.config.profiles import ConeProfile  # noqa: PLC0415

    cone = build_surface(MandrelConfig(LineAxis(900.0), ConeProfile(60.0, 50.0), CircleSection()))
    assert cone.cylinder_radius is None
    assert trace_friction(cone, (450.0, 0.0), 55.0, 0.2, 2000.0, stop_at_turnaround=True).nfev > 0

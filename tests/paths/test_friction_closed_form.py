"""Friction paths traced by scipy's DOP853: the friction path on a cylinder in closed form (cot(alpha)
falls linearly with the fiber length)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.geometry.build import build_surface
from winder.paths.friction import trace_friction
from winder.paths.headings import heading_of_velocity

CLOSED_FORM_TOL = 1e-10  # cylinder friction path at rtol 1e-12: cot(alpha), theta (rad), the turnaround (mm)
STATION_REL_TOL = 1e-11  # the same path's station z, relative to |z| (~1000 mm: rtol times the steps)


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

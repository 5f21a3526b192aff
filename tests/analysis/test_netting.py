"""Netting closed forms (docs/math/09-structure.md 9.2; issue 32's numbers)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.analysis.loads import LoadCase, resultants, revolution_geometry
from winder.analysis.netting import OPTIMUM_ANGLE, capacities, cylinder_limits, limits, optimum_angle, sizing

CLOSED_FORM = 1e-9  # the formulas are a few flops: exact to round-off
R, SIGMA = 100.0, 2000.0


def test_cylinder_limits_of_the_issue():
    a = math.radians(30.0)
    lim = cylinder_limits(R, SIGMA, 2.0, a, hoop_thickness=1.0)
    assert abs(lim.axial[0] - 2 * SIGMA * 2.0 * math.cos(a) ** 2 / R) < CLOSED_FORM
    assert abs(lim.axial[0] - 60.0) < CLOSED_FORM
    assert abs(lim.hoop[0] - 30.0) < CLOSED_FORM
    assert abs(lim.pressure - 30.0) < CLOSED_FORM
    assert lim.limit == "hoop"


def test_sizing_of_the_issue():
    t_h, t_c = sizing(30.0, R, SIGMA, math.radians(30.0))
    assert abs(t_h - 1.0) < CLOSED_FORM
    assert abs(t_c - 1.25) < CLOSED_FORM
    # the sized wall bursts at the pressure it was sized for, by both limits
    lim = cylinder_limits(R, SIGMA, t_h, math.radians(30.0), t_c)
    assert abs(lim.axial[0] - 30.0) < CLOSED_FORM and abs(lim.hoop[0] - 30.0) < CLOSED_FORM


def test_optimum_angle_balances_a_helical_layer_alone():
    assert abs(math.degrees(OPTIMUM_ANGLE) - 54.7356) < 5e-5
    assert abs(optimum_angle(0.5 * R, R) - OPTIMUM_ANGLE) < CLOSED_FORM
    t = 1.7
    lim = cylinder_limits(R, SIGMA, t, OPTIMUM_ANGLE)
    expected = 2 * SIGMA * t / (3 * R)
    assert abs(lim.axial[0] - expected) < CLOSED_FORM and abs(lim.hoop[0] - expected) < CLOSED_FORM
    t_h, t_c = sizing(30.0, R, SIGMA, OPTIMUM_ANGLE)
    assert abs(t_c) < CLOSED_FORM and abs(t_h - 3 * 30.0 * R / (2 * SIGMA)) < CLOSED_FORM


def test_past_the_optimum_no_hoops_are_needed():
    a = math.radians(70.0)
    t_h, t_c = sizing(30.0, R, SIGMA, a)
    assert t_c == 0.0
    assert abs(t_h - 30.0 * R / (2 * SIGMA * math.cos(a) ** 2)) < CLOSED_FORM
    lim = cylinder_limits(R, SIGMA, t_h, a)
    assert abs(lim.axial[0] - 30.0) < CLOSED_FORM and lim.hoop[0] > 30.0


def test_open_ends_need_hoops_only():
    lim = cylinder_limits(R, SIGMA, 2.0, math.radians(30.0), 1.0, closed=False)
    assert math.isinf(lim.axial[0]) and abs(lim.hoop[0] - 30.0) < CLOSED_FORM
    assert sizing(30.0, R, SIGMA, math.radians(30.0), closed=False) == pytest.approx((0.0, 1.5), abs=CLOSED_FORM)


def test_sphere_membrane_loads_and_its_netting():
    """A sphere of radius R (meridian r = R sin u, z = -R cos u): N_m = N_h = p R / 2, and a quasi-isotropic
    net of +-45 deg bursts at 2 sigma t sin^2(45) / R on both limits."""
    u = np.linspace(0.3, 1.5, 7)
    geo = revolution_geometry(u, R * np.sin(u), R * np.cos(u), R * np.sin(u), -R * np.sin(u), R * np.cos(u))
    per_p, held = resultants(geo, LoadCase(1.0))
    assert np.allclose(per_p[:, :2], 0.5 * R, rtol=0, atol=CLOSED_FORM * R) and not held.any()
    cap_m, cap_h = capacities(SIGMA, np.full((7, 1), 1.2), np.full((7, 1), math.radians(45.0)))
    lim = limits(cap_m, cap_h, per_p, held)
    assert np.allclose(lim.burst, SIGMA * 1.2 / R, rtol=0, atol=CLOSED_FORM)


def test_axial_force_adds_to_the_axial_demand():
    f = 2 * math.pi * R * 50.0  # 50 N/mm of meridional load
    lim = cylinder_limits(R, SIGMA, 2.0, math.radians(30.0), 1.0, axial_force=f)
    assert abs(lim.axial[0] - (SIGMA * 2.0 * 0.75 - 50.0) / (R / 2)) < CLOSED_FORM

"""Membrane loads of shells of revolution (docs/math/09-structure.md 9.1) and the station analysis of an
open-ended pipe against closed forms."""

from __future__ import annotations

import math

import numpy as np

from winder.analysis.clt import abd, membrane_strains, reduced_stiffness, rotated_stiffness
from winder.analysis.loads import LoadCase, resultants, revolution_geometry
from winder.analysis.materials import MATERIALS

CLOSED_FORM = 1e-9


def _cylinder(radius: float, n: int = 3):
    z = np.linspace(0.0, 100.0, n)
    one, zero = np.ones(n), np.zeros(n)
    return revolution_geometry(z, radius * one, zero, one, zero, zero)


def test_cylinder_loads_closed_open_axial_force_and_torque():
    geo = _cylinder(100.0)
    per_p, held = resultants(geo, LoadCase(1.0, axial_force=2 * math.pi * 100.0 * 7.0, torque=2 * math.pi * 1e4 * 3.0))
    assert np.allclose(per_p, [[50.0, 100.0, 0.0]] * 3, rtol=0, atol=CLOSED_FORM)
    assert np.allclose(held, [[7.0, 0.0, 3.0]] * 3, rtol=0, atol=CLOSED_FORM)
    per_p, _ = resultants(geo, LoadCase(1.0, closed=False))
    assert np.allclose(per_p, [[0.0, 100.0, 0.0]] * 3, rtol=0, atol=CLOSED_FORM)


def test_ellipsoidal_dome_hoop_load_turns_compressive_at_the_equator():
    """An oblate ellipsoid (a = 100, b = 50): at the equator N_m = p a / 2, N_h = p a (1 - a^2 / (2 b^2))
    (Timoshenko's closed form), compressive for a / b > sqrt 2."""
    a, b = 100.0, 50.0
    u = np.array([0.5 * math.pi])  # r = a sin u, z = -b cos u
    geo = revolution_geometry(u, a * np.sin(u), a * np.cos(u), b * np.sin(u), -a * np.sin(u), b * np.cos(u))
    per_p, _ = resultants(geo, LoadCase(1.0))
    assert abs(per_p[0, 0] - a / 2) < CLOSED_FORM * a
    assert abs(per_p[0, 1] - a * (1 - a * a / (2 * b * b))) < CLOSED_FORM * a


def test_membrane_strains_of_a_hoop_wound_pipe_are_the_ply_compliance():
    """Hoops alone (one 90 deg ply) under open-ended pressure: eps_h = p R / (E1 t), eps_m = -nu12 eps_h."""
    ply = MATERIALS["eglass_epoxy"]
    t, radius, p = 2.0, 50.0, 4.0
    q = reduced_stiffness(ply)
    a, _, _ = abd(rotated_stiffness(q[None, None], np.full((1, 1), 0.5 * math.pi)), np.full((1, 1), t))
    per_p, _ = resultants(_cylinder(radius, 1), LoadCase(p, closed=False))
    eps = membrane_strains(a, p * per_p)[0]
    hoop = p * radius / (ply.E1 * t)
    assert abs(eps[1] - hoop) < 1e-12 and abs(eps[0] + ply.nu12 * hoop) < 1e-12 and abs(eps[2]) < 1e-15

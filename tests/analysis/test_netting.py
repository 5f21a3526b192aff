"""Netting with every load (docs/math/09-structure.md 9.2): the statically determinate fiber forces of a
+-a + hoop wall under pressure, axial force and torque, each alone and together, against their closed
forms; the first family to reach its allowable sets the burst; mechanisms, indeterminate walls, loads
no fiber carries, and held loads that alone break the net."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.analysis.loads import LoadCase, resultants, revolution_geometry
from winder.analysis.netting import (OPTIMUM_ANGLE, Wall, cylinder_loads, cylinder_wall, family_stresses, limits,
                                     optimum_angle, sizing)

CLOSED_FORM = 1e-9  # the formulas are a few flops: exact to round-off (relative to the stresses' size)
R, SIGMA, SIGMA_C = 100.0, 2000.0, 1200.0
A = math.radians(30.0)
T_H, T_C = 2.0, 1.0
C, S = math.cos(A), math.sin(A)


def _stresses(per_p, held, pressure=0.0, wall=None):
    """(+a, -a, hoop) fiber stresses of the +-30 + hoop wall at `pressure` with the held loads."""
    wall = wall or cylinder_wall(T_H, A, T_C, tension=SIGMA, compression=SIGMA_C)
    sa, sb, lost, group = family_stresses(wall, per_p, held)
    assert np.allclose(sa, sb) and not lost.any() and group[0] == 1  # determinate: one answer, all carried
    return sa[0, :, 0] * pressure + sa[0, :, 1]


def test_pressure_alone_each_family_by_statics():
    per_p, held = cylinder_loads(R)
    got = _stresses(per_p, held, 1.0)
    helical = R / (2 * C * C * T_H)  # S = N_m / cos^2 a on t_h, the same in both families
    hoop = R * (1 - math.tan(A) ** 2 / 2) / T_C  # N_h - S sin^2 a on t_c
    assert got == pytest.approx([helical, helical, hoop], rel=CLOSED_FORM)
    burst = limits(cylinder_wall(T_H, A, T_C, tension=SIGMA, compression=SIGMA_C), per_p, held)
    assert burst.pressure == pytest.approx(min(SIGMA / helical, SIGMA / hoop), rel=CLOSED_FORM)
    assert burst.pressure == pytest.approx(24.0, rel=CLOSED_FORM)  # not 30: the helicals are not at sigma then
    assert burst.layer[0] == 1 and not burst.compression[0]


def test_axial_force_alone_pulls_the_helicals_and_pushes_the_hoops():
    force = 2 * math.pi * R * 50.0  # 50 N/mm along the meridian
    per_p, held = cylinder_loads(R, axial_force=force)
    got = _stresses(per_p * 0.0, held)
    helical = 50.0 / (C * C * T_H)
    assert got == pytest.approx([helical, helical, -50.0 * math.tan(A) ** 2 / T_C], rel=CLOSED_FORM)


def test_torque_alone_loads_the_helical_families_oppositely():
    torque = 3.0e6
    per_p, held = cylinder_loads(R, torque=torque)
    got = _stresses(per_p * 0.0, held)
    d = torque / (2 * math.pi * R * R) / (S * C * T_H)  # f+ - f- = N_mh / (sin a cos a), on t_h / 2 each
    assert got[0] == pytest.approx(d, rel=CLOSED_FORM) and got[1] == pytest.approx(-d, rel=CLOSED_FORM)
    assert abs(got[2]) < CLOSED_FORM * d


@pytest.mark.parametrize("closed", [True, False])
def test_all_loads_together_superpose_and_the_first_family_bursts(closed):
    force, torque = 2.0e5, 3.0e6
    per_p, held = cylinder_loads(R, closed, force, torque)
    n_m = np.array([R / 2 if closed else 0.0, force / (2 * math.pi * R)])  # [per MPa, held]
    n_h = np.array([R, 0.0])
    n_mh = np.array([0.0, torque / (2 * math.pi * R * R)])
    plus = (n_m / (C * C) + n_mh / (S * C)) / T_H
    minus = (n_m / (C * C) - n_mh / (S * C)) / T_H
    hoop = (n_h - n_m * math.tan(A) ** 2) / T_C
    p = 7.0
    assert _stresses(per_p, held, p) == pytest.approx([plus @ [p, 1], minus @ [p, 1], hoop @ [p, 1]], rel=CLOSED_FORM)
    first = min((SIGMA - f[1]) / f[0] for f in (plus, minus, hoop) if f[0] > 0)
    burst = limits(cylinder_wall(T_H, A, T_C, tension=SIGMA, compression=SIGMA_C), per_p, held)
    assert burst.pressure == pytest.approx(first, rel=CLOSED_FORM)


def test_held_loads_that_alone_break_a_family_give_zero():
    per_p, held = cylinder_loads(R, torque=2 * math.pi * R * R * SIGMA * T_H * S * C * 1.01)  # past +a's allowable
    assert limits(cylinder_wall(T_H, A, T_C, tension=SIGMA, compression=SIGMA_C), per_p, held).pressure == 0.0
    per_p, held = cylinder_loads(R, axial_force=-2 * math.pi * R * SIGMA_C * T_H * C * C * 1.01)  # crushed helicals
    burst = limits(cylinder_wall(T_H, A, T_C, tension=SIGMA, compression=SIGMA_C), per_p, held)
    assert burst.pressure == 0.0 and burst.compression[0]


def test_sizing_with_torque_bursts_where_it_was_sized():
    p, torque = 30.0, 4.0e6
    t_h, t_c = sizing(p, R, SIGMA, A, torque=torque)
    per_p, held = cylinder_loads(R, torque=torque)
    burst = limits(cylinder_wall(t_h, A, t_c, tension=SIGMA, compression=SIGMA), per_p, held)
    assert burst.pressure == pytest.approx(p, rel=1e-9)
    assert sizing(30.0, R, SIGMA, A) == pytest.approx((1.0, 1.25), abs=CLOSED_FORM)  # docs/math 9.2's example


def test_a_single_angle_net_is_a_mechanism_netted_direction_wise():
    """+-a alone: two families, three equations; the classic netting takes each direction's demand."""
    for deg in (30.0, 70.0, math.degrees(OPTIMUM_ANGLE)):
        a = math.radians(deg)
        wall = cylinder_wall(1.7, a, 0.0, tension=SIGMA, compression=SIGMA_C)
        burst = limits(wall, *cylinder_loads(R))
        expected = min(2 * SIGMA * 1.7 * math.cos(a) ** 2 / R, SIGMA * 1.7 * math.sin(a) ** 2 / R)
        assert burst.pressure == pytest.approx(expected, rel=CLOSED_FORM) and burst.group[0] == 0
    assert limits(cylinder_wall(1.7, OPTIMUM_ANGLE, 0.0, tension=SIGMA), *cylinder_loads(R)).pressure == \
        pytest.approx(2 * SIGMA * 1.7 / (3 * R), rel=CLOSED_FORM)
    assert abs(optimum_angle(0.5 * R, R) - OPTIMUM_ANGLE) < CLOSED_FORM


def test_loads_no_fiber_carries_break_the_net_at_once():
    hoops = cylinder_wall(np.zeros(0), np.zeros(0), 1.0, tension=SIGMA)
    assert limits(hoops, *cylinder_loads(R)).pressure == 0.0  # closed ends: axial load, no axial fiber
    assert limits(hoops, *cylinder_loads(R, closed=False)).pressure == pytest.approx(SIGMA / R, rel=CLOSED_FORM)
    assert limits(hoops, *cylinder_loads(R, closed=False, torque=1.0)).pressure == 0.0  # shear: no helical
    assert limits(hoops, *cylinder_loads(R, closed=False, torque=1.0)).layer[0] == -1


def test_an_indeterminate_wall_balances_the_loads_with_one_fiber_strain():
    """Two helical angles and hoops: five families, three equations. The forces still balance the loads,
    and every family's stress over its modulus is one membrane strain's component along it."""
    wall = Wall(angle=np.radians([[20.0, 50.0, 90.0]]), thickness=np.array([[0.8, 1.1, 0.6]]),
                helical=np.array([True, True, False]), modulus=np.array([140e3, 40e3, 140e3]),
                tension=np.full(3, SIGMA), compression=np.full(3, SIGMA_C))
    per_p, held = cylinder_loads(R, axial_force=1e5, torque=5e6)
    sa, sb, _, group = family_stresses(wall, per_p, held)
    assert group[0] == 2 and np.allclose(sa, sb)
    layer, sign = wall.families
    a = wall.angle[0, layer] * sign
    t = wall.thickness[0, layer] * np.where(wall.helical[layer], 0.5, 1.0)
    for col, load in ((0, per_p[0]), (1, held[0])):
        force = sa[0, :, col] * t
        balance = [np.sum(force * np.cos(a) ** 2), np.sum(force * np.sin(a) ** 2), np.sum(force * np.sin(a) * np.cos(a))]
        assert balance[:2] == pytest.approx(load[:2], rel=1e-9, abs=1e-9 * np.abs(load).max())
        strain = sa[0, :, col] / wall.modulus[layer]
        basis = np.column_stack([np.cos(a) ** 2, np.sin(a) ** 2, np.sin(a) * np.cos(a)])[:4]  # helical families
        fit, *_ = np.linalg.lstsq(basis, strain[:4], rcond=None)
        assert np.allclose(basis @ fit, strain[:4], rtol=0, atol=1e-9 * np.abs(strain).max())
    assert np.sum(sa[0, :4, 1] * t[:4] * np.sin(a[:4]) * np.cos(a[:4])) == pytest.approx(held[0, 2], rel=1e-9)


def test_sphere_membrane_loads_and_its_netting():
    """A sphere (r = R sin u, z = -R cos u): N_m = N_h = p R / 2; a +-45 net (the optimum there) bursts
    at sigma t / R."""
    u = np.linspace(0.3, 1.5, 7)
    geo = revolution_geometry(u, R * np.sin(u), R * np.cos(u), R * np.sin(u), -R * np.sin(u), R * np.cos(u))
    per_p, held = resultants(geo, LoadCase(1.0))
    assert np.allclose(per_p[:, :2], 0.5 * R, rtol=0, atol=CLOSED_FORM * R) and not held.any()
    wall = Wall(angle=np.full((7, 1), math.radians(45.0)), thickness=np.full((7, 1), 1.2), helical=np.array([True]),
                modulus=np.ones(1), tension=np.full(1, SIGMA), compression=np.full(1, SIGMA_C))
    assert np.allclose(limits(wall, per_p, held).burst, SIGMA * 1.2 / R, rtol=CLOSED_FORM, atol=0)


def test_the_issues_pipe():
    """Issue 44's +-30 + hoop pipe (R 50, its allowable 1897.5 MPa; the thicknesses its direction-wise 34.955
    MPa implies): the determinate families burst at 33.36 MPa, and at 29.69 with a torque of 3e6 N mm."""
    radius, sigma, a = 50.0, 1897.5, math.radians(30.0)
    t_h, t_c = 0.7543, 0.7325
    old = min(2 * sigma * t_h * math.cos(a) ** 2 / radius, sigma * (t_h * math.sin(a) ** 2 + t_c) / radius)
    assert old == pytest.approx(34.955, abs=2e-3)
    wall = cylinder_wall(t_h, a, t_c, tension=sigma, compression=SIGMA_C)
    assert limits(wall, *cylinder_loads(radius)).pressure == pytest.approx(33.36, abs=2e-3)
    assert limits(wall, *cylinder_loads(radius, torque=3.0e6)).pressure == pytest.approx(29.69, abs=2e-2)

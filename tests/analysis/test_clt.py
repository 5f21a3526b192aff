"""CLT against hand-derived closed forms (docs/math/09-structure.md 9.3), and first-ply failure of a UD ply
at its strengths (9.4)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.analysis.clt import abd, membrane_strains, ply_response, reduced_stiffness, rotated_stiffness
from winder.analysis.failure import max_stress_index, max_stress_pressure, tsai_wu_index, tsai_wu_pressure
from winder.analysis.materials import MATERIALS, Lamina

CLOSED_FORM = 1e-9  # relative: sums of a few products


def _qbar_polynomials(q11, q22, q12, q66, a):
    """Qbar typed from the polynomials of docs/math 9.3 (Jones, Daniel & Ishai), not from T matrices."""
    m, n = math.cos(a), math.sin(a)
    b11 = q11 * m**4 + 2 * (q12 + 2 * q66) * m**2 * n**2 + q22 * n**4
    b22 = q11 * n**4 + 2 * (q12 + 2 * q66) * m**2 * n**2 + q22 * m**4
    b12 = (q11 + q22 - 4 * q66) * m**2 * n**2 + q12 * (m**4 + n**4)
    b66 = (q11 + q22 - 2 * q12 - 2 * q66) * m**2 * n**2 + q66 * (m**4 + n**4)
    b16 = (q11 - q12 - 2 * q66) * m**3 * n + (q12 - q22 + 2 * q66) * m * n**3
    b26 = (q11 - q12 - 2 * q66) * m * n**3 + (q12 - q22 + 2 * q66) * m**3 * n
    return np.array([[b11, b12, b16], [b12, b22, b26], [b16, b26, b66]])


@pytest.mark.parametrize("deg", [20.0, 55.0, 75.0])
def test_abd_of_plus_minus_a_90_against_the_closed_form(deg):
    ply = MATERIALS["carbon_epoxy"]
    t = 0.3
    d = 1 - ply.nu12 * ply.nu12 * ply.E2 / ply.E1
    q11, q22, q12, q66 = ply.E1 / d, ply.E2 / d, ply.nu12 * ply.E2 / d, ply.G12
    a = math.radians(deg)
    qa, qm, q90 = (_qbar_polynomials(q11, q22, q12, q66, x) for x in (a, -a, math.pi / 2))
    assert np.allclose(q90, [[q22, q12, 0], [q12, q11, 0], [0, 0, q66]], rtol=0, atol=1e-9 * q11)
    a_ref = t * (qa + qm + q90)
    b_ref = t * t * (q90 - qa)
    d_ref = t**3 * (13 * qa + qm + 13 * q90) / 12
    q = reduced_stiffness(ply)
    angles = np.array([[a, -a, math.pi / 2]])
    a_, b_, d_ = abd(rotated_stiffness(q[None, None], angles), np.full((1, 3), t))
    for got, ref in ((a_[0], a_ref), (b_[0], b_ref), (d_[0], d_ref)):
        scale = np.abs(ref).max()
        assert np.abs(got - ref).max() <= CLOSED_FORM * scale
    assert abs(a_ref[0, 2]) < CLOSED_FORM * q11 and abs(a_ref[1, 2]) < CLOSED_FORM * q11  # balanced


UD = Lamina("ud", E1=140_000.0, E2=10_000.0, G12=5_000.0, nu12=0.3, Xt=2000.0, Xc=1200.0, Yt=50.0, Yc=200.0,
            S=70.0)
STRENGTH = (UD.Xt, UD.Xc, UD.Yt, UD.Yc, UD.S)


def _ud_stress(direction, load):
    """A single 0-deg ply of thickness 1 under N = load along direction (0: x, 1: y, 2: shear): its stresses."""
    q = reduced_stiffness(UD)
    a, _, _ = abd(rotated_stiffness(q[None, None], np.zeros((1, 1))), np.ones((1, 1)))
    n = np.zeros((1, 3))
    n[0, direction] = load
    return ply_response(membrane_strains(a, n), np.zeros((1, 1)), q[None, None])[1][0, 0]


@pytest.mark.parametrize("direction,sign,strength", [(0, 1, UD.Xt), (0, -1, UD.Xc), (1, 1, UD.Yt),
                                                     (1, -1, UD.Yc), (2, 1, UD.S)])
def test_first_ply_failure_of_a_ud_ply_at_its_strength(direction, sign, strength):
    per_unit = _ud_stress(direction, sign * 1.0)  # stress per unit load: uniaxial, the load itself
    assert abs(per_unit[direction] - sign) < 1e-12 and np.abs(np.delete(per_unit, direction)).max() < 1e-12
    held = np.zeros(3)
    assert abs(max_stress_pressure(per_unit, held, STRENGTH) - strength) < 1e-9 * strength
    # Tsai-Wu under a single stress component fails exactly at that strength: F1 s + F11 s^2 = 1
    assert abs(tsai_wu_pressure(per_unit, held, STRENGTH) - strength) < 1e-9 * strength
    at = per_unit * strength
    assert abs(tsai_wu_index(at, STRENGTH) - 1.0) < 1e-12
    assert abs(max_stress_index(at, STRENGTH) - 1.0) < 1e-12


def test_held_loads_shift_the_failure_pressure():
    per_p = np.array([1.0, 0.0, 0.0])
    held = np.array([500.0, 0.0, 0.0])
    assert abs(max_stress_pressure(per_p, held, STRENGTH) - 1500.0) < 1e-9
    assert abs(tsai_wu_pressure(per_p, held, STRENGTH) - 1500.0) < 1e-9

"""Tension loss in a wound wall (winder.analysis.prestress, docs/math/16-winding-tension.md): the ring
stack's changes against its equations solved by hand for two hoop layers on a rigid mandrel and one on
an elastic mandrel, and the uniform-prestress schedule leaving every layer the residual."""

from __future__ import annotations

import numpy as np
import pytest

from winder.analysis.prestress import RingStack, residual_tensions, tension_changes, uniform_prestress

REL = 1e-10  # two eliminations of the same linear equations
E1, E2, ER, AREA = 140_000.0, 10_000.0, 60.0, 10.0 * 0.5  # MPa, MPa, MPa (a wet wall), mm^2


def _stack(radius, thickness, mandrel=np.inf, angle=90.0):
    n = len(radius)
    return RingStack(radius=np.array(radius, float), thickness=np.array(thickness, float),
                     angle_deg=np.full(n, angle), e1=np.full(n, E1), e2=np.full(n, E2), band_area=np.full(n, AREA),
                     radial_modulus=np.full(n, ER), mandrel_stiffness=mandrel)


def test_two_hoop_layers_on_a_rigid_mandrel_by_hand():
    r1, r2, h1, h2 = 100.25, 100.75, 0.5, 0.5
    hoop1, hoop2 = E1 * h1 / r1**2, E1 * h2 / r2**2  # a hoop ring's stiffness, pressure per inward mm
    k1, k2 = ER / (h1 / 2), ER / ((h1 + h2) / 2)  # the springs under each ring
    p1, p2 = h1 / (AREA * r1), h2 / (AREA * r2)  # the pressure of 1 N of winding tension
    u_alone = p1 / (hoop1 + k1)
    u2 = p2 / (hoop2 + k2 - k2**2 / (hoop1 + k1 + k2))
    u1 = k2 * u2 / (hoop1 + k1 + k2)
    g = tension_changes(_stack([r1, r2], [h1, h2]))
    assert g[0, 0] == pytest.approx(-E1 * AREA / r1 * u_alone, rel=REL)
    assert g[0, 1] == pytest.approx(-E1 * AREA / r1 * u1, rel=REL)
    assert g[1, 1] == pytest.approx(-E1 * AREA / r2 * u2, rel=REL)
    assert g[1, 0] == 0.0  # layer 2 did not exist while layer 1 was wound


def test_an_elastic_mandrel_is_a_spring_in_series():
    r, h, km = 80.25, 0.5, 500.0
    hoop, k = E1 * h / r**2, ER / (h / 2)
    u = (h / (AREA * r)) / (hoop + k * km / (k + km))
    g = tension_changes(_stack([r], [h], mandrel=km))
    assert g[0, 0] == pytest.approx(-E1 * AREA / r * u, rel=REL)


def test_a_stiff_wall_loses_nothing():
    g = tension_changes(RingStack(radius=np.array([50.25, 50.75]), thickness=np.array([0.5, 0.5]),
                                  angle_deg=np.array([90.0, 90.0]), e1=np.full(2, E1), e2=np.full(2, E2),
                                  band_area=np.full(2, AREA), radial_modulus=np.full(2, 1e15)))
    assert np.abs(g).max() < 1e-6


@pytest.mark.parametrize("angle", [30.0, 55.0, 89.0])
def test_uniform_prestress_leaves_every_layer_the_residual(angle):
    n = 24
    stack = _stack(100.0 + 0.5 * np.arange(n) + 0.25, np.full(n, 0.5), mandrel=2000.0, angle=angle)
    wound = uniform_prestress(stack, 30.0)
    assert residual_tensions(stack, wound) == pytest.approx(np.full(n, 30.0), rel=1e-9)
    # A constant tension leaves the inner layers less than the outer ones: the loss the schedule makes up.
    constant = residual_tensions(stack, np.full(n, 30.0))
    assert constant[-1] > constant[n // 2] and np.all(constant < 30.0)
    assert np.all(wound >= 30.0 - 1e-9)

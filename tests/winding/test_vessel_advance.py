"""winder.winding.layers.vessel_advance.advances: the geodesic's theta advance over a vessel, against
closed forms, and smooth in the Clairaut constant down to round-off (the pattern closing solves
advance(c) = k / N_c, so any jitter in it moves the whole layer)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.geometry.domes import Hemisphere
from winder.geometry.vessel import VesselMeridian
from winder.winding.layers.vessel_advance import advances, half_advance

QUARTER_TOL = 2e-14  # rad: a hemisphere's quarter turn (round-off; past 80 deg r^2 - c^2 is small
# over the whole dome and the advance itself ill-conditioned: 2e-13 at 88 deg)
JITTER_TOL = 1e-14  # rad: advance(c) about its chord over c spaced 1e-14 mm apart
RADIUS, OPENING, CYLINDER = 80.0, 25.0, 300.0


@pytest.fixture(scope="module")
def vessel() -> VesselMeridian:
    return VesselMeridian(RADIUS, CYLINDER, Hemisphere(RADIUS, OPENING), Hemisphere(RADIUS, OPENING))


@pytest.mark.parametrize("angle_deg", [20.0, 35.0, 55.0, 70.0, 80.0])
def test_hemisphere_domes_turn_a_quarter_and_the_cylinder_is_clairaut(vessel, angle_deg):
    """A geodesic on a sphere is a great circle: from its highest parallel r = c down to the equator
    it turns exactly pi / 2 about the axis, whatever c. On the cylinder theta = L tan(alpha) / R."""
    c = RADIUS * math.sin(math.radians(angle_deg))
    if c <= OPENING:
        pytest.skip("turns inside the polar opening")
    first, cylinder, end = advances(vessel, c)
    assert abs(first - math.pi / 2) < QUARTER_TOL and abs(end - math.pi / 2) < QUARTER_TOL
    assert math.isclose(cylinder, CYLINDER * math.tan(math.radians(angle_deg)) / RADIUS, rel_tol=1e-14)


def test_advance_is_smooth_in_the_clairaut_constant(vessel):
    c0 = RADIUS * math.sin(math.radians(30.0))
    cs = c0 + np.arange(-50, 51) * 1e-14
    values = np.array([half_advance(vessel, c) for c in cs])
    chord = np.polyval(np.polyfit(cs - c0, values, 1), cs - c0)
    assert np.max(np.abs(values - chord)) < JITTER_TOL

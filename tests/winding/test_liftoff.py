"""winder.winding.liftoff: the lift-off of a fiber over a concave stretch (docs/math/08 8.10),
against the sagitta of a chord over a circular dent."""

from __future__ import annotations

import numpy as np
import pytest

from winder.winding.liftoff import heights, pass_lift_off, upper_envelope

SAGITTA_REL = 0.01  # the envelope touches just outside the dent: within 1 % of kappa w^2 / 8
ROUND_OFF_MM = 1e-9


@pytest.mark.parametrize("kappa, width", [(0.01, 40.0), (0.0025, 12.0), (0.05, 3.0)])
def test_lift_off_over_a_dent_is_its_chords_sagitta(kappa, width):
    # a dent of normal curvature -kappa between stretches curving 1000 times more the other way: the
    # taut fiber spans the dent's chord
    l = np.linspace(-5.0 * width, 5.0 * width, 20001)
    k_n = np.where(np.abs(l) < 0.5 * width, -kappa, 1000.0 * kappa)
    y = heights(l, k_n)
    lift = upper_envelope(l, y) - y
    assert lift.max() == pytest.approx(kappa * width**2 / 8.0, rel=SAGITTA_REL)
    assert l[np.argmax(lift)] == pytest.approx(0.0, abs=width / 50.0)  # at the dent's middle


def test_no_lift_off_where_the_fiber_presses_everywhere():
    l = np.linspace(0.0, 500.0, 2001)
    y = heights(l, np.full(l.size, 1.0 / 50.0))  # a helix on a cylinder
    assert np.max(upper_envelope(l, y) - y) < ROUND_OFF_MM
    assert np.max(upper_envelope(l, np.zeros(l.size))) < ROUND_OFF_MM  # a flat face: all on one line


def test_pass_lift_off_on_a_polyline():
    # a straight pass of points 0.1 mm apart whose k_n dents by -0.02 /mm over 10 mm in a convex run
    m = 4001
    x = 0.1 * np.arange(m)
    points = np.column_stack([x, np.zeros(m), np.zeros(m)])
    l = x[1:-1]
    k_n = np.where(np.abs(l - 200.0) < 5.0, -0.02, 20.0)
    out = pass_lift_off(points, k_n)
    # the dent's edges fall between samples 0.1 mm apart: its width is known to 0.2 mm, w^2 to 4 %
    assert out.lift_mm == pytest.approx(0.02 * 10.0**2 / 8.0, rel=0.05)
    assert abs(l[out.at] - 200.0) <= 0.5

"""Where a geodesic reaches a station in closed form (winding.advance), against independent truths."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.conftest import ellipse_arc
from winder.errors import SolverError
from winder.paths.ode import trace
from winder.winding.advance import reach_theta
from roundoff import assert_roundoff

CLOSED_FORM = 1e-12  # rad: the quadrature against the integral's closed form
ARC_RUN = 1e-8  # mm: the arc run along the section against the unrolled straight line
TRACE_AGREE = 1e-9  # rad: against the geodesic ODE traced at rtol 1e-12


def _cone_turn(r0: float, r1: float, length: float, alpha0: float) -> float:
    """theta gained from radius r0 to r1 on a cone: Clairaut's integral in closed form."""
    k = (r1 - r0) / length
    c = r0 * math.sin(alpha0)
    return math.sqrt(1.0 + k * k) / k * (math.acos(c / r1) - math.acos(c / r0))


@pytest.mark.parametrize("alpha_deg", [10.0, 25.0, 35.0])  # 50 sin(35 deg) < 30: no turnaround
def test_cone_both_ways_against_clairauts_closed_form(cone, alpha_deg):
    # cone: r = 60 - 0.1 s over 300 mm; out from s = 100 to both ends
    th_b = reach_theta(cone, 100.0, np.array([0.3]), alpha_deg, 300.0)
    th_a = reach_theta(cone, 100.0, np.array([0.3]), alpha_deg + 180.0, 0.0)
    alpha = math.radians(alpha_deg)
    assert abs(th_b[0] - 0.3 - _cone_turn(50.0, 30.0, 200.0, alpha)) <= CLOSED_FORM
    # going back the same helix: theta falls as s falls, by the turn from r = 60 to r = 50
    assert abs(0.3 - th_a[0] - _cone_turn(60.0, 50.0, 100.0, math.asin(50.0 * math.sin(alpha) / 60.0))) \
        <= CLOSED_FORM


def test_cone_turns_around_before_the_small_end(cone):
    with pytest.raises(SolverError, match="turns around at t = "):
        reach_theta(cone, 0.0, np.array([0.0]), 60.0, 300.0)  # 60 sin 60 = 52 > 30


@pytest.mark.parametrize("heading", [35.0, -20.0, 215.0])
def test_elliptic_cylinder_runs_tan_alpha_times_the_length_along_the_section(elliptic_tube, heading):
    starts = np.array([0.0, 0.5 * np.pi, np.pi, 1.5 * np.pi, 0.7])
    forward = math.cos(math.radians(heading)) > 0.0
    s0, s1 = (50.0, 400.0) if forward else (350.0, 0.0)
    th = reach_theta(elliptic_tube, s0, starts, heading, s1)
    lean = math.radians(heading if forward else heading - 180.0)
    run = math.tan(lean) * abs(s1 - s0) * (1.0 if forward else -1.0)
    arcs = np.array([ellipse_arc(60.0, 35.0, a, b) for a, b in zip(starts, th)])
    assert np.max(np.abs(arcs - run)) <= ARC_RUN


def test_straight_tube_against_the_traced_geodesic(straight_tube):
    th = reach_theta(straight_tube, 20.0, np.array([1.0]), 55.0, 280.0)
    assert abs(th[0] - 1.0 - math.tan(math.radians(55.0)) * 260.0 / 40.0) <= CLOSED_FORM
    tr = trace(straight_tube, (20.0, 1.0), 55.0, 260.0 / math.cos(math.radians(55.0)), rtol=1e-12, atol=1e-12,
               stop_at_ends=False)
    assert abs(tr.sol(np.array([tr.length]))[1][0] - th[0]) <= TRACE_AGREE


def test_a_bent_axis_is_left_to_the_tracer(quarter_bend):
    assert reach_theta(quarter_bend, 0.0, np.array([0.0]), 30.0, quarter_bend.length) is None


def test_gauss_rule_is_leggauss():
    from winder.winding.clairaut import GAUSS_W, GAUSS_X  # noqa: PLC0415

    x, w = np.polynomial.legendre.leggauss(GAUSS_X.size)
    assert_roundoff(GAUSS_X, x)
    assert_roundoff(GAUSS_W, w)

"""The friction-held pieces of planning (bend_paths, dome_paths, slip) against independent truths.

Truths: the torus closed forms of docs/math/07-friction.md (constant angle, its lambda), the cylinder's
sin(alpha(z)) closed form, the general friction ODE on the 3D surface (winder.paths.friction) for the
surface-of-revolution legs, and curvatures measured from the points with the exact normal.
"""

from __future__ import annotations

from dataclasses import replace

import math

import numpy as np
import pytest

from winder.paths.bend_paths import arc_angle, design, line_slip, pass_curves, region_pieces
from winder.config.axes import ArcAxis, PathAxis
from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.config.vessel import Dome, DomeType, VesselProfile
from winder.geometry.curvature import curve_curvatures, torus_constant_angle_slip
from winder.paths.dome_paths import close_leg, dome_meridian, solve_slip, trace_leg
from winder.errors import SolverError
from winder.paths.friction import trace_friction
from winder.paths.headings import heading_of_velocity
from winder.geometry.build import build_surface

A, RB = 40.0, 150.0
ANGLE_TOL = 1e-9  # rad: constant-angle arcs, closed-form transitions
SLIP_TOL = 1e-7  # measured lambda (exact derivatives) vs the closed forms
PERIOD_TOL = 1e-9  # rad: an arc of m periods returns every entry angle + 2 pi m
RADIUS_TOL = 1e-5  # mm: dome legs, profile ODE vs the general 3D friction ODE


def elbow(leg=100.0):
    axis = PathAxis((LineAxis(leg), ArcAxis(RB, 90.0), LineAxis(leg)))
    return build_surface(MandrelConfig(axis, ConstantProfile(A), CircleSection()))


def measured(surf, t, th, d1, d2):
    k_n, k_g = curve_curvatures(surf, t, th, np.ones_like(t), d1, np.zeros_like(t), d2)
    alpha, _ = heading_of_velocity(surf, t, th, np.ones_like(t), d1)
    return k_n, k_g, alpha


def test_elbow_passes_constant_angle_in_the_arc_and_whole_periods():
    surf = elbow()
    pieces, worst = design(region_pieces(surf, 0.0, surf.axial_length), math.radians(45.0), A, 0.2)
    arc = pieces[1]
    assert arc.rounds == 2 and arc.alpha0 == pytest.approx(arc_angle(2, A / RB, A, RB * math.pi / 2))
    starts = np.linspace(0.0, 2 * np.pi, 13)[:-1]
    t, th, d1, d2, adv = pass_curves(pieces, A, starts, 400, True)
    k_n, k_g, alpha = (np.stack(x) for x in zip(*(measured(surf, t, th[j], d1[j], d2[j]) for j in range(12))))
    inside = (t > 100.0 + 1e-6) & (t < 100.0 + RB * math.pi / 2 - 1e-6)
    assert np.max(np.abs(alpha[:, inside] - arc.alpha0)) < ANGLE_TOL
    # Every pass advances alike (the arc holds whole periods): the slots stay evenly spaced.
    assert np.max(np.abs(th[:, -1] - th[:, 0] - adv)) < PERIOD_TOL
    phi = th[:, inside] - arc.theta_in
    closed = torus_constant_angle_slip(arc.alpha0, phi, RB, A)
    assert np.max(np.abs(np.abs(k_g[:, inside] / k_n[:, inside]) - np.abs(closed))) < SLIP_TOL
    # At a joint itself the curvature jumps (one side's surface, the other's curve): off the joints.
    joint = np.isclose(t, 100.0) | np.isclose(t, 100.0 + RB * math.pi / 2)
    assert np.max(np.abs(k_g / k_n)[:, ~joint]) <= worst + SLIP_TOL and worst <= 0.2
    assert k_n.min() > 0.0


def test_elbow_legs_follow_the_cylinder_closed_form():
    surf = elbow()
    a0 = math.radians(45.0)
    pieces, _ = design(region_pieces(surf, 0.0, surf.axial_length), a0, A, 0.2)
    lam = A * (1 / math.sin(a0) - 1 / math.sin(pieces[1].alpha0)) / 100.0
    assert line_slip(a0, pieces[1].alpha0, A, 100.0) == pytest.approx(lam)
    t, th, d1, d2, _ = pass_curves(pieces, A, np.array([0.3]), 400, True)
    k_n, k_g, alpha = measured(surf, t, th[0], d1[0], d2[0])
    leg = t < 100.0 - 1e-9
    exact = np.sin(a0) / (1.0 - lam * t[leg] * np.sin(a0) / A)
    assert np.max(np.abs(np.sin(alpha[leg]) - exact)) < ANGLE_TOL
    assert np.max(np.abs(k_g[leg] / k_n[leg] - lam)) < SLIP_TOL


def test_return_passes_mirror_the_forward_ones():
    surf = elbow()
    pieces, _ = design(region_pieces(surf, 0.0, surf.axial_length), math.radians(50.0), A, 0.2)
    t, th, d1, _, adv = pass_curves(pieces, A, np.array([0.0, 1.0]), 300, False)
    assert t[0] == pytest.approx(surf.axial_length) and t[-1] == pytest.approx(0.0)
    assert np.all(np.diff(th, axis=1) > 0.0) and np.all(d1 < 0.0)
    assert np.max(np.abs(th[:, -1] - th[:, 0] - adv)) < PERIOD_TOL


def test_design_refuses_what_friction_cannot_hold():
    surf = elbow(leg=20.0)  # a short leg: 45 deg cannot turn to a whole-period angle within 0.05
    with pytest.raises(SolverError, match="least mu"):
        design(region_pieces(surf, 0.0, surf.axial_length), math.radians(45.0), A, 0.05)


# -- domes -------------------------------------------------------------------------------------------------
def vessel():
    return build_surface(MandrelConfig(None, VesselProfile(100.0, 200.0, Dome(DomeType.HEMISPHERE, 25.0),
                                                           Dome(DomeType.HEMISPHERE, 30.0)), CircleSection()))


def test_dome_leg_agrees_with_the_general_friction_ode():
    surf = vessel()
    prof = surf.profile
    e2 = prof.equator_s[1]
    leg = trace_leg(dome_meridian(prof, True), e2, math.radians(12.0), lambda l: 0.15)
    tr = trace_friction(surf, (e2, 0.0), 12.0, 0.15, 2000.0, stop_at_turnaround=True, rtol=1e-11, atol=1e-11)
    assert leg.turned and tr.event == "turnaround"
    assert leg.radius == pytest.approx(tr.turnaround_radius, abs=RADIUS_TOL)
    assert leg.advance == pytest.approx(tr.theta[-1], abs=1e-6)


@pytest.mark.parametrize("dome", [0, 1])
def test_turnaround_radius_solved_and_pattern_term(dome):
    surf = vessel()
    prof = surf.profile
    s_eq = prof.equator_s[dome]
    heading = math.radians(12.0) if dome == 1 else math.pi - math.radians(12.0)
    meridian = dome_meridian(prof, dome == 1)
    lam, leg = solve_slip(meridian, s_eq, heading, 35.0)
    assert leg.radius == pytest.approx(35.0, abs=1e-6) and abs(lam) < 0.2
    assert math.copysign(1.0, lam) == (1.0 if dome == 1 else -1.0)  # the sign follows the direction
    for start in (None, leg):  # the solved leg handed over, or traced again
        lam0, lam1, closed = close_leg(meridian, s_eq, heading, 35.0, lam, leg.length, leg.advance + 0.01, start)
        assert closed.radius == pytest.approx(35.0, abs=1e-6)
        assert closed.advance == pytest.approx(leg.advance + 0.01, abs=1e-7)


def test_turnaround_solved_on_a_grown_dome_within_the_radius_tolerance():
    """A laminate with a pile-up near the turnaround (as a helical layer leaves): the traced
    turnaround is smooth in lambda (its step-to-step noise below the radius tolerance: 2.6e-7 to
    5.0e-7 mm, from scipy 1.15.0's DOP853 to later releases'), so the solve lands within that
    tolerance (asserted first, on the solve itself)."""
    from winder.geometry.offset import grow_surface  # noqa: PLC0415
    from winder.paths.dome_paths import RADIUS_TOL as SOLVE_TOL  # noqa: PLC0415

    surf = vessel()
    prof = surf.profile
    s = np.linspace(0.0, surf.length, 800)
    r = prof.evaluate(s).r
    grown = grow_surface(surf, s, 0.5 + 3.0 * np.exp(-(((r - 45.0) / 12.0) ** 2)))
    gp = grown.profile
    meridian = dome_meridian(gp, True)
    heading = math.radians(14.0)
    lam, leg = solve_slip(meridian, gp.equator_s[1], heading, 38.0)
    assert leg.turned and abs(leg.radius - 38.0) < SOLVE_TOL and 0.0 < abs(lam) < 0.3
    radii = [trace_leg(meridian, gp.equator_s[1], heading, lambda l, x=lam + k * 1e-9: x).radius for k in range(6)]
    slope = (trace_leg(meridian, gp.equator_s[1], heading, lambda l: lam + 1e-6).radius
             - trace_leg(meridian, gp.equator_s[1], heading, lambda l: lam - 1e-6).radius) / 2e-6
    noise = np.diff(radii) - slope * 1e-9
    assert np.max(np.abs(noise)) < SOLVE_TOL


# -- vessel layers through the planner ---------------------------------------------------------------------
def vessel_job(opening_a: float, opening_b: float, layer: dict):
    from winder.config.job import parse_config  # noqa: PLC0415

    mandrel = {"profile": {"type": "vessel", "radius": 100, "cylinder_length": 200,
                           "dome": {"type": "hemisphere", "polar_opening": opening_a},
                           "end_dome": {"type": "hemisphere", "polar_opening": opening_b}}}
    return parse_config({"name": "v", "mandrel": mandrel,
                         "winding": {"band_width": 8, "friction": 0.2, "layers": [layer]}}, "v.yaml")


def test_vessel_slip_number_turns_where_the_3d_ode_does():
    from winder.winding.plan import plan  # noqa: PLC0415

    p = plan(vessel_job(20.0, 20.0, {"type": "helical", "angle": 12, "slip": 0.1}))
    layer = p.layers[0]
    e2 = p.surface.profile.equator_s[1]
    tr = trace_friction(p.surface, (e2, 0.0), 12.0, 0.1, 2000.0, stop_at_turnaround=True, rtol=1e-11, atol=1e-11)
    forward = layer.passes[0]
    r_end = float(np.hypot(*forward.points[-1, :2]))
    assert r_end == pytest.approx(tr.turnaround_radius, abs=1e-4)
    assert layer.coverage.covered_fraction >= 0.999 and layer.angle_deg == pytest.approx(12.0)
    assert layer.min_normal_curvature > 0.0 and layer.max_slip <= 0.2


def test_vessel_auto_turns_each_dome_just_outside_its_own_opening():
    from winder.winding.plan import plan  # noqa: PLC0415

    layer = plan(vessel_job(25.0, 30.0, {"type": "helical", "angle": 12, "slip": "auto"})).layers[0]
    first = [float(np.hypot(*p.points[k, :2])) for p in layer.passes for k in (0, -1) if p.t[k] < 100.0]
    end = [float(np.hypot(*p.points[k, :2])) for p in layer.passes for k in (0, -1) if p.t[k] > 100.0]
    assert np.allclose(first, 25.0 + 4.0, atol=1e-4) and np.allclose(end, 30.0 + 4.0, atol=1e-4)
    assert layer.turnaround_radii == pytest.approx((29.0, 34.0), abs=1e-4)
    assert layer.max_slip <= 0.2


def test_vessel_turnaround_radius_per_dome():
    from winder.winding.plan import plan  # noqa: PLC0415

    cfg = {"type": "helical", "angle": 14, "turnaround_radius": {"start": 33, "end": 36}}
    layer = plan(vessel_job(25.0, 30.0, cfg)).layers[0]
    assert layer.turnaround_radii == pytest.approx((33.0, 36.0), abs=1e-4)
    first = {round(float(np.hypot(*p.points[k, :2])), 3) for p in layer.passes for k in (0, -1) if p.t[k] < 100.0}
    assert first == {33.0}


def test_vessel_radius_beyond_the_friction_refused_with_the_least_mu():
    """The least friction named is the least that plans (to 0.01): it plans, 0.01 less does not."""
    from dataclasses import replace  # noqa: PLC0415

    from winder.winding.plan import plan  # noqa: PLC0415

    job = vessel_job(25.0, 30.0, {"type": "helical", "angle": 12, "turnaround_radius": 42})
    with pytest.raises(SolverError, match=r"layer 1 \(helical 12 deg\): on the first dome: .*needs \|k_g / k_n\| "
                                          r"= 0\.234.*what plans it: winding\.friction: 0\.24") as info:
        plan(job)
    least = float(info.value.message.rsplit(" ", 1)[1])
    assert plan(replace(job, winding=replace(job.winding, friction=least))).layers[0].max_slip <= least
    with pytest.raises(SolverError):
        plan(replace(job, winding=replace(job.winding, friction=least - 0.01)))


def open_job(axis: dict, layer: dict, **winding):
    from winder.config.job import parse_config  # noqa: PLC0415

    mandrel = {"axis": axis, "profile": {"type": "constant", "radius": A}}
    return parse_config({"name": "b", "mandrel": mandrel,
                         "winding": {"band_width": 8, "layers": [layer], **winding}}, "b.yaml")


def test_s_bend_even_and_held():
    """Two bends turning opposite ways with a straight piece between: each at its whole-period angle."""
    from winder.winding.plan import plan  # noqa: PLC0415

    axis = {"type": "path", "segments": [{"line": 80}, {"arc": {"radius": 200, "angle": 60, "toward": 0}},
                                         {"line": 120}, {"arc": {"radius": 200, "angle": 60, "toward": 180}},
                                         {"line": 80}]}
    layer = plan(open_job(axis, {"type": "helical", "angle": 50, "slip": "auto"})).layers[0]
    assert layer.coverage.covered_fraction >= 0.999 and layer.coverage.max_gap_mm <= 0.02 * 8
    assert layer.max_slip <= 0.2 and layer.min_normal_curvature > 0.0
    assert layer.alpha_min_deg == pytest.approx(50.0, abs=0.5)


def test_bend_at_the_end_of_the_region_reports_its_angle():
    from winder.winding.plan import plan  # noqa: PLC0415

    layer = plan(open_job({"type": "arc", "radius": RB, "angle": 90},
                          {"type": "helical", "angle": 50, "slip": "auto"})).layers[0]
    alpha_m = math.degrees(arc_angle(2, A / RB, A, RB * math.pi / 2))
    assert layer.angle_deg == pytest.approx(alpha_m) and layer.requested_angle_deg == 50.0
    assert layer.alpha_min_deg == pytest.approx(alpha_m, abs=1e-6)
    assert any("the angle there is the bend's" in n for n in layer.notes)


def test_circuits_above_the_closed_form_are_explained():
    """Through a bend the bands part on its outside, so the planner winds more circuits than the straight
    tube's N_c = ceil(2 pi a cos(alpha) / B) (docs/math/05-winding.md); the notes say so with both counts."""
    from winder.winding.plan import plan  # noqa: PLC0415

    axis = {"type": "path", "segments": [{"line": 150}, {"arc": {"radius": 300, "angle": 90}}, {"line": 150}]}
    layer = plan(open_job(axis, {"type": "helical", "angle": 55, "slip": "auto"}, friction=0.25)).layers[0]
    closed = math.ceil(2 * math.pi * A * math.cos(math.radians(55)) / 8)  # 19
    assert layer.circuits > closed
    assert any(n.startswith(f"{layer.circuits} circuits instead of {closed}:") for n in layer.notes), layer.notes

"""winder.winding.turnaround: the fiber past the winding region of an open mandrel, against docs/math/07-friction.md's
closed form on a cylinder, sin(alpha(z)) = sin(alpha0) / (1 - lambda z sin(alpha0) / R), and the plans
that use it: continuous fiber and directions from pass to pass, friction within mu."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import surface_of
from winder.config.job import load_config
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.winding.plan import plan as plan_job
from winder.winding.results import PassKind
from winder.winding.slip import measure
from winder.winding.turnaround import (SWING_MIN_DEG, TURN_SLIP_SHARE, heading_deg, leg_way, swing_headings,
                                       trace_leg)

R, MU = 50.0, 0.2
CLOSED_FORM_TOL = 1e-8  # sin(alpha) along a traced leg against the closed form
JOINT_TOL = 1e-9  # mm and rad: where one pass ends the next begins, in the same direction
JOINT_DIRECTION_TOL = 1e-6  # unit tangents on either side of a joint
SAMPLES = Path(__file__).resolve().parents[2] / "samples"


@pytest.fixture(scope="module")
def pipe():
    return surface_of(LineAxis(600.0), ConstantProfile(R))


def test_leg_on_a_cylinder_follows_the_closed_form(pipe):
    alpha0 = 55.0
    leg = trace_leg(pipe, 400.0, alpha0, 1.0, MU)
    lam = TURN_SLIP_SHARE * MU
    z = leg.s - 400.0
    s0 = math.sin(math.radians(alpha0))
    expected = s0 / (1.0 - lam * z * s0 / R)
    _, _, d = leg_way(pipe, leg, 0.0, back=False)
    got = np.sin(np.radians(heading_deg(pipe, leg.s, leg.dtheta, d)))
    assert np.max(np.abs(got - expected)) < CLOSED_FORM_TOL
    # It reaches the parallel where the closed form says: z = R (1 / sin(alpha0) - 1) / lambda.
    assert not leg.held_by_end and leg.apex_heading_deg == 90.0
    assert z[-1] == pytest.approx(R * (1.0 / s0 - 1.0) / lam, rel=1e-9)


def test_short_end_holds_the_fiber_at_the_closed_form_angle(pipe):
    leg = trace_leg(pipe, 580.0, 55.0, 1.0, MU)  # 20 mm of mandrel left: too short to turn
    s0 = math.sin(math.radians(55.0))
    expected = math.degrees(math.asin(s0 / (1.0 - TURN_SLIP_SHARE * MU * 20.0 * s0 / R)))
    assert leg.held_by_end and leg.s[-1] == 600.0
    assert leg.apex_heading_deg == pytest.approx(expected, abs=1e-7)
    # No room at all: no way in, the end holds the fiber at the pass's own angle.
    flush = trace_leg(pipe, 600.0, 55.0, 1.0, MU)
    assert flush.s.size == 0 and flush.held_by_end and flush.turn == 0.0


def test_way_out_mirrors_the_way_in(pipe):
    leg = trace_leg(pipe, 400.0, 180.0 - 40.0, -1.0, MU)  # a return pass arriving toward the start end
    s_in, th_in, d_in = leg_way(pipe, leg, 1.0, back=False)
    s_out, th_out, d_out = leg_way(pipe, leg, 1.0 + 0.5 * leg.turn, back=True)
    assert s_in[-1] == s_out[0] and th_in[-1] == pytest.approx(th_out[0], abs=1e-14)
    assert not leg.held_by_end and s_out[-1] == pytest.approx(400.0) and th_out[-1] == pytest.approx(1.0 + leg.turn, abs=1e-14)
    h_out = heading_deg(pipe, s_out, th_out, d_out)
    assert h_out[-1] == pytest.approx(40.0, abs=1e-9)  # leaves toward +t at the pass angle
    assert np.allclose(d_in[-1], d_out[0], atol=1e-12)  # along the parallel at the apex


def test_swing_passes_through_the_hoop():
    f = np.linspace(0.0, 1.0, 11)
    h = swing_headings(f, 60.0, 120.0)
    assert h[0] == 60.0 and h[5] == 90.0 and h[-1] == 120.0 and np.all(np.diff(h) > 0)


@pytest.mark.parametrize("name", ["pipe", "cone", "elliptic_tube", "vessel_hemi"])
def test_plans_are_continuous_and_held(name):
    """Every pass of every layer starts where the one before ended, leaving in the direction it
    arrived (the eye never jumps); turnarounds press and hold within the friction coefficient."""
    job = load_config(SAMPLES / f"{name}.yaml")
    plan = plan_job(job)
    for layer in plan.layers:
        passes = [p for p in layer.passes if len(p.points)]
        for a, b in zip(passes, passes[1:]):
            assert np.linalg.norm(a.points[-1] - b.points[0]) < JOINT_TOL
            assert np.linalg.norm(a.direction[-1] - b.direction[0]) < 1e-6
        turns = [p for p in passes if p.kind is PassKind.TURNAROUND]
        if turns:
            held = measure(plan.surface_of(layer.index), turns)
            assert held.max_slip <= TURN_SLIP_SHARE * job.winding.friction + 1e-3
            assert held.min_normal_curvature > 0.0
        dwells = [p for p in passes if p.kind is PassKind.DWELL]
        # A dwell where the end holds the fiber turns at least SWING_MIN_DEG of the perimeter (on a
        # circle: of the mandrel's turn), so the eye never swings round with the mandrel still.
        least = SWING_MIN_DEG - 1e-9 if plan.surface.section.is_circle else 0.5 * SWING_MIN_DEG
        for d in dwells:
            turn = math.degrees(d.theta[-1] - d.theta[0])
            swings = np.ptp(d.alpha_deg) > 1e-6 or abs(abs(d.alpha_deg[0]) - 90.0) > 1e-6
            assert turn >= (least if swings else 0.0)


def test_hoop_on_a_cone_reverses_without_a_kink():
    """A hoop on a cone holds its angle on the reference (largest) section only: toward the small end
    the constant pitch runs flatter. Each way in leaves with the hoop's own last direction, so the
    fiber does not kink and the eye does not swing back where the carriage reverses."""
    from winder.config.job import parse_config  # noqa: PLC0415

    job = parse_config({"name": "cone", "mandrel": {"axis": {"type": "line", "length": 600},
                                                    "profile": {"type": "cone", "start_radius": 60,
                                                                "end_radius": 40}},
                        "winding": {"band_width": 12, "friction": 0.3, "region": {"start": 100, "end": 500},
                                    "layers": [{"type": "hoop", "passes": 3}]}}, "cone.yaml")
    passes = [p for p in plan_job(job).layers[0].passes if len(p.points)]
    assert any(p.kind is PassKind.TURNAROUND for p in passes)
    for a, b in zip(passes, passes[1:]):
        assert np.linalg.norm(a.points[-1] - b.points[0]) < JOINT_TOL
        assert np.linalg.norm(a.direction[-1] - b.direction[0]) < JOINT_DIRECTION_TOL


def test_pipe_turns_on_its_20_mm_ends():
    """samples/pipe.yaml: the region stops 20 mm short of each end; the fiber runs on at lambda = 0.18
    to the mandrel's end (60.516 deg by the closed form) and the end holds it there."""
    plan = plan_job(load_config(SAMPLES / "pipe.yaml"))
    layer = plan.layers[0]
    kinds = [p.kind for p in layer.passes[:8]]
    assert kinds == [PassKind.FORWARD, PassKind.TURNAROUND, PassKind.DWELL, PassKind.TURNAROUND,
                     PassKind.RETURN, PassKind.TURNAROUND, PassKind.DWELL, PassKind.TURNAROUND]
    way_in = layer.passes[1]
    s0 = math.sin(math.radians(55.0))
    expected = math.degrees(math.asin(s0 / (1.0 - TURN_SLIP_SHARE * 0.2 * 20.0 * s0 / R)))
    assert way_in.t[-1] == pytest.approx(500.0) and abs(way_in.alpha_deg[-1]) == pytest.approx(expected, abs=1e-6)
    assert any("holds the fiber at 60.516 deg" in n for n in layer.notes)


def test_room_enough_turns_round_within_friction():
    """A pipe wound 80 mm short of each end: at 55 deg on R 50 friction (lambda = 0.18) turns the
    fiber round in R (1 / sin(55) - 1) / 0.18 = 61.3 mm, so no end holds it: the ways in reach the
    parallel, any dwell (what closes the pattern) lies along it with the carriage still."""
    from winder.config.job import parse_config  # noqa: PLC0415

    job = parse_config({"name": "long", "mandrel": {"axis": {"type": "line", "length": 660},
                                                    "profile": {"type": "constant", "radius": R}},
                        "winding": {"band_width": 10, "points": 30, "region": {"start": 80, "end": 580},
                                    "layers": [{"type": "helical", "angle": 55}]},
                        "machine": {"eye": {"clearance": 20}}}, "long.yaml")
    layer = plan_job(job).layers[0]
    ways = [p for p in layer.passes if p.kind is PassKind.TURNAROUND]
    assert len(ways) == 4 * layer.circuits
    span = R * (1.0 / math.sin(math.radians(55.0)) - 1.0) / (TURN_SLIP_SHARE * 0.2)
    for p in ways[:4]:
        apex = p.t[-1] if abs(p.alpha_deg[-1]) > abs(p.alpha_deg[0]) else p.t[0]
        assert abs(apex - (580.0 + span if apex > 330 else 80.0 - span)) < 1e-6
    for d in (p for p in layer.passes if p.kind is PassKind.DWELL):
        assert np.allclose(d.alpha_deg, 90.0) and np.ptp(d.t) == 0.0  # on the apex parallel
    assert all("friction turns the fiber round 61.3" in n for n in layer.notes[:2])


def test_a_leg_over_a_tight_edge_is_sampled_finely():
    """Past the region a laminate's edge is a few mm wide: the leg's points come at least LEG_CURVE_STEPS
    a radius of the meridian's curvature there (2 mm steps read a slip of 0.31 off a leg traced at 0.18:
    a generated cone of eight layers, refused), and LEG_STEP_MM apart on a plain cone."""
    from winder.config.job import parse_config  # noqa: PLC0415
    from winder.geometry.build import build_surface  # noqa: PLC0415
    from winder.winding import turnaround  # noqa: PLC0415

    def leg_of(points):
        job = parse_config({"name": "e", "mandrel": {"axis": {"type": "line", "length": points[-1][0]},
                                                     "profile": {"type": "table", "points": points}},
                            "winding": {"band_width": 10, "layers": [{"type": "hoop"}]}}, "e.yaml")
        surface = build_surface(job.mandrel, "e.yaml", "e")
        return surface, turnaround.trace_leg(surface, 600.0, 40.0, 1.0, 0.2)

    surface, leg = leg_of([[0, 100], [300, 100], [600, 100], [640, 100], [700, 100]])
    assert math.isclose(float(np.max(np.diff(leg.s))), turnaround.LEG_STEP_MM * math.cos(math.radians(40.0)),
                        rel_tol=0.05)
    surface, leg = leg_of([[0, 100], [600, 100], [610, 100], [613, 101.5], [616, 103], [626, 103], [700, 103]])
    ev = surface.profile.evaluate(leg.s)
    kappa = float(np.max(np.abs(ev[5]) / (1.0 + ev[4] ** 2) ** 1.5))
    assert 1.0 / (turnaround.LEG_CURVE_STEPS * kappa) < turnaround.LEG_STEP_MM  # the edge under the leg is tight
    # the axial step is at most the step along the fiber
    assert float(np.max(np.diff(leg.s))) <= 1.0 / (turnaround.LEG_CURVE_STEPS * kappa) * (1.0 + 1e-9)

"""The winding planner against closed forms (cylinder), Clairaut (vessels) and coverage."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.errors import ConfigError, SolverError
from winder.geometry.sections import arc_map
from winder.winding.results import PassKind
from winder.winding.plan import plan
from roundoff import assert_roundoff

CLAIRAUT_REL = 1e-6
COVERED = 0.999
GAP_OF_BAND = 0.02


def job(mandrel: dict, winding: dict, **extra) -> object:
    return parse_config({"name": "t", "mandrel": mandrel, "winding": winding, **extra}, "t.yaml")


PIPE = {"axis": {"type": "line", "length": 500}, "profile": {"type": "constant", "radius": 50}}
VESSEL = {"profile": {"type": "vessel", "radius": 100, "cylinder_length": 300,
                      "dome": {"type": "hemisphere", "polar_opening": 30}}}


def assert_even(layer, band):
    assert layer.coverage.covered_fraction >= COVERED
    assert layer.coverage.max_gap_mm <= GAP_OF_BAND * band


@pytest.fixture(scope="module")
def pipe_plan():
    return plan(job(PIPE, {"band_width": 10, "region": {"start": 20, "end": 480}, "points": 100,
                           "dwell": {"start": 10, "end": 10},
                           "layers": [{"type": "helical", "angle": 55}, {"type": "hoop", "passes": 2}]}))


def test_cylinder_closed_forms(pipe_plan):
    layer = pipe_plan.layers[0]
    alpha, radius, length = math.radians(55.0), 50.0, 460.0
    assert layer.circuits == math.ceil(2 * math.pi * radius * math.cos(alpha) / 10.0) == 19
    forward = [p for p in layer.passes if p.kind is PassKind.FORWARD]
    returns = [p for p in layer.passes if p.kind is PassKind.RETURN]
    assert len(forward) == len(returns) == layer.circuits
    for p in forward + returns:
        # The per-pass advance of a helix at alpha: L tan(alpha) / R.
        assert p.theta[-1] - p.theta[0] == pytest.approx(length * math.tan(alpha) / radius, rel=1e-9)
        assert p.length == pytest.approx(length / math.cos(alpha), rel=1e-9)
    assert np.allclose(np.concatenate([p.alpha_deg for p in forward]), 55.0, atol=1e-6)
    assert np.allclose(np.concatenate([p.alpha_deg for p in returns]), -55.0, atol=1e-6)
    # Every dwell respects the configured minimum.
    assert layer.dwell_start_deg >= 10.0 and layer.dwell_end_deg >= 10.0


def test_cylinder_pattern_closes_and_fills_every_slot(pipe_plan):
    layer = pipe_plan.layers[0]
    n = layer.circuits
    theta0 = layer.passes[0].theta[0]
    # After N_c circuits the start angle returns to itself (mod 360).
    turns = (layer.passes[-1].theta[-1] - theta0) / (2 * math.pi)
    assert abs(turns - round(turns)) < 1e-9
    starts = np.array([p.theta[0] for p in layer.passes if p.kind is PassKind.FORWARD]) - theta0
    slots = np.mod(starts, 2 * math.pi) / (2 * math.pi / n)
    assert np.allclose(slots, np.round(slots), atol=1e-9)
    assert sorted(np.round(slots).astype(int) % n) == list(range(n))
    assert math.gcd(layer.pattern, n) == 1


def test_cylinder_coverage_even(pipe_plan):
    assert_even(pipe_plan.layers[0], 10.0)
    # Bands of one direction overlap by (B / cos(alpha) - P / N_c) where neighbours meet.
    layer = pipe_plan.layers[0]
    overlap = 10.0 / math.cos(math.radians(55)) - 2 * math.pi * 50 / layer.circuits
    assert layer.coverage.max_overlap_mm == pytest.approx(overlap, abs=1e-3)


def test_hoop_on_cylinder(pipe_plan):
    hoop = pipe_plan.layers[1]
    perimeter = 2 * math.pi * 50
    assert hoop.angle_deg == pytest.approx(math.degrees(math.acos(10 / perimeter)))
    p = hoop.passes[0]
    turns = (p.theta[-1] - p.theta[0]) / (2 * math.pi)
    pitch = (p.t[-1] - p.t[0]) / turns
    assert pitch == pytest.approx(10 / math.sin(math.radians(hoop.angle_deg)), rel=1e-9)
    assert_even(hoop, 10.0)
    assert [q.t[0] for q in hoop.passes if q.kind is PassKind.HOOP] == [20.0, 480.0]


def test_totals(pipe_plan):
    total = sum(p.length for layer in pipe_plan.layers for p in layer.passes)
    assert pipe_plan.total_fiber_length_mm == pytest.approx(total)
    assert pipe_plan.total_time_s == pytest.approx(total / 3000.0 * 60.0)


@pytest.fixture(scope="module")
def vessel_plan():
    return plan(job(VESSEL, {"band_width": 10, "points": 200, "layers": [{"type": "helical", "angle": 22}]}))


def test_vessel_clairaut_along_every_pass(vessel_plan):
    layer = vessel_plan.layers[0]
    c = layer.turnaround_radius
    surface = vessel_plan.surface
    assert c > 30.0 + 5.0  # clears the polar opening plus half a band
    for p in layer.passes:
        r = surface.radius(p.s, p.theta)
        constant = r * np.abs(np.sin(np.radians(p.alpha_deg)))
        assert np.max(np.abs(constant / c - 1.0)) < CLAIRAUT_REL
        # The turnarounds: on the parallel r = c and tangent to it.
        assert r[0] == pytest.approx(c, rel=1e-12) and r[-1] == pytest.approx(c, rel=1e-12)
        assert abs(p.alpha_deg[0]) > 89.99 and abs(p.alpha_deg[-1]) > 89.99


def test_vessel_angle_moved_to_close_pattern(vessel_plan):
    layer = vessel_plan.layers[0]
    assert layer.angle_deg == pytest.approx(math.degrees(math.asin(layer.turnaround_radius / 100.0)))
    assert abs(layer.angle_change_deg) < 1.0
    assert any("angle moved" in note for note in layer.notes)
    turns = (layer.passes[-1].theta[-1] - layer.passes[0].theta[0]) / (2 * math.pi)
    assert abs(turns - round(turns)) < 1e-9
    assert_even(layer, 10.0)


def test_vessel_angle_below_polar_opening_refused():
    with pytest.raises(SolverError, match=r"layer 1 \(helical 15 deg\)\.angle: 15 deg turns around at r = 25.882 mm, "
                                          r"inside the polar opening"):
        plan(job(VESSEL, {"band_width": 10, "layers": [{"type": "helical", "angle": 15}]}))


def test_cone_coverage():
    p = plan(job({"axis": {"type": "line", "length": 300}, "profile": {"type": "cone", "start_radius": 60,
                                                                         "end_radius": 40}},
                 {"band_width": 10, "points": 80, "layers": [{"type": "helical", "angle": 30}]}))
    assert_even(p.layers[0], 10.0)


def test_elliptic_tube_each_circuit_solved_and_even():
    p = plan(job({"axis": {"type": "line", "length": 300}, "section": {"type": "ellipse", "a": 60, "b": 35}},
                 {"band_width": 10, "points": 80, "layers": [{"type": "helical", "angle": 45}]}))
    layer = p.layers[0]
    assert_even(layer, 10.0)
    forward = [q for q in layer.passes if q.kind is PassKind.FORWARD]
    # Not rotated copies: the shape theta(t) - theta(0) depends on where the pass starts.
    shapes = np.array([q.theta - q.theta[0] for q in forward])
    assert np.max(np.ptp(shapes, axis=0)) > 1e-2


def test_gentle_elbow_even_with_more_circuits():
    p = plan(job({"axis": {"type": "path", "segments": [{"line": 50}, {"arc": {"radius": 800, "angle": 90}},
                                                         {"line": 50}]},
                  "profile": {"type": "constant", "radius": 40}},
                 {"band_width": 10, "points": 100, "layers": [{"type": "helical", "angle": 55}]}))
    layer = p.layers[0]
    assert_even(layer, 10.0)
    assert layer.circuits >= math.ceil(2 * math.pi * 40 * math.cos(math.radians(55)) / 10)


ELBOW_AXIS = {"type": "path", "segments": [{"line": 100}, {"arc": {"radius": 150, "angle": 90}}, {"line": 100}]}


def test_tight_elbow_geodesics_refused_friction_covers():
    """Geodesics bunch toward the inside of a tight bend and bridge there: slip 0 is refused (the 30 deg
    one from the config alone, docs/math/07-friction.md's 31.1 deg), slip auto covers evenly within the friction."""
    tube = {"axis": ELBOW_AXIS, "profile": {"type": "constant", "radius": 40}}
    with pytest.raises(ConfigError, match="below 31.1 deg on this bend no friction holds it"):
        job(tube, {"band_width": 10, "points": 60, "layers": [{"type": "helical", "angle": 30}]})
    with pytest.raises(SolverError, match="bridges"):
        plan(job(tube, {"band_width": 10, "points": 16, "layers": [{"type": "helical", "angle": 45}]}))
    layer = plan(job(tube, {"band_width": 10, "layers": [{"type": "helical", "angle": 45, "slip": "auto"}]})).layers[0]
    assert layer.coverage.covered_fraction >= COVERED and 0.0 < layer.max_slip <= 0.2
    assert layer.min_normal_curvature > 0.0


def test_hoop_on_cone_slips():
    with pytest.raises(SolverError, match="a hoop layer would slip"):
        plan(job({"axis": {"type": "line", "length": 300}, "profile": {"type": "cone", "start_radius": 60,
                                                                         "end_radius": 30}},
                 {"band_width": 10, "friction": 0.05, "layers": [{"type": "hoop"}]}))


def test_hoop_on_a_cone_closes_its_band_across_the_slant():
    """A cone 160 -> 85 over 500 mm (8.5 deg): consecutive turns lie along the slant, sqrt(1 + r'^2)
    times their axial pitch apart, and the band closes where that spacing across the fiber, dm sin(alpha)
    with tan(alpha) = 2 pi r / dm, is at most the band: at the wide end (largest r) it is the band
    itself. Read from the planned pass: the axial pitch is its t advance over one turn of theta."""
    band, r_a, r_b, length = 10.0, 160.0, 85.0, 500.0
    hoop = plan(job({"axis": {"type": "line", "length": length},
                     "profile": {"type": "cone", "start_radius": r_a, "end_radius": r_b}},
                    {"band_width": band, "friction": 0.25, "layers": [{"type": "hoop", "passes": 2}]})).layers[0]
    p = hoop.passes[0]
    pitch = (p.t[-1] - p.t[0]) / ((p.theta[-1] - p.theta[0]) / (2.0 * math.pi))
    dm = abs(pitch) * math.hypot(1.0, (r_b - r_a) / length)
    across = [dm * math.sin(math.atan2(2.0 * math.pi * r, dm)) for r in (r_a, r_b)]
    assert across[0] == pytest.approx(band, rel=1e-6)  # closed at the wide end, no more turns than needed
    assert across[1] < band
    assert hoop.coverage.covered_fraction >= COVERED and hoop.coverage.max_gap_mm == 0.0  # 0.9889 at the axial pitch


def test_hoop_closes_its_band_over_a_short_ramp():
    """A table profile stepping 100 -> 120 mm over 65 mm of a 1 m tube: the stretch there (up to 1.34)
    sets the pitch, found on a grid a quarter band apart; the band's union measured at stations on
    the ramp itself (the layer's own stations are 45 mm apart) closes."""
    from winder.winding.coverage import layer_coverage  # noqa: PLC0415

    points = ([[t, 100] for t in range(0, 481, 60)] + [[500, 101], [512, 110], [524, 119]]
              + [[t, 120] for t in range(545, 1001, 65)])
    pl = plan(job({"axis": {"type": "line", "length": 1000}, "profile": {"type": "table", "points": points}},
                  {"band_width": 10, "friction": 1.0, "layers": [{"type": "hoop"}]}))
    hoop = pl.layers[0]
    ramp = layer_coverage(pl.surface, arc_map(pl.surface.section), list(hoop.passes), 10.0,
                          np.linspace(482.0, 543.0, 62))
    assert ramp.covered_fraction >= COVERED and ramp.max_gap_mm == 0.0  # 0.83, a 116 mm gap on 41 stations


def test_a_spaced_hoop_on_a_cone_says_so():
    """At 89.4272 deg on the 160 -> 85 mm cone the turns lie 1.005 bands apart across the slant at the
    wide end: the layer's note says its coverage stays incomplete."""
    hoop = plan(job({"axis": {"type": "line", "length": 500},
                     "profile": {"type": "cone", "start_radius": 160, "end_radius": 85}},
                    {"band_width": 10, "friction": 0.25, "layers": [{"type": "hoop", "angle": 89.4272}]})).layers[0]
    assert hoop.coverage.covered_fraction < 1.0
    assert any("coverage stays incomplete" in note for note in hoop.notes)


@pytest.mark.parametrize("mandrel, friction", [
    (PIPE, 0.0),  # a hoop on a cylinder is a helix, a geodesic: no friction needed, round-off apart
    ({"axis": {"type": "line", "length": 400},
      "section": {"type": "rounded_rectangle", "width": 100, "height": 70, "corner_radius": 15}}, 0.3),
    ({"axis": {"type": "line", "length": 400},
      "section": {"type": "superellipse", "a": 50, "b": 40, "exponent": 4}}, 0.3),
])
def test_hoop_on_a_straight_tube_holds(mandrel, friction):
    """A constant-pitch hoop on a straight tube of any section is a geodesic (the tube develops flat):
    it holds whatever the friction, on flat faces too (k_n = 0 there: friction is not what holds it)."""
    p = plan(job(mandrel, {"band_width": 10, "friction": friction, "region": {"start": 20, "end": 380},
                           "layers": [{"type": "hoop", "passes": 2}]}))
    assert p.layers[0].max_slip <= friction + 1e-3


def test_plan_needs_winding():
    with pytest.raises(ConfigError, match="t.yaml: winding: missing"):
        plan(parse_config({"name": "t", "mandrel": PIPE}, "t.yaml"))


def test_turned_copies_are_copies_made_one_at_a_time(pipe_plan):
    from winder.winding.layers.helical_open import _turned
    from winder.winding.passes import make_pass, turned_copies
    surf = pipe_plan.surface
    first = [p for p in pipe_plan.layers[0].passes if p.circuit == 1]
    shifts = [0.1, 2.5, -1.0]
    heads = [(1, j + 2, 0, p.kind, p.length) for j in range(len(shifts)) for p in first]
    got = turned_copies(surf, heads, [(p.s, p.theta, p.direction) for p in first], shifts)
    want = [make_pass(surf, 1, j + 2, 0, p.kind, p.s, p.theta + v, _turned(p.direction, v), p.length)
            for j, v in enumerate(shifts) for p in first]
    assert len(got) == len(want)
    for g, w in zip(got, want):
        for name in ("t", "s", "theta", "points", "direction", "alpha_deg"):
            assert_roundoff(getattr(g, name), getattr(w, name), err_msg=name)
        assert (g.circuit, g.kind, g.length) == (w.circuit, w.kind, w.length)
    # and a turn about +z: the points of a copy are the first's turned by the shift
    c, s = math.cos(0.1), math.sin(0.1)
    rot = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    assert np.allclose(got[0].points, first[0].points @ rot, atol=1e-9)


def test_end_headings_are_each_points_heading():
    from winder.winding.layers.helical_open import _end_headings
    from winder.winding.turnaround import heading_deg
    p = plan(job({"axis": {"type": "line", "length": 300}, "section": {"type": "ellipse", "a": 60, "b": 35}},
                 {"band_width": 10, "points": 40, "layers": [{"type": "helical", "angle": 45}]}))
    laid = [q for q in p.layers[0].passes if q.kind in (PassKind.FORWARD, PassKind.RETURN)][:6]
    got = _end_headings(p.surface, laid)
    for q, row in zip(laid, got):
        for end, h in zip((0, -1), row):
            assert h == heading_deg(p.surface, q.s[[end]], q.theta[[end]], q.direction[[end]])[0]
    # forward passes leave the start at the layer angle (45 deg at the reference section, near it elsewhere)
    assert np.all(np.abs(got[0::2, 0] - 45.0) < 15.0)


def test_hoop_with_gaps_says_so():
    """A hoop angle below the closed one (cos(alpha) = B / P) advances more per turn than the band covers
    along the axis (B / sin(alpha)): the layer is planned as asked, but its notes name the gap."""
    layer = plan(job(PIPE, {"band_width": 10, "region": {"start": 20, "end": 480},
                            "layers": [{"type": "hoop", "angle": 80}]})).layers[0]
    pitch = 2 * math.pi * 50 / math.tan(math.radians(80))  # 55.4 mm per turn
    axial = 10 / math.sin(math.radians(80))  # 10.15 mm
    assert layer.coverage.covered_fraction == pytest.approx(axial / pitch, abs=0.01)
    assert len(layer.notes) == 1
    note = layer.notes[0]
    assert f"advances {pitch:.3f} mm per turn" in note and f"({axial:.3f} mm)" in note, note
    assert f"{layer.coverage.covered_fraction:.4f}" in note, note
    closed = math.degrees(math.acos(10 / (2 * math.pi * 50)))
    assert f"leave the angle out ({closed:.3f} deg here)" in note, note


def test_hoop_steeper_than_closed_has_no_gap_note():
    layer = plan(job(PIPE, {"band_width": 10, "region": {"start": 20, "end": 480},
                            "layers": [{"type": "hoop", "angle": 89}]})).layers[0]
    assert_even(layer, 10.0)
    assert layer.notes == ()


def test_angle_range_is_the_laid_one_at_the_region_ends():
    """On a cone a geodesic's angle follows Clairaut, r sin(alpha) = R0 sin(alpha0): the layer's range
    runs from the asked angle on the large end to asin(60 sin(40) / 40) on the small one, whatever the
    number of points (the pass ends are laid too)."""
    cone = {"axis": {"type": "line", "length": 600},
            "profile": {"type": "cone", "start_radius": 60, "end_radius": 40}}
    layer = plan(job(cone, {"band_width": 12, "points": 30, "dwell": {"start": 15, "end": 15},
                            "layers": [{"type": "helical", "angle": 40, "pattern": 3}]})).layers[0]
    small_end = math.degrees(math.asin(60 * math.sin(math.radians(40)) / 40))  # 74.618 deg
    assert layer.alpha_min_deg == pytest.approx(40.0, abs=1e-3)
    assert layer.alpha_max_deg == pytest.approx(small_end, abs=1e-3)


def test_angle_range_on_a_vessel_reaches_the_hoop_at_the_turnaround(vessel_plan):
    # Clairaut: r sin(alpha) = c, so alpha = 90 deg where the fiber turns round on the parallel r = c.
    layer = vessel_plan.layers[0]
    assert layer.alpha_min_deg == pytest.approx(layer.angle_deg, abs=1e-6)
    assert layer.alpha_max_deg == pytest.approx(90.0, abs=1e-6)

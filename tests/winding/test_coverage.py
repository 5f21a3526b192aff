"""Coverage crossings: the batched splines against the pass-by-pass ones (to round-off) and closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.geometry.sections import arc_map
from winder.winding import coverage
from winder.winding.passes import make_pass, make_passes
from winder.winding.plan import plan
from winder.winding.results import FiberPass, PassKind
from roundoff import assert_roundoff

HELIX_ABS = 1e-12  # rad: a spline through samples of a line reproduces it (round-off only)


def _job(mandrel: dict, winding: dict):
    return parse_config({"name": "t", "mandrel": mandrel, "winding": winding}, "t.yaml")


@pytest.fixture(scope="module")
def elliptic():
    return plan(_job({"axis": {"type": "line", "length": 300}, "section": {"type": "ellipse", "a": 60, "b": 35}},
                     {"band_width": 10, "points": 80, "layers": [{"type": "helical", "angle": 45}]}))


@pytest.fixture(scope="module")
def elliptic_layer(elliptic):
    return elliptic.layers[0]


def _pass(t: np.ndarray, theta: np.ndarray, kind: PassKind = PassKind.FORWARD) -> FiberPass:
    m = t.size
    return FiberPass(1, 1, 1, kind, t, t.copy(), theta, np.zeros((m, 3)), np.zeros((m, 3)), np.zeros(m), 0.0)


def _per_pass(passes, stations, arcs=None):
    return [np.concatenate(c) for c in zip(*[coverage._spline_crossings(p, stations, arcs) for p in passes])]


@pytest.mark.parametrize("kind", [PassKind.FORWARD, PassKind.RETURN])
def test_batched_crossings_are_the_pass_by_pass_ones(elliptic_layer, kind):
    passes = [p for p in elliptic_layer.passes if p.kind is kind]
    stations = elliptic_layer.coverage.stations
    batched = coverage._spline_crossings_batched(passes, stations)
    assert batched is not None
    for got, want in zip(batched, _per_pass(passes, stations)):
        assert got.dtype == want.dtype
        assert_roundoff(got, want)


def test_helix_crossings_closed_form():
    # theta linear in t (a helix on a cylinder, forward and back): the crossing is theta0 + k t.
    t = np.linspace(0.0, 100.0, 12)
    k = math.tan(math.radians(40.0)) / 50.0
    back = t[::-1].copy()
    passes = [_pass(t, 0.3 + k * t), _pass(back, 1.0 + k * back, PassKind.RETURN)]
    stations = np.linspace(0.0, 100.0, 23)[1:-1]
    idx, s, th, ds, dth = coverage._spline_crossings_batched(passes, stations)
    assert np.array_equal(idx, np.concatenate([np.arange(21), np.arange(21)]))
    assert np.allclose(s, np.concatenate([stations, stations]), atol=HELIX_ABS)
    assert np.allclose(th, np.concatenate([0.3 + k * stations, 1.0 + k * stations]), atol=HELIX_ABS)
    assert np.allclose(dth, k, atol=HELIX_ABS) and np.allclose(ds, 1.0, atol=HELIX_ABS)


def test_short_pass_falls_back_to_pass_by_pass(elliptic, elliptic_layer):
    stations = elliptic_layer.coverage.stations
    t = np.linspace(0.0, 300.0, 3)  # three points: a parabola, not a not-a-knot cubic
    passes = [p for p in elliptic_layer.passes if p.kind is PassKind.FORWARD][:2] + [_pass(t, 0.01 * t)]
    assert coverage._spline_crossings_batched(passes, stations) is None
    surf = elliptic.surface
    arcs = arc_map(surf.section)
    got = coverage.crossings_many(surf, arcs, passes, stations, 10.0)
    want = coverage._bands(surf, arcs, *coverage._from_fraction(arcs, _per_pass(passes, stations, arcs)), 10.0)
    for a, b in zip(got, want):
        assert_roundoff(a, b)


def test_make_passes_is_make_pass(elliptic, elliptic_layer):
    surf = elliptic.surface
    src = [p for p in elliptic_layer.passes if p.kind is not PassKind.DWELL][:6]
    heads = [(p.layer, p.circuit, p.number, p.kind, p.length) for p in src]
    got = make_passes(surf, heads, [p.s.size for p in src], np.concatenate([p.s for p in src]),
                      np.concatenate([p.theta + 0.25 for p in src]), np.concatenate([p.direction for p in src]))
    for g, p in zip(got, src):
        want = make_pass(surf, p.layer, p.circuit, p.number, p.kind, p.s, p.theta + 0.25, p.direction, p.length)
        for name in ("t", "s", "theta", "points", "direction", "alpha_deg"):
            assert_roundoff(getattr(g, name), getattr(want, name), err_msg=name)
        assert (g.layer, g.circuit, g.number, g.kind, g.length) == (want.layer, want.circuit, want.number,
                                                                    want.kind, want.length)


HOOP_CLOSED_TOL = 1e-6  # covered fraction below 1 that round-off may leave where turns abut exactly


@pytest.mark.parametrize("section", [
    {"type": "rounded_rectangle", "width": 120, "height": 80, "corner_radius": 15},
    {"type": "rounded_rectangle", "width": 200, "height": 50, "corner_radius": 5},
    {"type": "ellipse", "a": 45, "b": 15},
    {"type": "superellipse", "a": 50, "b": 30, "exponent": 4},
])
def test_hoop_on_a_straight_non_circular_tube_closes(section):
    """A straight tube unrolls flat: a hoop is a straight line in (t, arc length) whose turns lie
    pitch P / sqrt(P^2 + pitch^2) = B apart across the fiber (closed form, read from the planned
    points' own arc positions), so its bands meet edge to edge and the layer is covered (the spline
    through theta against t read 0.989 with a 4 mm gap on the 120 x 80 tube)."""
    band = 10.0
    done = plan(_job({"axis": {"type": "line", "length": 400}, "section": section},
                     {"band_width": band, "region": {"start": 20, "end": 380}, "layers": [{"type": "hoop"}]}))
    hoop = done.layers[0]
    fp = hoop.passes[0]
    perimeter = float(done.surface.perimeter(np.array([200.0]))[0])
    arc = arc_map(done.surface.section).fraction(fp.theta) * perimeter  # unwrapped arc position (mm)
    pitch = float(np.polyfit(arc, fp.t, 1)[0]) * perimeter  # axial advance per turn
    across = pitch * perimeter / math.hypot(perimeter, pitch)
    assert across == pytest.approx(band, rel=1e-9)
    assert hoop.coverage.covered_fraction >= 1.0 - HOOP_CLOSED_TOL
    assert hoop.coverage.max_gap_mm <= 1e-3

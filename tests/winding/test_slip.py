"""The layer slip measure: over all passes at once against pass by pass (the same result exactly), and
against the closed form on a cylinder (a geodesic helix: k_g = 0, k_n = sin^2(alpha) / R)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.winding import slip
from winder.winding.plan import plan
from winder.winding.results import PassKind

HELIX_KN_REL = 2e-3  # polyline curvature of a pass at 8 mm vertex spacing on R = 50: O((h / R)^2 / 24) = 1e-3


def _plan(mandrel: dict, winding: dict):
    return plan(parse_config({"name": "t", "mandrel": mandrel, "winding": winding}, "t.yaml"))


@pytest.fixture(scope="module")
def plans():
    tube = {"axis": {"type": "line", "length": 300}, "section": {"type": "ellipse", "a": 60, "b": 35}}
    pipe = {"axis": {"type": "line", "length": 500}, "profile": {"type": "constant", "radius": 50}}
    return (_plan(tube, {"band_width": 10, "points": 80, "layers": [{"type": "helical", "angle": 45}]}),
            _plan(pipe, {"band_width": 10, "points": 100, "layers": [{"type": "helical", "angle": 55},
                                                                      {"type": "hoop", "passes": 2}]}))


def test_measure_is_pass_by_pass(plans):
    for p in plans:
        for layer in p.layers:
            laid = [q for q in layer.passes if q.kind is not PassKind.DWELL and q.s.size >= 3]
            want = slip._measure_each(laid, slip._curvatures(p.surface, laid))
            assert slip.measure(p.surface, layer.passes) == want


def test_measure_on_a_cylinder_helix(plans):
    out = slip.measure(plans[1].surface, plans[1].layers[0].passes)
    assert out.max_slip < 1e-6
    assert out.min_normal_curvature == pytest.approx(math.sin(math.radians(55.0)) ** 2 / 50.0, rel=HELIX_KN_REL)


def test_measure_with_a_non_finite_curvature_goes_pass_by_pass(plans, monkeypatch):
    p = plans[0]
    real = slip._curvatures

    def with_nan(surface, passes):
        curves = real(surface, passes)
        if len(curves) < 2:
            return curves
        k_n, k_g = curves[1]
        curves[1] = (np.where(np.arange(k_n.size) == 3, np.nan, k_n), k_g)
        return curves

    monkeypatch.setattr(slip, "_curvatures", with_nan)
    laid = [q for q in p.layers[0].passes if q.kind is not PassKind.DWELL and q.s.size >= 3]
    assert slip.measure(p.surface, p.layers[0].passes) == slip._measure_each(laid, with_nan(p.surface, laid))
    assert slip.measure(p.surface, []) == slip.LayerSlip(0.0, np.inf, 0.0, 0.0, 0, 0.0, 0)

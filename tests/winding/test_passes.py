"""Pass tangents solved together against pass by pass (the same values to the bit) and the closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.errors import ConfigError, SolverError
from winder.geometry.build import build_surface
from winder.geometry.sections import arc_map
from winder.winding import passes as P
from roundoff import assert_roundoff

HELIX_DIR_ABS = 1e-9  # unit tangent of a helix from the spline through its refined vertices


def _ctx(mandrel: dict, points: int | None, tolerance: float | None = None) -> P.PlanContext:
    size = {"points": points} if tolerance is None else {"tolerance": tolerance}
    job = parse_config({"name": "t", "mandrel": mandrel,
                        "winding": {"band_width": 10, **size, "layers": [{"type": "helical", "angle": 45}]}},
                       "t.yaml")
    surface = build_surface(job.mandrel, job.source, job.name)
    return P.PlanContext(job, job.winding, surface, arc_map(surface.section), job.machine.feed)


@pytest.mark.parametrize("batch", [P.TANGENT_BATCH_POINTS, 500])
def test_solved_passes_are_directions_pass_by_pass(monkeypatch, batch):
    monkeypatch.setattr(P, "TANGENT_BATCH_POINTS", batch)
    ctx = _ctx({"axis": {"type": "line", "length": 300}, "section": {"type": "ellipse", "a": 60, "b": 35}}, 30)
    fines = [P.fine_geodesic(ctx, (0.0, th0), (300.0, th0 + 4.0), None, n)
             for th0, n in ((0.0, 30), (1.0, 30), (2.0, 20), (3.0, 30))]  # two sizes of fine solve
    got = P.solved_passes(ctx.surface, fines)
    k = P.TANGENT_REFINE
    for f, g in zip(fines, got):
        want = P.directions(ctx.surface, f.refined_s, f.refined_theta)[::k]
        assert_roundoff(g.direction, want)
        assert np.array_equal(g.s, f.refined_s[::k]) and np.array_equal(g.theta, f.refined_theta[::k])
        assert g.length == f.length and g.result is f


def test_solved_pass_tangent_on_a_cylinder_is_the_helix():
    ctx = _ctx({"axis": {"type": "line", "length": 300}, "profile": {"type": "constant", "radius": 50}}, 40)
    sp = P.solve_pass(ctx, (0.0, 0.0), (300.0, 3.0), None)
    # the helix theta = 3 t / 300 on r = 50: its direction at (t, theta) is (-r k sin, r k cos, 1) / norm
    rk = 50.0 * 3.0 / 300.0
    want = np.column_stack([-rk * np.sin(sp.theta), rk * np.cos(sp.theta), np.ones_like(sp.theta)])
    want /= math.hypot(rk, 1.0)
    assert np.allclose(sp.direction, want, atol=HELIX_DIR_ABS)


def test_a_dwell_from_one_evaluation_is_the_pass_evaluated_anew():
    # dwell_pass hands its evaluation to make_pass: the same pass as make_pass evaluating it itself
    ctx = _ctx({"axis": {"type": "line", "length": 300}, "section": {"type": "ellipse", "a": 60, "b": 35}}, 30)
    for heading_in, heading_out in ((90.0, 90.0), (60.0, 120.0)):
        fp = P.dwell_pass(ctx, 1, 1, 1, 120.0, 0.3, 2.9, heading_in, heading_out)
        again = P.make_pass(ctx.surface, 1, 1, 1, fp.kind, fp.s, fp.theta, fp.direction, fp.length)
        pts = ctx.surface.points(fp.s, fp.theta)
        assert_roundoff(fp.points, again.points)
        assert_roundoff(fp.points, pts)
        assert_roundoff(fp.alpha_deg, again.alpha_deg)
        assert_roundoff(fp.length, float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1))))


def test_a_tolerance_past_double_precision_names_winding_tolerance():
    """The solver's refusal of a tolerance below its roundoff floor names the config key, not the
    solver's own 'tolerance' (which the command line reads as geodesic's --tolerance)."""
    ctx = _ctx({"axis": {"type": "line", "length": 300}, "profile": {"type": "constant", "radius": 50}}, None,
               tolerance=1e-300)
    with pytest.raises(SolverError, match=r"below what double precision resolves") as err:
        P.fine_geodesic(ctx, (0.0, 0.0), (300.0, 4.0), None)
    assert (err.value.file, err.value.key_path) == ("t.yaml", "winding.tolerance")
    assert str(err.value).startswith("t.yaml: winding.tolerance: 1e-300 mm is below")


def test_too_few_points_for_a_pass_of_many_rounds_names_winding_points():
    """A pass sweeping more rounds than a third of its segments is refused as the solver refuses it,
    under the config's key: 10 points cannot follow 5 rounds (a chord would span 180 deg)."""
    ctx = _ctx({"axis": {"type": "line", "length": 300}, "profile": {"type": "constant", "radius": 50}}, 10)
    with pytest.raises(ConfigError) as err:
        P.fine_geodesic(ctx, (0.0, 0.0), (300.0, 10.0 * math.pi), None)
    assert (err.value.file, err.value.key_path) == ("t.yaml", "winding.points")
    assert str(err.value).startswith("t.yaml: winding.points: must be at least 14 for a path of 5 rounds")
    assert P.fine_geodesic(ctx, (0.0, 0.0), (300.0, 6.0 * math.pi), None).converged  # 3 rounds: 9 segments do

"""A long pass on a non-circular tube (the issue's rounded-rectangle boom: 120 x 80, corners 15, stations
50..1950 at 45 deg, five turns) converges from the unrolled straight line (winder.winding.passes.
unrolled_line). Truth: a general cylinder is developable, so the geodesic is the unrolled line, its length
hypot(axial run, perimeter x turns) with the rounded rectangle's closed-form perimeter."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.geometry.build import build_surface
from winder.geometry.sections import arc_map
from winder.winding.passes import PlanContext, fine_geodesic

WIDTH, HEIGHT, CORNER = 120.0, 80.0, 15.0
PERIMETER = 2.0 * (WIDTH + HEIGHT) - 8.0 * CORNER + 2.0 * math.pi * CORNER
LENGTH_RTOL = 1e-6  # the solved length (polyline, Richardson) against the unrolled line's
PATH_TOL = 0.1  # mm: the vertices' arc position off the unrolled line (600 chords over 15 mm corners)


def test_boom_pass_converges_on_the_unrolled_line() -> None:
    job = parse_config({"name": "boom", "mandrel": {
        "axis": {"type": "line", "length": 2000},
        "section": {"type": "rounded_rectangle", "width": WIDTH, "height": HEIGHT, "corner_radius": CORNER}},
        "winding": {"band_width": 10, "points": 600, "region": {"start": 50, "end": 1950},
                    "layers": [{"type": "helical", "angle": 45}]}}, "boom.yaml")
    surf = build_surface(job.mandrel)
    ctx = PlanContext(job, job.winding, surf, arc_map(surf.section), job.machine.feed)
    turns = 1900.0 / PERIMETER  # at 45 deg the arc run equals the axial run
    end = float(ctx.arcs.theta(np.array([turns]))[0])
    res = fine_geodesic(ctx, (50.0, 0.0), (1950.0, end), None, 600)
    assert res.converged
    assert res.length == pytest.approx(math.hypot(1900.0, turns * PERIMETER), rel=LENGTH_RTOL)
    arc = ctx.arcs.fraction(res.theta) * PERIMETER
    assert np.max(np.abs(arc - (res.s - res.s[0]) * turns * PERIMETER / 1900.0)) < PATH_TOL


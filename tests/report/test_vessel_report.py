"""The report's vessel section (winder.report.vessel): the domes bare and as wound after each layer, each
layer's wall along the bare dome, and the turnarounds per dome, checked against the plan itself: the
grown meridians are the surfaces the layers were wound on, the stacked walls add up to the summary's
wall reading (winder.winding.dome_wall), the table's radii are the CSV's least radii per dome (a closed
end turning round its shaft, an unequal boss)."""

from __future__ import annotations

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.export.summary import summary_dict
from winder.report.vessel import is_wound_vessel, turnaround_table, vessel_figure
from winder.winding.dome_wall import wall_at
from winder.winding.plan import plan

JOB = {"name": "v", "mandrel": {"profile": {
    "type": "vessel", "radius": 50, "cylinder_length": 80,
    "dome": {"type": "hemisphere", "polar_opening": 10},
    "end_dome": {"type": "ellipsoid", "polar_opening": 0, "shaft_radius": 6, "depth": 35}}},
    "winding": {"band_width": 6, "points": 24, "material": {"ply_thickness": 0.3},
                "layers": [{"type": "helical", "angle": 12, "slip": "auto"}, {"type": "hoop", "passes": 2},
                           {"type": "helical", "angle": 30}]}}


@pytest.fixture(scope="module")
def planned():
    return plan(parse_config(JOB, "v.yaml"))


def test_contours_and_walls_per_layer(planned):
    assert is_wound_vessel(planned)
    fig = vessel_figure(planned)
    contours = [d for d in fig["data"] if "stackgroup" not in d]
    walls = [d for d in fig["data"] if "stackgroup" in d]
    assert len(contours) == 2 * (1 + len(planned.layers)) and len(walls) == 2 * len(planned.layers)
    # the first dome's last contour is the finished part's meridian
    last = contours[len(planned.layers)]
    outer = planned.outer_surface.profile
    ev = outer.evaluate(np.linspace(*outer.dome_ranges.dome, 200))
    np.testing.assert_allclose(last["y"], ev.r, atol=0.006)  # the figure keeps 2 decimals of a coordinate
    # the stacked walls on each dome sum to the summary's reading at the same bare points
    bare = planned.surface.profile
    for i, rng in enumerate((bare.dome_ranges.dome, bare.dome_ranges.end_dome)):
        ev = bare.evaluate(np.linspace(*rng, 200))
        total = sum(np.asarray(w["y"], dtype=float) for w in walls[i * len(planned.layers):(i + 1) * len(planned.layers)])
        np.testing.assert_allclose(total, wall_at(planned, np.column_stack([ev.z, ev.r])), atol=1e-3)


def test_turnaround_table_per_dome(planned):
    text = turnaround_table(summary_dict(planned))
    # the 12 deg layer turns at its own floor on each dome: the boss 10 + 3, the shaft 6 + 3
    assert "<td>layer 1</td><td>12.00°</td><td>13.00</td><td class=dim>friction-held</td><td>9.00</td>" in text
    assert "<td>layer 3</td>" in text and "geodesic" in text and "<td>layer 2</td>" not in text

"""The numbers a shop asks first (issue 49.4): a vessel's enclosed volume against cylinder + two domes in
closed form within 1e-6, and a pipe's mass per metre against its rings of composite."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.analysis.quantities import enclosed_volume
from winder.config.job import load_config
from winder.export.summary import summary_dict
from winder.geometry.build import build_surface
from winder.winding.plan import plan

VOLUME = 1e-6  # relative: the bound


def _cap(radius: float, depth: float, opening: float) -> float:
    """pi r^2 integrated over an ellipsoid's cap r^2 = R^2 (1 - z^2 / d^2), from the equator to r = opening."""
    h = depth * math.sqrt(1.0 - (opening / radius) ** 2)
    return math.pi * radius ** 2 * (h - h ** 3 / (3.0 * depth ** 2))


@pytest.mark.parametrize("radius, cylinder, dome, end", [
    (100.0, 300.0, "{type: hemisphere, polar_opening: 30}", None),
    (150.0, 600.0, "{type: hemisphere, polar_opening: 25}", "{type: hemisphere, polar_opening: 60}"),
    (40.0, 120.0, "{type: ellipsoid, depth: 25, polar_opening: 8}", "{type: ellipsoid, depth: 70, polar_opening: 12}"),
    (600.0, 2000.0, "{type: ellipsoid, depth: 400, polar_opening: 90}", None),
])
def test_vessel_volume_is_cylinder_plus_two_domes(tmp_path, radius, cylinder, dome, end):
    path = tmp_path / "v.yaml"
    path.write_text(f"""name: v
mandrel:
  profile: {{type: vessel, radius: {radius}, cylinder_length: {cylinder}, dome: {dome}{', end_dome: ' + end if end else ''}}}
winding:
  band_width: 10
  layers: [{{type: hoop, passes: 1}}]
""", encoding="utf-8")
    job = load_config(path)
    surface = build_surface(job.mandrel)
    caps = []
    for text in (dome, end or dome):
        spec = dict(part.split(": ") for part in text.strip("{}").split(", "))
        depth = float(spec.get("depth", radius))
        caps.append(_cap(radius, depth, float(spec["polar_opening"])))
    expected = math.pi * radius ** 2 * cylinder + sum(caps)
    assert abs(enclosed_volume(surface.profile) / expected - 1.0) < VOLUME


PIPE = """name: pipe
mandrel:
  axis: {type: line, length: 400}
  profile: {type: constant, radius: 80}
winding:
  band_width: 10
  region: {start: 30, end: 370}
  points: 30
  material: {fiber_tex: 2400, tows: 2, fiber_density: 2.56, resin_density: 1.15, fiber_volume_fraction: 0.55}
  layers:
    - {type: helical, angle: 55}
    - {type: hoop, passes: 2}
"""


def test_pipe_mass_per_metre_is_its_rings_of_composite(tmp_path):
    path = tmp_path / "pipe.yaml"
    path.write_text(PIPE, encoding="utf-8")
    job = load_config(path)
    planned = plan(job)
    summary = summary_dict(planned, None, job=job)
    rho = (0.55 * 2.56 + 0.45 * 1.15) * 1e-6  # kg/mm^3
    inner, expected = 80.0, 0.0
    for layer in summary["layers"]:
        outer = inner + layer["thickness_mm"]
        expected += rho * math.pi * (outer ** 2 - inner ** 2) * 1000.0
        inner = outer
    # thickness_mm is written at 4 decimals: the rings agree to that
    assert abs(summary["mass_per_metre_kg"] / expected - 1.0) < 1e-4
    trimmed = summary["trimmed"]
    t0, t1 = trimmed["t_mm"]
    assert 30.0 < t0 < t1 < 370.0 and abs(trimmed["length_mm"] - (t1 - t0)) < 1e-3
    # a uniform pipe: the trimmed mass is the mass per metre over its length, within the wall's ripple
    assert abs(trimmed["mass_kg"] / (summary["mass_per_metre_kg"] * (t1 - t0) / 1000.0) - 1.0) < 0.02
    assert abs(trimmed["mass_per_metre_kg"] - trimmed["mass_kg"] / (t1 - t0) * 1000.0) < 1e-5
    assert "volume_l" not in summary

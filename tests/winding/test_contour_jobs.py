"""A liner drawn as points plans the job its formula plans (docs/math/17-vessels-as-built.md 17.4): an
ellipsoid dome given as points sampled from it, in a CSV and in a DXF written by ezdxf, against the
analytic ellipsoid, through two helical layers and a hoop grown on each other: every layer's fiber
length within 1e-4 of the analytic job's and its turnaround radius within 0.01 mm."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.config.job import load_config
from winder.winding.plan import plan

R, DEPTH, OPENING = 120.0, 75.0, 20.0
SAMPLES = 160
LENGTH_RTOL = 1e-4
RADIUS_TOL = 0.01  # mm

JOB = """name: {name}
mandrel:
  profile:
    type: vessel
    radius: {R:g}
    cylinder_length: 250
    dome: {dome}
    end_dome: {{type: ellipsoid, polar_opening: 28, depth: 70}}
winding:
  band_width: 10
  points: 40
  material: {{ply_thickness: 0.3}}
  layers:
    - {{type: helical, angle: 16, slip: auto}}
    - {{type: hoop, passes: 2, taper: 10}}
    - {{type: helical, angle: 24}}
"""


def _points() -> np.ndarray:
    tau = np.linspace(0.0, math.acos(OPENING / R), SAMPLES)
    return np.column_stack([DEPTH * np.sin(tau), R * np.cos(tau)])


def _plan(tmp_path, name: str, dome: str):
    path = tmp_path / f"{name}.yaml"
    path.write_text(JOB.format(name=name, R=R, dome=dome), encoding="utf-8")
    return plan(load_config(path))


@pytest.fixture(scope="module")
def analytic(tmp_path_factory):
    return _plan(tmp_path_factory.mktemp("ell"), "ell", f"{{type: ellipsoid, polar_opening: {OPENING:g}, depth: {DEPTH:g}}}")


def _same_job(got, want) -> None:
    for a, b in zip(got.layers, want.layers, strict=True):
        assert a.fiber_length_mm == pytest.approx(b.fiber_length_mm, rel=LENGTH_RTOL)
        if b.turnaround_radius is not None:
            assert a.turnaround_radius == pytest.approx(b.turnaround_radius, abs=RADIUS_TOL)
        assert (a.circuits, a.pattern) == (b.circuits, b.pattern)


def test_contour_csv_plans_the_ellipsoid_job(tmp_path, analytic) -> None:
    lines = ["z,r"] + [f"{z:.12g},{r:.12g}" for z, r in _points()]
    (tmp_path / "liner.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    _same_job(_plan(tmp_path, "csv", "{type: contour, file: liner.csv}"), analytic)


def test_contour_dxf_plans_the_ellipsoid_job(tmp_path, analytic) -> None:
    ezdxf = pytest.importorskip("ezdxf")
    doc = ezdxf.new()
    doc.modelspace().add_lwpolyline([tuple(p) for p in _points()])
    doc.saveas(tmp_path / "liner.dxf")
    _same_job(_plan(tmp_path, "dxf", "{type: contour, file: liner.dxf}"), analytic)

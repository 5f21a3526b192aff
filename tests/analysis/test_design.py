"""`winder design CONFIG [--json]` (docs/guide/will-it-hold.md): netting sizing before planning, against
the closed forms of docs/math/09-structure.md 9.2 and docs/math/08-laminate-edges.md."""

from __future__ import annotations

import json
import math
from pathlib import Path

from click.testing import CliRunner

from winder.cli import main

CLOSED_FORM = 1e-4  # the JSON's 4 decimals
R, SIGMA, VF = 100.0, 2000.0, 0.5


def _config(tmp_path: Path, layers: str, analysis: str = "{pressure: 30}") -> Path:
    path = tmp_path / "tube.yaml"
    path.write_text(f"""name: tube
mandrel:
  axis: {{type: line, length: 400}}
  profile: {{type: constant, radius: {R}}}
winding:
  band_width: 10
  material: {{name: carbon_epoxy, ply_thickness: 0.5, fiber_volume_fraction: {VF}, strand_strength: {SIGMA / VF}}}
  layers:
{layers}
analysis: {analysis}
""", encoding="utf-8")
    return path


def _design(path: Path) -> dict:
    result = CliRunner().invoke(main, ["design", str(path), "--json"])
    assert result.exit_code == 0, result.output
    return json.loads(result.output)


def test_design_json_sizes_each_helical_layer_and_gives_the_burst(tmp_path):
    out = _design(_config(tmp_path, "    - {type: helical, angle: 30}\n    - {type: hoop, passes: 2}"))
    hel, hoop = out["layers"]
    assert hel["netting_stress_mpa"] == SIGMA and hel["allowable_source"] == "strand_strength"  # strand V_f
    assert abs(hel["helical_thickness_needed_mm"] - 1.0) < CLOSED_FORM  # the sizing at 30 MPa, 30 deg
    assert abs(hel["hoop_thickness_needed_mm"] - 1.25) < CLOSED_FORM
    # as configured: docs/math/08-laminate-edges.md's helical thickness with N_c = ceil(2 pi R cos a / B); hoops t_p per pass
    a = math.radians(30.0)
    n_c = math.ceil(2 * math.pi * R * math.cos(a) / 10.0)
    t_h = 2 * 0.5 * n_c * 10.0 / (2 * math.pi * R * math.cos(a))
    assert abs(hel["thickness_mm"] - t_h) < CLOSED_FORM and abs(hoop["thickness_mm"] - 1.0) < CLOSED_FORM
    # the first family to reach sigma (docs/math 9.2): the helicals at 2 sigma t_h cos^2 a / R, the hoops
    # (carrying N_h - N_m tan^2 a) at sigma t_c / (R (1 - tan^2 a / 2))
    helical = 2 * SIGMA * t_h * math.cos(a) ** 2 / R
    hoops = SIGMA * 1.0 / (R * (1 - math.tan(a) ** 2 / 2))
    assert abs(out["burst_pressure_netting_mpa"] - min(helical, hoops)) < CLOSED_FORM
    assert out["burst_netting_layer"] == 2 and out["zones"][0]["zone"] == "reference section"
    assert abs(out["netting_optimum_angle_deg"] - 54.7356) < CLOSED_FORM
    assert abs(out["optimum_helical_thickness_mm"] - 3 * 30 * R / (2 * SIGMA)) < CLOSED_FORM


def test_design_text_and_refusals(tmp_path):
    path = _config(tmp_path, "    - {type: helical, angle: 45}")
    result = CliRunner().invoke(main, ["design", str(path)])
    assert result.exit_code == 0 and "burst (netting)" in result.output and "optimum angle 54.7356" in result.output
    # every load it used, and what it covered
    assert "at 30 MPa, axial force 0 N, torque 0 N mm, closed ends" in result.output
    assert "covers the reference section" in result.output and "layer 1 (helical 45 deg)" in result.output
    path = _config(tmp_path, "    - {type: helical, angle: 45}", "{pressure: 0}")
    result = CliRunner().invoke(main, ["design", str(path)])
    assert result.exit_code == 2 and "analysis.pressure: must be > 0" in result.output


def test_design_refuses_a_bent_mandrel(tmp_path):
    path = tmp_path / "bend.yaml"
    path.write_text("""name: bend
mandrel:
  axis: {type: arc, radius: 150, angle: 90}
  profile: {type: constant, radius: 40}
winding:
  band_width: 10
  material: {name: eglass_epoxy, ply_thickness: 0.4}
  layers:
    - {type: helical, angle: 60, slip: auto}
analysis: {pressure: 3, ends: open}
""", encoding="utf-8")
    result = CliRunner().invoke(main, ["design", str(path)])
    assert result.exit_code == 2 and "mandrel: winder design needs a surface of revolution" in result.output


def test_abaqus_without_a_load_case_is_refused_before_planning(tmp_path):
    path = _config(tmp_path, "    - {type: helical, angle: 45}")
    text = path.read_text(encoding="utf-8").replace("analysis: {pressure: 30}\n", "")
    path.write_text(text, encoding="utf-8")
    result = CliRunner().invoke(main, ["run", str(path), "-o", str(tmp_path / "out"), "--format", "abaqus"])
    assert result.exit_code == 2 and "analysis: required for --format abaqus" in result.output
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_design_covers_a_vessels_domes(tmp_path):
    """A vessel: the cylinder and both domes (helicals at their geodesic angles, hoops ending at the
    equators): the dome's shoulder, just past the equator where the hoops end, governs a +-a + hoop wall,
    at the closed form of the helicals alone on the dome's membrane loads there."""
    path = tmp_path / "vessel.yaml"
    path.write_text(f"""name: vessel
mandrel:
  profile: {{type: vessel, radius: {R}, cylinder_length: 200, dome: {{type: hemisphere, polar_opening: 30}}}}
winding:
  band_width: 10
  material: {{name: carbon_epoxy, ply_thickness: 0.5, fiber_volume_fraction: {VF}, strand_strength: {SIGMA / VF}}}
  layers:
    - {{type: helical, angle: 25}}
    - {{type: hoop, passes: 2}}
analysis: {{pressure: 30}}
""", encoding="utf-8")
    out = _design(path)
    zones = {z["zone"]: z for z in out["zones"]}
    assert set(zones) == {"cylinder", "start dome", "end dome"} and "both domes" in out["covered"]
    shoulder = zones["start dome"]
    assert shoulder["r_mm"] > 0.99 * R and out["burst_netting_zone"] in ("start dome", "end dome")
    # a sphere's membrane loads p R / 2 both ways on a +-a net alone, a at the equator: direction-wise
    a = math.radians(25.0)
    t_h = out["layers"][0]["thickness_mm"]
    expected = min(2 * SIGMA * t_h * math.cos(a) ** 2 / R, 2 * SIGMA * t_h * math.sin(a) ** 2 / R)
    assert abs(shoulder["burst_pressure_netting_mpa"] - expected) < 2e-3 * expected
    assert shoulder["burst_pressure_netting_mpa"] < zones["cylinder"]["burst_pressure_netting_mpa"]

"""The structural analysis of a planned job (docs/guide/will-it-hold.md): samples/vessel_laminate.yaml
reports its netting burst and first-ply failure pressures in the summary and the report; the cylinder's
netting burst is the closed form over the layup CSV's layers there."""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np
import pytest

from winder.analysis.materials import MATERIALS
from winder.config.job import load_config
from winder.export import registry
from winder.export.summary import summary_dict
from winder.winding.plan import plan

SAMPLE = Path(__file__).resolve().parents[2] / "samples" / "vessel_laminate.yaml"
PRESSURE_DECIMALS = 1e-3  # the summary's MPa decimals


@pytest.fixture(scope="module")
def planned():
    job = load_config(SAMPLE)
    return job, plan(job)


def test_summary_reports_burst_and_first_ply_failure(planned):
    job, pl = planned
    block = summary_dict(pl, None, job=job)["analysis"]
    assert block["success"] and block["pressure_mpa"] == job.analysis.pressure
    for key in ("burst_pressure_netting_mpa", "first_ply_failure_pressure_mpa", "first_ply_failure_max_stress_mpa"):
        assert block[key] is not None and block[key] > 0.0, key
    assert block["layer"] in (1, 2, 3) and 0.0 <= block["t"] <= pl.surface.axial_length
    assert abs(block["netting_optimum_angle_deg"] - 54.7356) < 1e-4
    # first-ply failure (matrix cracking) comes before the fibers burst
    assert block["first_ply_failure_pressure_mpa"] < block["burst_pressure_netting_mpa"]
    per_layer = min(x["first_ply_failure_pressure_mpa"] for x in block["layers"])
    assert abs(per_layer - block["first_ply_failure_pressure_mpa"]) < PRESSURE_DECIMALS
    # mid-cylinder from the layup CSV's rows (docs/math 9.2): five families (+-22, +-35, hoops), three
    # equations: the fibers share the load by one membrane strain, S_k = E t_k n_k . e, K e = N
    layup = registry.FORMATS[[f.name for f in registry.FORMATS].index("layup")].render(pl, job).decode()
    rows = np.array([[float(r[k]) for k in ("layer", "t", "angle_deg", "thickness_mm")]
                     for r in csv.DictReader(io.StringIO(layup))])
    mid = 0.5 * sum(pl.surface.profile.equator_t)
    ply = MATERIALS["carbon_epoxy"]
    sigma = ply.strand_strength * job.winding.material.fiber_volume_fraction
    n = []
    for layer in (1, 2, 3):
        mine = rows[rows[:, 0] == layer]
        row = mine[np.argmin(np.abs(mine[:, 1] - mid))]
        a = math.radians(row[2])
        n.append((row[3], math.cos(a) ** 2, math.sin(a) ** 2))
    k = sum(ply.E1 * t * np.outer([c, s], [c, s]) for t, c, s in n)
    strain = np.linalg.solve(k, [100.0 / 2, 100.0])  # per MPa: N_m = p R / 2, N_h = p R on R 100
    cylinder_burst = min(sigma / (ply.E1 * (c * strain[0] + s * strain[1])) for _, c, s in n)
    from winder.analysis.structure import analyze

    st = analyze(pl, job).stations
    k = int(np.argmin(np.abs(st.geometry.t - mid)))
    assert abs(st.netting.burst[k] - cylinder_burst) < 1e-3 * cylinder_burst  # the rows nearest mid-length
    # the headline comes from the cylinder's gauge, the ends apart and labelled
    assert block["gauge"] == "cylinder" and block["gauge_t_mm"][0] > pl.surface.profile.equator_t[0]
    assert block["burst_pressure_netting_mpa"] <= cylinder_burst + PRESSURE_DECIMALS
    assert block["end_zones"]["label"].startswith("outside the gauge")
    assert block["end_zones"]["first_ply_failure_pressure_mpa"] < block["first_ply_failure_pressure_mpa"]
    p = job.analysis.pressure
    assert abs(block["burst_ratio"] - block["burst_pressure_netting_mpa"] / p) < 1e-3
    assert abs(block["first_ply_failure_ratio"] - block["safety_factor"]) < 1e-4
    (ratio,) = block["stress_ratio"]  # one fiber material; no held load: the burst ratio
    assert ratio["material"] == "carbon_epoxy" and ratio["required"] is None and ratio["pass"] is None
    assert abs(ratio["achieved"] - block["burst_ratio"]) < 1e-3
    assert block["netting_allowables"][0]["source"] == "strand_strength" and block["notes"]


def test_report_shows_the_structure(planned):
    pytest.importorskip("plotly")
    job, pl = planned
    page = next(f for f in registry.FORMATS if f.name == "report").render(pl, job).decode("utf-8")
    block = summary_dict(pl, None, job=job)["analysis"]
    assert "Will it hold?" in page and 'id="winder-structure"' in page
    assert f"{block['burst_pressure_netting_mpa']} MPa" in page
    assert f"{block['first_ply_failure_pressure_mpa']} MPa" in page


PIPE = """name: gauge_pipe
mandrel:
  axis: {{type: line, length: 400}}
  profile: {{type: constant, radius: 80}}
winding:
  band_width: 10
  points: 30
  material: {{name: eglass_epoxy, ply_thickness: 0.4, fiber_volume_fraction: 0.55}}
  layers:
    - {{type: helical, angle: 30}}
    - {{type: hoop, passes: 2, taper: 40}}
analysis: {{pressure: 2, ends: closed{gauge}}}
"""


@pytest.fixture(scope="module")
def pipe(tmp_path_factory):
    path = tmp_path_factory.mktemp("gauge") / "gauge_pipe.yaml"
    path.write_text(PIPE.format(gauge=""), encoding="utf-8")
    job = load_config(path)
    return path, job, plan(job)


def test_an_open_mandrels_headline_is_its_trimmed_part(pipe):
    """The hoops' taper steps their reversals in: the headline figures come from where every layer is laid at
    its full thickness (the `wound` gauge), the tapered ends apart in end_zones, where they are lower."""
    path, job, planned = pipe
    block = summary_dict(planned, None, job=job)["analysis"]
    hoop = planned.layers[1].laminate
    laid = hoop.t[hoop.thickness > 0.0]
    t0, t1 = block["gauge_t_mm"]
    assert block["gauge"] == "wound" and laid.min() < t0 < t1 < laid.max()
    assert block["burst_netting_t"] is not None and t0 <= block["burst_netting_t"] <= t1
    ends = block["end_zones"]
    assert ends["burst_pressure_netting_mpa"] < block["burst_pressure_netting_mpa"]
    # the +-30 + hoop wall is determinate; the ends' weakest station has fewer hoops
    assert block["burst_netting_wall"] == "determinate"
    assert not t0 <= ends["burst_netting_t"] <= t1
    mid = int(np.argmin(np.abs(hoop.t - 0.5 * (t0 + t1))))
    assert np.interp(ends["burst_netting_t"], hoop.t, hoop.thickness) < 0.9 * hoop.thickness[mid]
    # gauge: all takes every station: the least of both
    whole = path.with_name("all.yaml")
    whole.write_text(PIPE.format(gauge=", gauge: all"), encoding="utf-8")
    job_all = load_config(whole)
    every = summary_dict(planned, None, job=job_all)["analysis"]
    assert every["gauge_t_mm"] is None and every["end_zones"] is None
    assert every["burst_pressure_netting_mpa"] == min(block["burst_pressure_netting_mpa"],
                                                      ends["burst_pressure_netting_mpa"])

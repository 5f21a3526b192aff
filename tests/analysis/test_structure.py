"""The structural analysis of a planned job (SPEC.md "Structural analysis"): samples/vessel_laminate.yaml
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

"""The job CSV and the summary JSON."""

from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest

from conftest import surface_of
from plans import cylinder_plan
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.export.job_csv import job_csv_text
from winder.export.summary import summary_dict, summary_text

HALF_ULP6 = 5e-7 + 1e-12  # what 6 printed decimals may lose


@pytest.fixture(scope="module")
def plan():
    return cylinder_plan(surface_of(LineAxis(300.0), ConstantProfile(40.0)))


# -- CSV -------------------------------------------------------------------------------------------
def test_csv_header_and_rows(plan):
    text = job_csv_text(plan)
    lines = text.splitlines()
    assert lines[0] == "layer,circuit,pass,i,t,theta_deg,x,y,z,alpha_deg,kind"
    passes = [fp for layer in plan.layers for fp in layer.passes]
    assert len(lines) - 1 == sum(len(fp.t) for fp in passes)
    assert text.endswith("\n") and "-0.000000" not in text


def test_csv_values_parse_back(plan):
    rows = list(csv.DictReader(io.StringIO(job_csv_text(plan))))
    k = 0
    for layer in plan.layers:
        for fp in layer.passes:
            block = rows[k:k + len(fp.t)]
            k += len(fp.t)
            assert {r["kind"] for r in block} == {fp.kind.value}
            assert [int(r["i"]) for r in block] == list(range(len(fp.t)))
            assert {(int(r["layer"]), int(r["circuit"]), int(r["pass"])) for r in block} == \
                {(fp.layer, fp.circuit, fp.number)}
            num = np.array([[float(r[c]) for c in ("t", "theta_deg", "x", "y", "z", "alpha_deg")] for r in block])
            truth = np.column_stack([fp.t, np.degrees(fp.theta), fp.points, fp.alpha_deg])
            assert np.abs(num - truth).max() <= HALF_ULP6
            for r in block:  # fixed precision: six decimals everywhere
                assert all(len(r[c].split(".")[1]) == 6 for c in ("t", "theta_deg", "x", "alpha_deg"))
    assert k == len(rows)


def test_csv_theta_unwrapped(plan):
    rows = list(csv.DictReader(io.StringIO(job_csv_text(plan))))
    theta = np.array([float(r["theta_deg"]) for r in rows if r["layer"] == "2"])
    assert theta.max() > 4000.0  # the hoop layer's 14-odd turns, never reduced modulo 360
    assert (np.diff(theta) > 0).all()


def test_csv_deterministic(plan):
    assert job_csv_text(plan) == job_csv_text(plan)


# -- summary ---------------------------------------------------------------------------------------
LAYER_KEYS = {"type", "angle_deg", "requested_angle_deg", "angle_change_deg", "circuits", "pattern",
              "fiber_length_mm", "dwell_start_deg", "dwell_end_deg", "turnaround_radius_mm", "alpha_range_deg",
              "time_s", "coverage", "notes"}
COVERAGE_KEYS = {"covered_fraction", "max_gap_mm", "max_overlap_mm", "min_layers", "max_layers"}


def test_summary_keys_and_values(plan):
    data = json.loads(summary_text(plan))
    assert {"name", "source", "total_fiber_length_mm", "estimated_time_s", "layers"} <= set(data)
    assert data["name"] == "tube-test" and data["source"] == "tests/tube.yaml"
    assert data["total_fiber_length_mm"] == pytest.approx(plan.total_fiber_length_mm, abs=5e-4)
    assert data["estimated_time_s"] == pytest.approx(2 * 123.456789, abs=5e-3)
    assert len(data["layers"]) == 2
    for entry, layer in zip(data["layers"], plan.layers):
        assert LAYER_KEYS <= set(entry)
        assert COVERAGE_KEYS <= set(entry["coverage"])
        assert entry["type"] == layer.type.value
        assert entry["circuits"] == layer.circuits and entry["pattern"] == layer.pattern
        assert entry["angle_change_deg"] == pytest.approx(0.25)
        assert entry["fiber_length_mm"] == pytest.approx(layer.fiber_length_mm, abs=5e-4)
        assert entry["turnaround_radius_mm"] is None
        assert entry["coverage"]["covered_fraction"] == 0.987654
        assert entry["coverage"]["max_gap_mm"] == 1.235
        assert entry["alpha_range_deg"] == [round(layer.alpha_min_deg, 4), round(layer.alpha_max_deg, 4)]
        assert entry["notes"] == ["a note"]


def test_summary_text_stable_and_sorted(plan):
    text = summary_text(plan)
    assert text == summary_text(plan) and text.endswith("\n")
    assert text == json.dumps(json.loads(text), sort_keys=True, indent=2) + "\n"
    assert summary_dict(plan)["layers"][0]["time_s"] == 123.46
    for word in ("seconds", "timestamp", "NaN", "Infinity"):
        assert word not in text


def test_summary_not_finite_is_null(plan):
    from dataclasses import replace  # noqa: PLC0415
    layer = replace(plan.layers[0], coverage=replace(plan.layers[0].coverage, max_gap_mm=float("nan")),
                    turnaround_radius=37.12345678)
    data = json.loads(summary_text(replace(plan, layers=(layer,))))
    assert data["layers"][0]["coverage"]["max_gap_mm"] is None
    assert data["layers"][0]["turnaround_radius_mm"] == 37.123


def test_axis_travel_is_the_programs_range_as_written():
    """axis_travel: each axis's [least, largest] over the program's rows, at the program's decimals."""
    from winder.config.machine import MachineConfig  # noqa: PLC0415
    from winder.export.gcode import gcode_text  # noqa: PLC0415

    tube = surface_of(LineAxis(300.0), ConstantProfile(40.0))
    plan = cylinder_plan(tube)
    machine = MachineConfig(eye_clearance=20.0)
    rows = np.array([[float(w[1:]) for w in line.split()[1:5]] for line in gcode_text(plan, machine).splitlines()
                     if line.startswith("G1 ")])
    travel = summary_dict(plan, machine)["axis_travel"]
    assert list(travel) == ["carriage", "rotation", "cross_feed", "yaw"]
    for k, axis in enumerate(travel):
        assert travel[axis] == [rows[:, k].min(), rows[:, k].max()]
    assert travel["cross_feed"] == [60.0, 60.0]  # R + clearance on a cylinder

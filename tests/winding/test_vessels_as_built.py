"""Vessels as built (docs/math/17-vessels-as-built.md): a closed end, unequal bosses and a tank of 30 layers
plan, and each dome is covered by the helicals down to its own turnaround, measured from the job CSV that
`winder run` writes (the radius of its points, per dome), not from the planner's numbers.

In the suite: a small vessel with a closed end and an unequal boss. Nightly (WINDER_NIGHTLY=1): the three
vessels of parts/ (breathing_air, motor_case_12in, tank_700bar), each within 20 s of CPU and 1.5 GB.
"""

from __future__ import annotations

import csv
import json
import os
import resource
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
PARTS = ROOT / "parts"
RADIUS_TOL = 0.01  # mm: the CSV's least radius on a dome vs the turnaround (the CSV prints 6 decimals)
FLOOR_TOL = 1e-3  # mm: slip auto turns this close outside a dome's opening plus half a band
CPU_S = 20.0
PEAK_KB = 1.5e6

SMALL = """name: small
mandrel:
  profile:
    type: vessel
    radius: 60
    cylinder_length: 150
    dome: {type: ellipsoid, polar_opening: 12, depth: 40}
    end_dome: {type: torispherical, crown_radius: 120, knuckle_radius: 12, polar_opening: 0, shaft_radius: 8}
winding:
  band_width: 6
  points: 30
  material: {ply_thickness: 0.3}
  layers:
    - {type: helical, angle: 12, slip: auto}
    - {type: hoop, passes: 2, taper: 6}
    - {type: helical, angle: 24, slip: auto}
"""


def _run(config: Path, out: Path) -> tuple[dict, dict[int, dict[str, float]], resource.struct_rusage]:
    """The summary and, per helical layer, the least radius of its CSV points on each dome."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run([sys.executable, "-m", "winder", "run", str(config), "-o", str(out), "--format", "csv"],
                          cwd=ROOT, capture_output=True, text=True, timeout=1800,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    assert done.returncode == 0, done.stderr
    summary = json.loads(next(out.glob("*.summary.json")).read_text())
    least: dict[int, dict[str, float]] = {}
    mid = None
    with open(next(out.glob("*.csv")), newline="") as fh:
        rows = list(csv.DictReader(fh))
    t = np.array([float(r["t"]) for r in rows])
    mid = 0.5 * (t.min() + t.max())
    for row, tt in zip(rows, t):
        layer = int(row["layer"])
        r = float(np.hypot(float(row["x"]), float(row["y"])))
        side = "first" if tt < mid else "end"
        least.setdefault(layer, {"first": np.inf, "end": np.inf})
        least[layer][side] = min(least[layer][side], r)
    return summary, least, after


def _covered_to_own_turnaround(summary: dict, least: dict) -> None:
    for layer in summary["layers"]:
        if layer["type"] != "helical":
            continue
        first, end = layer["turnaround_radii_mm"]
        got = least[layer["index"]]
        assert got["first"] == pytest.approx(first, abs=RADIUS_TOL), layer["index"]
        assert got["end"] == pytest.approx(end, abs=RADIUS_TOL), layer["index"]


def test_closed_end_and_unequal_boss_each_dome_its_own_turnaround(tmp_path):
    config = tmp_path / "small.yaml"
    config.write_text(SMALL, encoding="utf-8")
    summary, least, _ = _run(config, tmp_path)
    _covered_to_own_turnaround(summary, least)
    first = summary["layers"][0]
    # the lowest helical down to each dome's own floor: the neck 12 + 3, the shaft 8 + 3
    assert first["turnaround_radii_mm"] == pytest.approx([15.0, 11.0], abs=FLOOR_TOL)
    assert least[1]["first"] == pytest.approx(15.0, abs=RADIUS_TOL)
    assert least[1]["end"] == pytest.approx(11.0, abs=RADIUS_TOL)
    assert all(layer["coverage"]["covered_fraction"] >= 0.999 for layer in summary["layers"])


NIGHTLY = os.environ.get("WINDER_NIGHTLY") == "1"


@pytest.mark.skipif(not NIGHTLY, reason="a minute of CPU: WINDER_NIGHTLY=1 runs it")
@pytest.mark.parametrize("name, floors", [("breathing_air", (18.0, 14.0)), ("motor_case_12in", (44.0, 86.0)),
                                          ("tank_700bar", (34.0, 30.0))])
def test_vessel_parts_plan_each_dome_covered(tmp_path, name, floors):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    summary, least, after = _run(PARTS / f"{name}.yaml", tmp_path)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    assert cpu <= CPU_S, cpu
    assert after.ru_maxrss <= PEAK_KB
    _covered_to_own_turnaround(summary, least)
    lowest = min(least.values(), key=lambda d: d["first"])
    assert lowest["first"] == pytest.approx(floors[0], abs=RADIUS_TOL)
    assert min(d["end"] for d in least.values()) == pytest.approx(floors[1], abs=RADIUS_TOL)
    assert all(layer["coverage"]["covered_fraction"] >= 0.999 for layer in summary["layers"])

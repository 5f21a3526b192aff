"""Parts nobody tuned for (tests/part_generator.py): every generated part plans with every invariant
proved, or is refused for a physical reason that names the key to change. A numerical refusal (no
convergence, an integral that did not settle, an iteration limit) is a defect, never an outcome.

The suite runs SUITE_COUNT small parts, the classes in turn (a few minutes). Nightly, the ranges as
shops wind them: `WINDER_NIGHTLY=1 WINDER_GENERATED=1000 .venv/bin/python -m pytest -q
tests/test_generated_parts.py` (WINDER_GENERATED parts, default 1000; WINDER_GENERATED_SEED the first
seed, default 0). `python -m bench --parts N` runs the same parts in fresh processes and tables them
per class with their CPU time and peak memory.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
import yaml

from part_generator import NIGHTLY, SUITE, outcome, parts
from winder.app.jobs import run_job

SUITE_COUNT = 42  # seven of each class
# The suite's parts that meet a defect of winder not mended yet: (class, seed) -> what and whose. They
# are expected to fail (not strictly: the day one plans, the entry goes).
KNOWN = {
    ("tube", 6): "invariant: midpoints 0.26 mm off the tangent, 70.5 deg over 7.5 mm corners (issue 41 item 1)",
    ("duct", 4): "the eye at a dwell round a spline duct's end cuts 2.6 mm into the mandrel (eye planning)",
}
NIGHTLY_RUN = os.environ.get("WINDER_NIGHTLY") == "1"
COUNT = int(os.environ.get("WINDER_GENERATED", "1000")) if NIGHTLY_RUN else SUITE_COUNT
FIRST_SEED = int(os.environ.get("WINDER_GENERATED_SEED", "0"))
DRAWN = parts(COUNT, FIRST_SEED, NIGHTLY if NIGHTLY_RUN else SUITE)


def run_generated(config: dict, folder: Path):
    """Run one generated part as `winder run` does: (report, summary dict or None)."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{config['name']}.yaml"
    path.write_text(yaml.safe_dump(config, sort_keys=False), encoding="utf-8")
    report = run_job(path, folder / "out", formats=("gcode",))
    summary = folder / "out" / f"{config['name']}.summary.json"
    return report, (json.loads(summary.read_text(encoding="utf-8")) if report.ok else None)


@pytest.mark.parametrize("cls, seed, config", DRAWN, ids=[f"{c}_{s}" for c, s, _ in DRAWN])
def test_generated_part_plans_or_is_refused_physically(cls, seed, config, tmp_path):
    report, summary = run_generated(config, tmp_path)
    kind = outcome(report.ok, report.message)
    if kind not in ("planned", "physical") and (cls, seed) in KNOWN and not NIGHTLY_RUN:
        pytest.xfail(KNOWN[(cls, seed)])
    assert kind in ("planned", "physical"), f"{cls} seed {seed}: {kind}: {report.message}\n{yaml.safe_dump(config)}"
    if kind == "planned":
        block = summary["invariants"]
        tol = 0.05  # machine.chord_tolerance's default: the generator leaves it
        assert block["min_covered_fraction"] >= 0.999
        assert block["max_point_deviation_mm"] <= tol and block["max_midpoint_deviation_mm"] <= tol
        assert block["min_clearance_mm"] >= config["machine"]["eye"]["clearance"] - tol

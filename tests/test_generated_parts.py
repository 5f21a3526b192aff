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
    # its dwell mended (the eye's lead a false root next to the contact point, 2.6 mm inside the mandrel):
    # on a return pass the first crossing of the fiber line with the envelope jumps from 63.4 to 78.4 mm
    # between two dense poses, where the line grazes the envelope over the spline's first leg (reaching
    # 0.095 mm past it, one dense pose on 0.079 mm short) and then runs past the start; their chord cuts in
    ("duct", 4): "a return pass's eye jumps where its fiber line grazes the envelope (its first crossing "
                 "63.4 mm, then 78.4): the move comes within 11.680 mm of 11.950 (eye planning)",
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

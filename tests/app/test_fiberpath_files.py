"""fiberpath's own examples (the folder WINDER_FIBERPATH_EXAMPLES names, which .ci/run sets: each X.wind beside a hand-written X.yaml of the same
job) through `winder run X.wind`, `fiberpath simulate` and `winder patterns X.wind`.

The examples are fiberpath's (AGPL): they are read where they lie, never copied; the tests skip, saying
why, where the folder (WINDER_FIBERPATH_EXAMPLES) or fiberpath itself (WINDER_FIBERPATH, else on PATH or
beside this Python) is missing.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from winder.cli import main
from winder.config.job import load_config
from winder.winding.plan import plan

ROOT = Path(__file__).resolve().parents[2]
_FOLDER = os.environ.get("WINDER_FIBERPATH_EXAMPLES")
EXAMPLES = Path(_FOLDER) if _FOLDER and Path(_FOLDER).is_dir() else None
NAMES = sorted(p.stem for p in EXAMPLES.glob("*.wind") if p.with_suffix(".yaml").exists()) if EXAMPLES else []
_EXE = [os.environ.get("WINDER_FIBERPATH"), shutil.which("fiberpath"), str(Path(sys.executable).parent / "fiberpath")]
FIBERPATH = next((p for p in _EXE if p and Path(p).exists()), None)
ANGLE_TOL = 0.01  # deg
LENGTH_RTOL = 1e-3  # the 0.1 %

pytestmark = pytest.mark.skipif(not NAMES, reason="fiberpath's examples not found: set WINDER_FIBERPATH_EXAMPLES to their folder")
needs_fiberpath = pytest.mark.skipif(FIBERPATH is None, reason="fiberpath is not installed (the bench extra)")


def _cli(*args: str):
    result = CliRunner().invoke(main, list(args))
    assert result.exit_code == 0, result.output
    return result


@pytest.mark.parametrize("name", NAMES)
def test_the_wind_file_runs_to_the_plan_of_its_yaml_and_fiberpath_reads_the_program(name, tmp_path):
    _cli("run", str(EXAMPLES / f"{name}.wind"), "-o", str(tmp_path), "--format", "gcode")
    summary = json.loads((tmp_path / f"{name}.summary.json").read_text(encoding="utf-8"))
    mine = plan(load_config(EXAMPLES / f"{name}.yaml"))
    assert len(summary["layers"]) == len(mine.layers)
    for got, want in zip(summary["layers"], mine.layers):
        assert got["circuits"] == want.circuits and got["type"] == want.type.value
        assert abs(got["angle_deg"] - want.angle_deg) <= ANGLE_TOL
        assert math.isclose(got["fiber_length_mm"], want.fiber_length_mm, rel_tol=LENGTH_RTOL)
    program = tmp_path / f"{name}.gcode"
    assert program.read_text(encoding="utf-8").startswith("; Parameters ")  # the marlin dialect
    if FIBERPATH is None:
        pytest.skip("fiberpath is not installed (the bench extra): the program was not read by it")
    done = subprocess.run([FIBERPATH, "simulate", "--json", str(program)], capture_output=True, text=True,
                          timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    sim = json.loads(done.stdout)
    assert sim["moves"] > 0 and sim["tow_length_mm"] > 0.0


_COUNTS: dict[str, int] = {}  # fiberpath's count per helical layer (its JSON): examples repeat their layers


def _fiberpath_circuits(name: str, tmp_path: Path) -> list[int]:
    """Circuits per helical layer of fiberpath's own plan: the `Circuit:` comments of its program for a job
    of that layer alone (a temporary .wind, never kept)."""
    job = json.loads((EXAMPLES / f"{name}.wind").read_text(encoding="utf-8"))
    counts = []
    for layer in job["layers"]:
        if layer.get("windType") != "helical":
            continue
        key = json.dumps([job["mandrelParameters"], job["towParameters"], layer], sort_keys=True)
        if key not in _COUNTS:
            one, out = tmp_path / "one.wind", tmp_path / "fiberpath.gcode"
            one.write_text(json.dumps({**job, "layers": [layer]}), encoding="utf-8")
            done = subprocess.run([FIBERPATH, "plan", str(one), "-o", str(out)], capture_output=True, text=True,
                                  timeout=300, check=False)
            assert done.returncode == 0, done.stderr
            _COUNTS[key] = len(re.findall(r"Circuit: \d+/\d+", out.read_text(encoding="utf-8")))
        counts.append(_COUNTS[key])
    return counts


@needs_fiberpath
@pytest.mark.parametrize("name", NAMES)
def test_patterns_lists_fiberpaths_circuit_count(name, tmp_path):
    theirs = _fiberpath_circuits(name, tmp_path)
    if not theirs:
        pytest.skip(f"{name} has no helical layer")
    rows = json.loads(_cli("patterns", str(EXAMPLES / f"{name}.wind"), "--json").stdout)
    layers = sorted({row["layer"] for row in rows})
    assert len(layers) == len(theirs)
    for layer, count in zip(layers, theirs):
        listed = {row["circuits"] for row in rows if row["layer"] == layer}
        assert count in listed, (layer, count, sorted(listed))
        assert sum(row["chosen"] for row in rows if row["layer"] == layer) == 1

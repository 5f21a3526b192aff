"""Hostile reference folders for `regress` (issue 34): each made from the pipe sample's reference by one
edit; regress reads them into readable differences (exit 1, one Error line), never an internal error,
and never reads a reference file past its size limit."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tests.sandbox import run_limited
from winder.app.jobs import run_job

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "pipe.yaml"
REFERENCE = ROOT / "samples" / "reference" / "pipe"
HANG_GUARD_S = 120


def _folder(tmp_path: Path, name: str) -> Path:
    folder = tmp_path / name
    ref = folder / "reference" / "pipe"
    ref.parent.mkdir(parents=True)
    shutil.copy(SAMPLE, folder / "pipe.yaml")
    shutil.copytree(REFERENCE, ref)
    if name == "csv_0e999":
        lines = (ref / "pipe.csv").read_text().splitlines()
        cells = lines[1].split(",")
        k = next(j for j, cell in enumerate(cells) if j > 3 and cell.replace(".", "").strip("-0"))  # not zero
        lines[1] = ",".join(cells[:k] + ["0.0e999"] + cells[k + 1:])
        (ref / "pipe.csv").write_text("\n".join(lines) + "\n")
    elif name == "gcode_z0e999":
        text = (ref / "pipe.gcode").read_text()
        (ref / "pipe.gcode").write_text(text.replace("Z70.000", "Z0e999", 1))
    elif name == "ply_property_twice":
        assert run_job(SAMPLE, ref, formats=("ply",), source="pipe.yaml").ok
        data = (ref / "pipe.ply").read_bytes()
        (ref / "pipe.ply").write_bytes(data.replace(b"property float y\n", b"property float x\n", 1))
    elif name == "gcode_3gb":
        with open(ref / "pipe.gcode", "r+b") as fh:  # sparse: no 3 GB on the disk
            fh.truncate(3 * 1024**3)
    elif name == "csv_20x":  # far past its output's size, far below the absolute limit
        with open(ref / "pipe.csv", "r+b") as fh:
            fh.truncate(20 * (ref / "pipe.csv").stat().st_size + 2_000_000)
    return folder


CASES = {"csv_20x": "pipe.csv", "csv_0e999": "pipe.csv", "gcode_z0e999": "pipe.gcode", "ply_property_twice": "pipe.ply",
         "gcode_3gb": "pipe.gcode"}


@pytest.mark.parametrize("name", sorted(CASES))
def test_tampered_reference_is_a_readable_difference(tmp_path: Path, name: str) -> None:
    folder = _folder(tmp_path, name)
    (result,), = run_limited([[["regress", str(folder)]]], seconds=HANG_GUARD_S)
    assert result["uncaught"] is None and "internal error" not in result["stderr"], result
    assert result["code"] == 1, result
    errors = [line for line in result["stderr"].splitlines() if line.startswith("Error:")]
    assert len(errors) == 1 and CASES[name] in errors[0], result["stderr"]
    assert result["peak_mb"] < 2048
    if name in ("csv_20x", "gcode_3gb"):
        assert "not read" in result["stdout"], result["stdout"]

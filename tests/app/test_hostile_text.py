"""Hostile input, third round (issue 45): a config's path reaches the programs' comments as one comment.

The G-code header names the config (`; source: ...`); a path holding line breaks and parentheses must
not end the comment or start a line of words (winder.escape.gcode_comment). The program is read back
by rs274 (LinuxCNC's own reader) where it is installed."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from tests.configs import tiny_pipe
from winder.app.jobs import run_job

NAMES = ["a)\nG0 X999 (b.yaml", "c\rG1 Z-50\r;.yaml", "d\u2028G0 X777\u2028.yaml", "e\x85G0 Y1.yaml"]


@pytest.mark.parametrize("name", NAMES)
def test_a_config_path_stays_inside_its_comment(tmp_path: Path, name: str) -> None:
    config = tmp_path / name
    config.write_text(tiny_pipe("t", 45, "machine:\n  axes: {carriage: X, rotation: A, cross_feed: Z, yaw: B}\n"
                                "  eye: {clearance: 20}\n  feed: 3000\n  chord_tolerance: 0.05\n"
                                "  limits: {carriage: [-500, 800], cross_feed: [0, 300], yaw: [-90, 90]}\n"),
                      encoding="utf-8")
    report = run_job(config, tmp_path / "out", formats=("gcode",))
    assert report.ok, report.message
    lines = (tmp_path / "out" / "t.gcode").read_text(encoding="utf-8").split("\n")
    source = [line for line in lines if line.startswith("; source:")]
    assert len(source) == 1 and "(" not in source[0] and ")" not in source[0]
    words = [line for line in lines if line and not line.startswith(";")]
    assert not any(w.startswith(("G0 X999", "G1 Z-50", "G0 X777", "G0 Y1")) for w in words)
    if shutil.which("rs274") is None:
        pytest.skip("rs274 (LinuxCNC) not installed")
    res = subprocess.run(["rs274", "-g", str(tmp_path / "out" / "t.gcode")], capture_output=True, text=True,
                         timeout=120, input="")
    assert "X999" not in res.stdout and "Z-50" not in res.stdout.split("COMMENT")[0]

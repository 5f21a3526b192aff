"""Hostile input, third round (issue 45): refusals made up front (exit 2) and messages that name their
real cause: a robot language the config cannot be written in, options with digit separators or other
scripts' digits, fiberpath schema versions that are no version."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.configs import tiny_pipe
from winder.app.jobs import run_job
from winder.cli import main

ROOT = Path(__file__).resolve().parents[2]
PIPE = ROOT / "samples" / "pipe.yaml"
UP_FRONT_S = 20.0  # well below planning the pipe sample on a busy machine; the refusal needs no plan
CELL = """\
name: {name}
mandrel:
  axis: {{type: arc, radius: 150, angle: 90}}
  profile: {{type: constant, radius: 40}}
winding:
  band_width: 10
  points: 30
  layers:
    - {{type: helical, angle: 45}}
machine:
  robot: {{arm: {arm}}}
"""


def _invoke(args: list[str]) -> tuple[int, list[str]]:
    result = CliRunner().invoke(main, args)
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    return result.exit_code, [line for line in result.stderr.splitlines() if line.startswith("Error:")]


@pytest.mark.parametrize("fmt", ["krl", "rapid", "urscript"])
def test_a_robot_language_without_a_cell_is_refused_before_planning(tmp_path: Path, fmt: str) -> None:
    started = time.perf_counter()
    report = run_job(PIPE, tmp_path / "out", formats=(fmt,))
    assert report.exit_code == 2 and "machine.robot: --format " + fmt + " needs a robot cell" in report.message
    assert report.layers == 0 and time.perf_counter() - started < UP_FRONT_S  # nothing planned
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(("name", "arm", "fmt", "key"), [("elbow-90", "kuka_kr16", None, "name: KRL needs a module name"),
                                                         ("elbow", "kuka_kr16", "urscript", "machine.robot.arm: URScript"),
                                                         ("e" * 30, "kuka_kr16", None, "at most 24 characters")])
def test_what_a_cell_cannot_write_is_refused_by_check(tmp_path: Path, name: str, arm: str, fmt, key: str) -> None:
    config = tmp_path / "cell.yaml"
    config.write_text(CELL.format(name=name, arm=arm), encoding="utf-8")
    if fmt is None:  # the cell's own language: check knows it
        code, errors = _invoke(["check", str(config)])
        assert code == 2 and len(errors) == 1 and key in errors[0], errors
    report = run_job(config, tmp_path / "out", formats=(fmt,) if fmt else ("csv", "krl"))
    assert report.exit_code == 2 and key in report.message, report.message


@pytest.mark.parametrize("args", [["patterns", str(PIPE), "--angle", "1_0"], ["patterns", str(PIPE), "--layer", "\u0661"],
                                  ["patterns", str(PIPE), "--angle", "\u0664\u0665"],
                                  ["geodesic", str(PIPE), "--start", "10,0", "--end", "400,90", "--rounds", "1_0"],
                                  ["geodesic", str(PIPE), "--start", "1\u0660,0", "--end", "400,90"],
                                  ["run", str(PIPE), "--time-limit", "6_0"], ["check", str(PIPE), "--time-limit", "1_0"]])
def test_numbers_python_reads_but_a_user_does_not_mean_are_refused(args: list[str]) -> None:
    code, errors = _invoke(args)
    assert code == 2 and len(errors) == 1, errors
    assert "is not a plain number" in errors[0] or "expected T,DEG" in errors[0], errors


@pytest.mark.parametrize("version", ["1.", "1." + "9" * 100_000, "1.\u0663", "\u0661.0", "1.0.0", "2.0", "1.00000"])
def test_schema_versions_that_are_no_version_are_refused(tmp_path: Path, version: str) -> None:
    job = {"schemaVersion": version, "mandrelParameters": {"diameter": 100, "windLength": 400},
           "towParameters": {"width": 8, "thickness": 0.4}, "defaultFeedRate": 6000,
           "layers": [{"windType": "hoop", "terminal": False}]}
    path = tmp_path / "v.wind"
    path.write_text(json.dumps(job), encoding="utf-8")
    code, errors = _invoke(["check", str(path)])
    assert code == 2 and len(errors) == 1 and "schemaVersion: must be a 1.x version string" in errors[0], errors
    assert len(errors[0]) < 400  # the value shown cut short


def test_a_plain_config_still_checks(tmp_path: Path) -> None:
    config = tmp_path / "t.yaml"
    config.write_text(tiny_pipe(), encoding="utf-8")
    assert _invoke(["check", str(config)]) == (0, [])

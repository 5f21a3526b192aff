"""`winder patterns` on the command line (docs/guide/commands.md): the JSON fields, the
table, and its refusals (one Error line, exit 2)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from winder.cli import main

ROOT = Path(__file__).resolve().parents[2]
PIPE = ROOT / "samples" / "pipe.yaml"
SPEC_KEYS = {"circuits", "pattern", "angle_deg", "covered_fraction", "max_layers", "fiber_length_mm", "time_s",
             "max_slip", "chosen", "yaml"}


def test_json_has_the_spec_fields_and_one_chosen_row():
    result = CliRunner().invoke(main, ["patterns", str(PIPE), "--json"])
    assert result.exit_code == 0, result.output
    rows = json.loads(result.stdout)
    assert rows and all(SPEC_KEYS <= set(row) for row in rows)
    chosen = [row for row in rows if row["chosen"]]
    assert len(chosen) == 1 and chosen[0]["yaml"] == "{type: helical, angle: 55, circuits: 19, pattern: 13}"
    assert all(row["layer"] == 1 for row in rows)


def test_the_table_marks_the_planners_choice_and_says_its_rule():
    result = CliRunner().invoke(main, ["patterns", str(PIPE), "--layer", "1", "--angle", "50"])
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0].startswith("layer 1: helical at 50 deg") and lines[1].startswith("sorted by: complete coverage")
    starred = [line for line in lines if line.startswith("*")]
    assert len(starred) == 1 and starred[0].endswith("}") and "angle: 50," in starred[0]


@pytest.mark.parametrize("args,expected", [
    (["--layer", "2"], "--layer: layer 2 of"),
    (["--layer", "3"], "--layer: "),
    (["--angle", "90"], "--angle"),
    (["--within", "-1"], "--within"),
])
def test_refusals_are_one_line_exit_2(args, expected):
    result = CliRunner().invoke(main, ["patterns", str(PIPE), *args])
    lines = result.stderr.splitlines()
    assert result.exit_code == 2 and len(lines) == 1 and lines[0].startswith("Error: ") and expected in lines[0]


def test_a_job_without_helical_layers_is_refused(tmp_path):
    config = tmp_path / "hoops.yaml"
    config.write_text("name: hoops\nmandrel:\n  axis: {type: line, length: 300}\n  profile: {type: constant, "
                      "radius: 40}\nwinding:\n  band_width: 8\n  layers:\n    - {type: hoop}\n", encoding="utf-8")
    result = CliRunner().invoke(main, ["patterns", str(config)])
    assert result.exit_code == 2 and "no helical layer" in result.stderr

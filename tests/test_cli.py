"""The command line (docs/guide/commands.md): geodesic, check, run, regress, through click's CliRunner.

Exit status: 0 success; 2 bad usage or an invalid config; 1 a job that could not be computed. Every
error is one line starting with `Error:`; never a traceback.
"""

from __future__ import annotations

import csv
import io
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

from tests.configs import TINY_PIPE
from winder.cli import main

ROOT = Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "samples"
INVALID = ROOT / "tests" / "config" / "invalid"
PIPE = SAMPLES / "pipe.yaml"
ELBOW = SAMPLES / "elbow.yaml"

# A 90 deg elbow (bend radius 150, tube 40) wound geodesically at 20 deg: the fiber bridges at the
# inside of the bend, where no friction holds it below 31.1 deg. Valid YAML and values, but no winding
# exists (exit 1, not 2). (A vessel angle whose turnaround falls inside the polar opening is refused as
# invalid by check, exit 2: tests/config/invalid/vessel_angle_inside_opening.yaml.)
INFEASIBLE = """\
name: {name}
mandrel:
  axis:
    type: path
    segments:
      - line: 100
      - arc: {{radius: 150, angle: 90, toward: 0}}
      - line: 100
  profile: {{type: constant, radius: 40}}
winding:
  band_width: 10
  points: 8
  layers:
    - {{type: helical, angle: 20}}
"""

SPEC_JSON_KEYS = {"length_mm", "polyline_length_mm", "length_extrapolated_mm", "error_estimate_mm", "points",
                  "iterations", "converged", "method", "seconds"}


def invoke(*args: object):
    result = CliRunner().invoke(main, [str(a) for a in args])
    assert "Traceback" not in result.output, result.output
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result


def error_lines(result) -> list[str]:
    return [line for line in result.stderr.splitlines() if line.startswith("Error:")]


def tiny(tmp_path: Path, name: str = "tiny", template: str = TINY_PIPE, machine: str = "") -> Path:
    path = tmp_path / f"{name}.yaml"
    path.write_text(template.format(name=name, machine=machine, angle=45), encoding="utf-8")
    return path


def files_of(folder: Path) -> set[str]:
    return {p.name for p in folder.iterdir()} if folder.exists() else set()


# -- geodesic --------------------------------------------------------------------------------------
def test_geodesic_csv_columns(tmp_path):
    out = tmp_path / "path.csv"
    result = invoke("geodesic", PIPE, "--start", "20,0", "--end", "480,90", "--points", 10, "-o", out)
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    assert list(rows[0])[:6] == ["i", "t", "theta_deg", "x", "y", "z"]
    assert len(rows) == 12  # the two end points and 10 intermediate ones
    assert [int(r["i"]) for r in rows] == list(range(12))
    assert float(rows[0]["t"]) == pytest.approx(20.0) and float(rows[-1]["t"]) == pytest.approx(480.0)
    assert float(rows[-1]["theta_deg"]) == pytest.approx(90.0)
    assert float(rows[0]["x"]) == pytest.approx(50.0)  # (r cos 0, r sin 0, t) on the straight pipe


def test_geodesic_json_has_spec_keys():
    result = invoke("geodesic", PIPE, "--start", "20,0", "--end", "480,90", "--points", 20, "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert SPEC_JSON_KEYS <= set(data)
    assert data["converged"] is True and data["method"] == "newton" and data["points"] == 20
    # a helix on a cylinder: sqrt(460^2 + (50 pi / 2)^2)
    assert data["length_mm"] == pytest.approx(math.hypot(460.0, 50.0 * math.pi / 2), rel=1e-6)


def test_geodesic_rounds_unwrap_theta(tmp_path):
    out = tmp_path / "path.csv"
    base = json.loads(invoke("geodesic", PIPE, "--start", "20,0", "--end", "480,90", "--points", 30,
                             "--json").stdout)
    result = invoke("geodesic", PIPE, "--start", "20,0", "--end", "480,90", "--rounds", 2, "--points", 30,
                    "-o", out, "--json")
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    assert float(rows[-1]["theta_deg"]) == pytest.approx(90.0 + 720.0)
    thetas = [float(r["theta_deg"]) for r in rows]
    assert all(b > a for a, b in zip(thetas, thetas[1:]))  # continuous, never reduced mod 360
    length = json.loads(result.stdout)["length_mm"]
    assert length == pytest.approx(math.hypot(460.0, 50.0 * math.radians(810.0)), rel=1e-6)  # a helix
    assert length > base["length_mm"]


def test_geodesic_tolerance_refines():
    result = invoke("geodesic", ELBOW, "--start", "0,0", "--end", "300,90", "--tolerance", "0.01", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["converged"] is True
    assert data["smooth_error_estimate_mm"] < 0.01  # the bound on the reported length's error


def test_cli_option_constants_match_the_library():
    """cli.py writes them out so that --help imports no numpy; they must stay the library's."""
    from winder import cli  # noqa: PLC0415
    from winder.config.winding import DEFAULT_POINTS  # noqa: PLC0415
    from winder.paths.geodesic import Method  # noqa: PLC0415

    assert cli.DEFAULT_POINTS == DEFAULT_POINTS
    assert cli.METHODS == tuple(m.value for m in Method)


@pytest.mark.parametrize("command", ["geodesic", "run", "report", "check", "regress", "simulate"])
def test_every_command_help_says_what_its_exit_status_means(command):
    text = " ".join(invoke(command, "--help").stdout.split())
    assert re.search(r"Exit status( as for run)?: 0 ", text), text
    assert "--method" not in text or "the paper's" in text  # geodesic's --method says what lbfgs is


def test_run_help_and_readme_name_every_format_run_accepts():
    from winder.export.registry import SELECTABLE  # noqa: PLC0415

    shown = "|".join(SELECTABLE)  # csv|gcode|ply|layup|report: --format layup is docs/guide/conventions.md's
    assert f"--format {shown}" in invoke("run", "--help").stdout
    assert f"[--format {shown} ...]" in (ROOT / "docs" / "guide" / "commands.md").read_text(encoding="utf-8")


def test_geodesic_text_output():
    result = invoke("geodesic", PIPE, "--start", "20,0", "--end", "480,90", "--points", 10)
    assert result.exit_code == 0, result.output
    assert "geodesic length" in result.stdout and "pipe" in result.stdout


@pytest.mark.parametrize("start", ["abc", "1,2,3", "10", "nan,0", "10,inf", "10,x"])
def test_geodesic_bad_start_is_usage_error(start):
    result = invoke("geodesic", PIPE, "--start", start, "--end", "480,90", "--points", 10)
    assert result.exit_code == 2
    lines = error_lines(result)
    assert len(lines) == 1 and "--start" in lines[0]


def test_geodesic_start_off_the_mandrel():
    result = invoke("geodesic", PIPE, "--start", "-5,0", "--end", "480,90", "--points", 10)
    assert result.exit_code == 2
    assert error_lines(result)


def test_geodesic_invalid_config_names_the_file():
    bad = INVALID / "bad_radius.yaml"
    result = invoke("geodesic", bad, "--start", "0,0", "--end", "10,90")
    assert result.exit_code == 2
    lines = error_lines(result)
    assert len(lines) == 1 and "bad_radius.yaml" in lines[0]


def test_geodesic_missing_config():
    result = invoke("geodesic", ROOT / "no_such_file.yaml", "--start", "0,0", "--end", "10,90")
    assert result.exit_code == 2
    assert "no_such_file.yaml" in error_lines(result)[0]


def test_geodesic_points_and_tolerance_refused():
    result = invoke("geodesic", PIPE, "--start", "20,0", "--end", "480,90", "--points", 10,
                    "--tolerance", "0.1")
    assert result.exit_code == 2
    lines = error_lines(result)
    assert len(lines) == 1 and "--points" in lines[0] and "--tolerance" in lines[0]


# -- check -----------------------------------------------------------------------------------------
def test_check_ok():
    configs = sorted(SAMPLES.glob("*.yaml"))
    result = invoke("check", *configs)
    assert result.exit_code == 0, result.output
    assert result.stdout.count("ok:") == len(configs)
    assert not result.stderr


def test_check_bad_and_mixed():
    bad = [INVALID / "nan_radius.yaml", INVALID / "unknown_top_key.yaml"]
    result = invoke("check", PIPE, *bad)
    assert result.exit_code == 2
    assert "ok: " in result.stdout and "pipe" in result.stdout
    lines = error_lines(result)
    assert len(lines) == 2
    assert "nan_radius.yaml" in lines[0] and "unknown_top_key.yaml" in lines[1]


def test_check_refuses_two_jobs_of_one_name_as_a_batch_run_does(tmp_path):
    twin = tmp_path / "pipe.yaml"
    shutil.copy(PIPE, twin)
    checked = invoke("check", PIPE, twin)
    run = invoke("run", PIPE, twin, "-o", tmp_path / "out")
    assert checked.exit_code == run.exit_code == 2
    (line,) = error_lines(checked)
    assert line.startswith(f"Error: {twin}: name: 'pipe' is also the name of {PIPE} in this batch")
    assert invoke("check", twin).exit_code == 0  # alone it is fine


def test_check_every_invalid_config_is_refused():
    configs = sorted(INVALID.glob("*.yaml"))
    result = invoke("check", *configs)
    assert result.exit_code == 2
    assert "ok:" not in result.stdout
    assert len(error_lines(result)) == len(configs)
    assert "internal error" not in result.output


# -- run -------------------------------------------------------------------------------------------
def test_run_writes_all_outputs(tmp_path):
    config = tiny(tmp_path)
    out = tmp_path / "out"
    result = invoke("run", config, "-o", out)
    assert result.exit_code == 0, result.output
    assert files_of(out) == {"tiny.csv", "tiny.gcode", "tiny.ply", "tiny.summary.json"}
    summary = json.loads((out / "tiny.summary.json").read_text())
    assert summary["name"] == "tiny" and summary["total_fiber_length_mm"] > 0
    layer = summary["layers"][0]
    assert {"type", "angle_deg", "circuits", "pattern", "fiber_length_mm", "coverage"} <= set(layer)
    assert {"covered_fraction", "max_gap_mm"} <= set(layer["coverage"])
    header = (out / "tiny.csv").read_text().splitlines()[0].split(",")
    assert set("layer,circuit,pass,i,t,theta_deg,x,y,z,alpha_deg".split(",")) <= set(header)
    gcode = (out / "tiny.gcode").read_text()
    for word in ("G21", "G90", "G94", "G1"):
        assert word in gcode
    assert (out / "tiny.ply").read_bytes().startswith(b"ply")
    # the table names the job, its status and its fiber length
    assert "tiny" in result.stdout and "ok" in result.stdout
    assert f"{summary['total_fiber_length_mm']:.3f}" in result.stdout


def test_run_formats(tmp_path):
    config = tiny(tmp_path)
    out = tmp_path / "out"
    result = invoke("run", config, "-o", out, "--format", "csv")
    assert result.exit_code == 0, result.output
    assert files_of(out) == {"tiny.csv", "tiny.summary.json"}
    out2 = tmp_path / "out2"
    result = invoke("run", config, "-o", out2, "--format", "gcode,ply")
    assert result.exit_code == 0, result.output
    assert files_of(out2) == {"tiny.gcode", "tiny.ply", "tiny.summary.json"}


def test_run_bad_format_is_usage_error(tmp_path):
    result = invoke("run", tiny(tmp_path), "-o", tmp_path / "out", "--format", "step")
    assert result.exit_code == 2
    assert "step" in result.output
    assert not (tmp_path / "out").exists()


def test_run_invalid_config_exit_2(tmp_path):
    out = tmp_path / "out"
    result = invoke("run", INVALID / "nan_radius.yaml", "-o", out)
    assert result.exit_code == 2
    lines = error_lines(result)
    assert len(lines) == 1 and "nan_radius.yaml" in lines[0]
    assert files_of(out) == set()


def test_run_config_without_winding_exit_2(tmp_path):
    config = tmp_path / "bare.yaml"
    config.write_text("name: bare\nmandrel:\n  axis: {type: line, length: 100}\n"
                      "  profile: {type: constant, radius: 20}\n")
    result = invoke("run", config, "-o", tmp_path / "out")
    assert result.exit_code == 2
    assert "bare.yaml" in error_lines(result)[0] and "winding" in error_lines(result)[0]
    assert files_of(tmp_path / "out") == set()


def test_run_infeasible_exit_1(tmp_path):
    out = tmp_path / "out"
    result = invoke("run", tiny(tmp_path, "bridging", INFEASIBLE), "-o", out)
    assert result.exit_code == 1, result.output
    lines = error_lines(result)
    assert len(lines) == 1 and "bridging.yaml" in lines[0]
    assert files_of(out) == set()


def test_run_export_error_exit_1_leaves_nothing(tmp_path):
    # A 300 mm pipe on a carriage that travels 50 mm: the G-code exporter refuses the program.
    config = tiny(tmp_path, "short", machine="machine:\n  limits: {carriage: [0, 50]}\n")
    out = tmp_path / "out"
    result = invoke("run", config, "-o", out)
    assert result.exit_code == 1, result.output
    assert "short.yaml" in error_lines(result)[0]
    assert files_of(out) == set()


@pytest.mark.parametrize("jobs", [1, 2])
def test_run_batch_with_broken_configs(tmp_path, jobs):
    good = [tiny(tmp_path, "good1"), tiny(tmp_path, "good2")]
    infeasible = tiny(tmp_path, "bridging", INFEASIBLE)
    invalid = INVALID / "bad_radius.yaml"
    out = tmp_path / "out"
    result = invoke("run", good[0], infeasible, invalid, good[1], "-o", out, "--jobs", jobs)
    assert result.exit_code == 2, result.output  # an invalid config outranks an infeasible one
    lines = error_lines(result)
    assert len(lines) == 2
    assert "bridging.yaml" in lines[0] and "bad_radius.yaml" in lines[1]  # in the order given
    expected = {f"{n}.{ext}" for n in ("good1", "good2") for ext in ("csv", "gcode", "ply", "summary.json")}
    assert files_of(out) == expected  # the others ran; nothing of the failed ones, no temp files
    table = result.stdout
    assert table.index("good1") < table.index("bridging") < table.index("bad_radius") < table.index("good2")
    assert "failed" in table and "invalid" in table
    assert result.output.rstrip("\n").splitlines()[-2:] == lines  # the Error lines last, after the table (issue 49.6)

    result = invoke("run", good[0], infeasible, "-o", tmp_path / "out1", "--jobs", jobs)
    assert result.exit_code == 1, result.output
    assert files_of(tmp_path / "out1") == {f"good1.{ext}" for ext in ("csv", "gcode", "ply", "summary.json")}


def test_run_duplicate_names_refused(tmp_path):
    a = tiny(tmp_path, "same")
    b = tmp_path / "other.yaml"
    b.write_text(a.read_text())
    out = tmp_path / "out"
    result = invoke("run", a, b, "-o", out, "--format", "csv")
    assert result.exit_code == 2
    lines = error_lines(result)
    assert len(lines) == 1 and "other.yaml" in lines[0] and "same" in lines[0]
    assert files_of(out) == {"same.csv", "same.summary.json"}


def test_run_missing_config_reported(tmp_path):
    result = invoke("run", tmp_path / "nope.yaml", tiny(tmp_path), "-o", tmp_path / "out", "--format", "csv")
    assert result.exit_code == 2
    assert "nope.yaml" in error_lines(result)[0]
    assert files_of(tmp_path / "out") == {"tiny.csv", "tiny.summary.json"}


def test_run_output_dir_is_a_file(tmp_path):
    target = tmp_path / "file"
    target.write_text("x")
    result = invoke("run", tiny(tmp_path), "-o", target)
    assert result.exit_code == 2
    assert target.read_text() == "x"


# -- regress ---------------------------------------------------------------------------------------
def test_regress_shipped_samples_pass():
    """The CI regression: every shipped sample reproduces its reference outputs."""
    result = invoke("regress", SAMPLES, "--jobs", 2)
    assert result.exit_code == 0, result.output
    names = sorted(p.stem for p in SAMPLES.glob("*.yaml"))
    assert len(names) >= 6
    for name in names:
        assert f"ok   {name}" in result.stdout
    assert not error_lines(result)


def copy_sample(tmp_path: Path, name: str = "pipe") -> Path:
    folder = tmp_path / "samples"
    (folder / "reference").mkdir(parents=True)
    shutil.copy(SAMPLES / f"{name}.yaml", folder)
    shutil.copytree(SAMPLES / "reference" / name, folder / "reference" / name)
    return folder


def _tamper_csv(path: Path, row: int, column: str, delta: float) -> tuple[str, str]:
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    j = header.index(column)
    fields = lines[row].split(",")
    old = fields[j]
    fields[j] = f"{float(old) + delta:.6f}"
    lines[row] = ",".join(fields)
    path.write_text("\n".join(lines) + "\n")
    return old, fields[j]


def test_regress_tampered_reference_fails_readably(tmp_path):
    folder = copy_sample(tmp_path)
    old, new = _tamper_csv(folder / "reference" / "pipe" / "pipe.csv", 5, "x", 0.01)
    summary = folder / "reference" / "pipe" / "pipe.summary.json"
    data = json.loads(summary.read_text())
    data["total_fiber_length_mm"] *= 1.001
    summary.write_text(json.dumps(data, indent=2))
    result = invoke("regress", folder)
    assert result.exit_code == 1
    out = result.stdout
    assert "FAIL pipe" in out
    assert "pipe.csv" in out and "line 6" in out and "column x" in out
    assert f"expected {new}, got {old}" in out
    assert "pipe.summary.json" in out and "total_fiber_length_mm" in out
    lines = error_lines(result)
    assert len(lines) == 1 and "pipe.yaml" in lines[0]


def test_regress_within_tolerance_passes(tmp_path):
    folder = copy_sample(tmp_path)
    path = folder / "reference" / "pipe" / "pipe.csv"
    lines = path.read_text().splitlines()
    # 4e-7 is below one unit of the 6 printed decimals: printed with more digits, the same number
    fields = lines[3].split(",")
    fields[-2] = f"{float(fields[-2]) + 4e-7:.7f}"
    lines[3] = ",".join(fields)
    path.write_text("\n".join(lines) + "\n")
    result = invoke("regress", folder)
    assert result.exit_code == 0, result.output


def test_regress_structure_change_fails(tmp_path):
    folder = copy_sample(tmp_path)
    gcode = folder / "reference" / "pipe" / "pipe.gcode"
    lines = gcode.read_text().splitlines()
    del lines[len(lines) // 2]
    gcode.write_text("\n".join(lines) + "\n")
    result = invoke("regress", folder)
    assert result.exit_code == 1
    assert "pipe.gcode" in result.stdout and "lines" in result.stdout


def test_regress_update_in_a_copy(tmp_path):
    folder = copy_sample(tmp_path)
    ref = folder / "reference" / "pipe" / "pipe.csv"
    original = ref.read_bytes()
    _tamper_csv(ref, 5, "x", 0.5)
    (folder / "reference" / "pipe" / "stale.gcode").write_text("G1 X0\n")
    result = invoke("regress", folder, "--update")
    assert result.exit_code == 0, result.output
    assert "pipe.csv: changed" in result.stdout
    assert "stale.gcode: removed" in result.stdout
    assert ref.read_bytes() == original
    assert not (folder / "reference" / "pipe" / "stale.gcode").exists()
    result = invoke("regress", folder)
    assert result.exit_code == 0, result.output
    result = invoke("regress", folder, "--update")
    assert result.exit_code == 0 and "references unchanged" in result.stdout


def test_regress_new_sample_without_reference(tmp_path):
    folder = tmp_path / "samples"
    folder.mkdir()
    tiny(folder, "fresh")
    result = invoke("regress", folder)
    assert result.exit_code == 1
    assert "--update" in result.stdout
    result = invoke("regress", folder, "--update")
    assert result.exit_code == 0, result.output
    assert files_of(folder / "reference" / "fresh") == {"fresh.csv", "fresh.gcode", "fresh.summary.json"}
    assert invoke("regress", folder).exit_code == 0


def test_regress_usage_errors(tmp_path):
    result = invoke("regress", tmp_path / "nowhere")
    assert result.exit_code == 2 and error_lines(result)
    result = invoke("regress", tmp_path)  # a folder without samples
    assert result.exit_code == 2 and "no samples" in error_lines(result)[0]


# -- standard output that cannot be written --------------------------------------------------------
def _winder(args: list[str], stdout) -> subprocess.CompletedProcess:
    """winder in a child process whose standard output is stdout (a closed pipe, /dev/full)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "winder", *args], stdout=stdout, stderr=subprocess.PIPE,
                          text=True, env=env, timeout=120, check=False)


@pytest.mark.parametrize("args", [["check", str(PIPE)], ["--help"],
                                  ["geodesic", str(PIPE), "--start", "10,0", "--end", "100,0", "--json"]])
def test_a_closed_pipe_ends_quietly(args):
    """`winder ... | head -1` with the reader gone: exit 1 and nothing on stderr, as click does for its
    own output; before, winder's own output said 'internal error (BrokenPipeError); please report it'."""
    read, write = os.pipe()
    os.close(read)
    with os.fdopen(write, "w") as closed:
        proc = _winder(args, closed)
    assert (proc.returncode, proc.stderr) == (1, "")


@pytest.mark.skipif(not Path("/dev/full").is_char_device(), reason="no /dev/full")
@pytest.mark.parametrize("args", [["check", str(PIPE)], ["--help"],
                                  ["geodesic", str(PIPE), "--start", "10,0", "--end", "100,0"]])
def test_a_full_standard_output_is_one_error_line(args):
    """Standard output on a full disk: one Error line and exit 1, not an internal error or a traceback."""
    with open("/dev/full", "w") as full:
        proc = _winder(args, full)
    assert proc.returncode == 1
    assert proc.stderr == "Error: standard output: cannot write: No space left on device\n"


def test_geodesic_output_over_its_config_is_refused_before_the_solve(tmp_path):
    config = tmp_path / "pipe.yaml"
    shutil.copy(PIPE, config)
    before = config.read_bytes()
    result = invoke("geodesic", config, "--start", "10,0", "--end", "100,0", "-o", config)
    assert result.exit_code == 2
    assert error_lines(result) == [f"Error: -o: is CONFIG itself, which writing there would destroy, got '{config}'"]
    assert config.read_bytes() == before


def test_run_format_names_given_as_configs_are_a_usage_error(tmp_path):
    """`--format csv gcode` takes gcode for a config: refused before any job with the way to ask for more
    formats, instead of running the config with csv alone and failing on a file named gcode."""
    out = tmp_path / "out"
    result = invoke("run", tiny(tmp_path), "-o", out, "--format", "csv", "gcode", "ply")
    assert result.exit_code == 2
    assert error_lines(result) == [
        "Error: gcode: not a config file but a format: give one format per --format (--format csv "
        "--format gcode) or comma-separate them (--format csv,gcode)"]
    assert result.stderr.count("\n") == 1
    assert not out.exists()

"""winder.app.regress: the comparison of outputs with their references (tolerances, structure, readable
differences) and the sample runner, with a stand-in job so that these tests need no planning."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from winder.errors import ConfigError
from winder.app.jobs import JobReport
from winder.app.regress import (
    Difference,
    compare_csv,
    compare_file,
    compare_json,
    compare_lines,
    failure_line,
    find_samples,
    format_result,
    regress,
    regress_exit_status,
)

CSV = "layer,circuit,pass,i,t,theta_deg,x,y,z,alpha_deg\n" + "".join(
    f"1,1,1,{i},{i * 1.5:.6f},{i * 10.0 + 0.5:.6f},50.000000,0.000000,{i * 1.5:.6f},55.000000\n" for i in range(8))
GCODE = "; winder job\nG21\nG90\nG94\nG1 X0.000 A0.000 Z70.000 B0.000 F3000\nG1 X12.500 A36.250 Z70.000 B5.000\n"
SUMMARY = {"name": "job", "total_fiber_length_mm": 12345.678901,
           "layers": [{"type": "helical", "angle_deg": 55.0, "circuits": 19, "pattern": 5, "fiber_length_mm": 12345.678901,
                       "coverage": {"covered_fraction": 1.0, "max_gap_mm": 0.0}}]}


def _replace_field(text: str, line: int, column: int, value: str) -> str:
    lines = text.splitlines()
    fields = lines[line].split(",")
    fields[column] = value
    lines[line] = ",".join(fields)
    return "\n".join(lines) + "\n"


# -- JSON ------------------------------------------------------------------------------------------
def test_json_equal_within_one_printed_unit():
    """The summary writes mm with 3 decimals: a last-digit flip is round-off, two units are not."""
    got = json.loads(json.dumps(SUMMARY))
    got["total_fiber_length_mm"] = 12345.679  # one unit of 3 decimals away from 12345.678(901)
    got["layers"][0]["coverage"]["max_gap_mm"] = 0.001
    got["layers"][0]["angle_deg"] = 55.0001  # 4 decimals for degrees
    assert compare_json(json.dumps(SUMMARY), json.dumps(got)) == ([], 0)
    got["layers"][0]["angle_deg"] = 55.0002
    shown, count = compare_json(json.dumps(SUMMARY), json.dumps(got))
    assert count == 1 and shown[0].where == "layers[0].angle_deg" and "tolerance 0.0001" in shown[0].note


def test_json_differences_are_named_by_key_path():
    got = json.loads(json.dumps(SUMMARY))
    got["total_fiber_length_mm"] = 12345.7039
    got["layers"][0]["circuits"] = 21
    got["layers"][0]["type"] = "hoop"
    del got["layers"][0]["pattern"]
    got["extra"] = 1
    shown, count = compare_json(json.dumps(SUMMARY), json.dumps(got))
    assert count == 5
    text = "\n".join(map(str, shown))
    assert "total_fiber_length_mm: expected 12345.678901, got 12345.7039" in text
    assert "layers[0].circuits: expected 19, got 21" in text
    assert 'layers[0].type: expected "helical", got "hoop"' in text
    assert "layers[0].pattern: expected 5, got (key missing)" in text
    assert "extra: expected (no such key)" in text


def test_json_structure():
    got = json.loads(json.dumps(SUMMARY))
    got["layers"].append(got["layers"][0])
    shown, count = compare_json(json.dumps(SUMMARY), json.dumps(got))
    assert count == 1 and "layers: expected 1 items, got 2 items" in str(shown[0])
    shown, count = compare_json(json.dumps(SUMMARY), json.dumps({**SUMMARY, "layers": {}}))
    assert count == 1 and "expected list" in str(shown[0])
    shown, count = compare_json('{"a": true}', '{"a": 1}')
    assert count == 1  # a boolean is not a number
    shown, count = compare_json(json.dumps(SUMMARY), "{not json")
    assert count == 1 and "unreadable" in str(shown[0])


def test_json_numbers_in_text():
    a = json.dumps({"notes": ["dwells lengthened to 14.561 / 14.561 deg (k = 5 of 19)"]})
    assert compare_json(a, a.replace("14.561 /", "14.5610000001 /")) == ([], 0)
    assert compare_json(a, a.replace("14.561 /", "14.562 /")) == ([], 0)  # last digit
    shown, count = compare_json(a, a.replace("14.561 /", "14.563 /"))
    assert count == 1 and shown[0].where == "notes[0]"
    assert compare_json(a, a.replace("dwells", "dwell"))[1] == 1


def test_numbers_in_text_printed_to_different_places():
    # configs/vessel_friction.yaml with friction 0.2 -> 0.25 changes only its note's "(friction 0.25)";
    # compared at the coarser place of "0.2" (0.1) the change passed.
    a = json.dumps({"notes": ["|k_g / k_n| up to 0.155 (friction 0.2); pattern k = 3 of 77"]})
    shown, count = compare_json(a, a.replace("friction 0.2)", "friction 0.25)"))
    assert count == 1 and shown[0].where == "notes[0]"
    assert compare_json(a, a.replace("friction 0.2)", "friction 0.21)"))[1] == 0  # one unit of 0.21
    assert compare_json(a, a.replace("friction 0.2)", "friction 0.2001)"))[1] == 0  # %g: 0.20005 either way
    b = json.dumps({"notes": ["stations at 5 mm"]})
    assert compare_json(b, b.replace("5 mm", "5.00001 mm"))[1] == 0  # %g of 5.000005
    assert compare_json(b, b.replace("5 mm", "5.5 mm"))[1] == 1
    assert compare_json(b, b.replace("5 mm", "6 mm"))[1] == 1


def test_json_nan_and_inf():
    assert compare_json('{"a": NaN, "b": Infinity}', '{"a": NaN, "b": Infinity}')[1] == 0
    assert compare_json('{"a": NaN}', '{"a": 1.0}')[1] == 1
    assert compare_json('{"b": Infinity}', '{"b": -Infinity}')[1] == 1


# -- CSV -------------------------------------------------------------------------------------------
def test_csv_tolerance_is_one_printed_unit():
    near = _replace_field(CSV, 3, 6, "50.000001")  # the last of 6 decimals flipped: round-off
    assert compare_csv(CSV, near) == ([], 0)
    far = _replace_field(CSV, 3, 6, "50.000002")
    shown, count = compare_csv(CSV, far)
    assert count == 1
    d = shown[0]
    assert d.where == "line 4 (layer 1, circuit 1, pass 1, i 2), column x"
    assert (d.expected, d.got) == ("50.000000", "50.000002")
    assert "tolerance 1.5e-06" in d.note  # one unit + REL_NOISE x 50
    # integers (layer, circuit, pass, i) are exact
    assert compare_csv(CSV, _replace_field(CSV, 3, 3, "3"))[1] == 1


def test_csv_alpha_is_a_line_angle():
    """alpha_deg is compared modulo 180: -89.999999 and 90.000000 are one fiber line."""
    at_90 = _replace_field(CSV, 3, 9, "90.000000")
    assert compare_csv(at_90, _replace_field(CSV, 3, 9, "-89.999999")) == ([], 0)
    assert compare_csv(at_90, _replace_field(CSV, 3, 9, "-89.999990"))[1] == 1
    assert compare_csv(CSV, _replace_field(CSV, 3, 9, "55.010000"))[1] == 1  # +0.01 deg is real


def test_csv_structure():
    shown, count = compare_csv(CSV, CSV.replace("alpha_deg", "alpha"))
    assert count == 1 and "header" in shown[0].where
    shown, count = compare_csv(CSV, CSV + CSV.splitlines()[-1] + "\n")
    assert count == 1 and "rows" in shown[0].where and "8 rows" in shown[0].expected
    shown, count = compare_csv(CSV, _replace_field(CSV, 2, 9, "55.0,1"))
    assert count == 1 and "11 fields" in shown[0].got
    shown, count = compare_csv(CSV, _replace_field(CSV, 2, 0, "x"))
    assert count == 1 and shown[0].got == "x"


def test_csv_shows_the_first_few_and_counts_all():
    lines = CSV.splitlines()
    got = "\n".join([lines[0]] + [line.replace("50.000000", "51.000000") for line in lines[1:]]) + "\n"
    shown, count = compare_csv(CSV, got)
    assert count == 8 and len(shown) == 5


# -- G-code ----------------------------------------------------------------------------------------
def test_gcode_numbers_within_one_printed_unit():
    assert compare_lines(GCODE, GCODE.replace("A36.250", "A36.251")) == ([], 0)  # last digit
    assert compare_lines(GCODE, GCODE.replace("X0.000", "X-0.000")) == ([], 0)
    shown, count = compare_lines(GCODE, GCODE.replace("A36.250", "A36.252"))
    assert count == 1 and "tolerance 0.001" in shown[0].note
    assert compare_lines(GCODE, GCODE.replace("F3000", "F3001"))[1] == 1  # integers are exact


def test_gcode_word_differences():
    shown, count = compare_lines(GCODE, GCODE.replace("A36.250", "A36.260"))
    assert count == 1
    assert shown[0].where == "line 6, word A" and (shown[0].expected, shown[0].got) == ("36.250", "36.260")
    shown, count = compare_lines(GCODE, GCODE.replace("G1 X12.500", "G0 X12.500"))
    assert count == 1 and shown[0].where == "line 6, word G"
    shown, count = compare_lines(GCODE, GCODE.replace("Z70.000 B5", "Y70.000 B5"))
    assert count == 1 and shown[0].where == "line 6"  # another axis word: the whole line
    shown, count = compare_lines(GCODE, GCODE.replace("; winder job", "; winder job 2"))
    assert count == 1


def test_gcode_line_count():
    shown, count = compare_lines(GCODE, GCODE + "M30\n")
    assert count == 1 and shown[0].where == "lines" and "6 lines" in shown[0].expected


def test_compare_file_dispatch():
    assert compare_file("a.summary.json", json.dumps(SUMMARY).encode(), json.dumps(SUMMARY, indent=2).encode()) == ([], 0)
    assert compare_file("a.ply", b"ply\x00\x01", b"ply\x00\x02")[1] == 1
    assert compare_file("a.csv", CSV.encode(), CSV.replace("55.000000", "55.000001").encode()) == ([], 0)
    assert compare_file("a.csv", CSV.encode(), CSV.replace("55.000000", "55.000011").encode())[1] == 8
    assert compare_file("a.gcode", GCODE.encode(), GCODE.encode()) == ([], 0)


def test_difference_text():
    d = Difference("line 4, column x", "1.0", "2.0", "off by 1")
    assert str(d) == "line 4, column x: expected 1.0, got 2.0 (off by 1)"


# -- samples and the runner ------------------------------------------------------------------------
def fake_job(config, out_dir, formats, source=None):
    """Stand-in for run_job: writes the outputs from the config's text (no planning)."""
    text = Path(config).read_text()
    name = Path(config).stem
    if "invalid" in text:
        return JobReport(str(config), name, False, 2, f"{config}: mandrel: invalid")
    scale = float(text.split("scale:")[1].split()[0]) if "scale:" in text else 1.0
    files = {f"{name}.csv": _replace_field(CSV, 2, 6, f"{50 * scale:.6f}"),
             f"{name}.summary.json": json.dumps({**SUMMARY, "total_fiber_length_mm": 1000.0 * scale})}
    if "gcode" in formats:
        files[f"{name}.gcode"] = GCODE
    if "ply" in formats:
        files[f"{name}.ply"] = "ply\n"
    outputs = []
    for file_name, data in files.items():
        (Path(out_dir) / file_name).write_text(data)
        outputs.append(str(Path(out_dir) / file_name))
    return JobReport(str(config), name, True, 0, "", tuple(outputs), 1000.0 * scale, 1, 0.01)


def make_samples(tmp_path: Path, **scales: float) -> Path:
    folder = tmp_path / "samples"
    folder.mkdir(exist_ok=True)
    for name, scale in scales.items():
        (folder / f"{name}.yaml").write_text(f"name: {name}\nscale: {scale}\n")
    return folder


def test_find_samples(tmp_path):
    folder = make_samples(tmp_path, b=1.0, a=1.0)
    (folder / "notes.txt").write_text("x")
    samples = find_samples(folder)
    assert [s.name for s in samples] == ["a", "b"]
    assert samples[0].reference == folder / "reference" / "a"
    (tmp_path / "empty").mkdir()
    with pytest.raises(ConfigError, match="no samples"):
        find_samples(tmp_path / "empty")
    with pytest.raises(ConfigError, match="missing: no such folder$"):
        find_samples(tmp_path / "missing")
    with pytest.raises(ConfigError, match="notes.txt: not a folder of samples$"):
        find_samples(folder / "notes.txt")
    # A sample that is a broken link is not skipped: CI would stop checking it and pass forever.
    (folder / "c.yaml").symlink_to(tmp_path / "gone.yaml")
    with pytest.raises(ConfigError, match=r"c\.yaml: a sample that is a broken link$"):
        find_samples(folder)


@pytest.mark.parametrize("workers", [1, 2])
def test_regress_update_then_compare(tmp_path, workers):
    folder = make_samples(tmp_path, a=1.0, b=2.0)
    results = regress(folder, workers=workers, job=fake_job)
    assert [r.ok for r in results] == [False, False]  # no references yet
    assert "--update" in "\n".join(format_result(results[0]))

    results = regress(folder, update=True, workers=workers, job=fake_job)
    assert all(r.ok for r in results)
    assert sorted(p.name for p in (folder / "reference" / "a").iterdir()) == ["a.csv", "a.gcode", "a.summary.json"]
    assert all(f.status == "new" for f in results[0].files)

    results = regress(folder, workers=workers, job=fake_job)
    assert all(r.ok for r in results) and regress_exit_status(results) == 0
    assert format_result(results[0])[0].startswith("ok   a")

    make_samples(tmp_path, b=2.001)
    results = regress(folder, workers=workers, job=fake_job)
    assert [r.ok for r in results] == [True, False] and regress_exit_status(results) == 1
    lines = format_result(results[1])
    assert lines[0].startswith("FAIL b")
    assert any("b.csv: differs, 1 difference" in line for line in lines)
    assert any("line 3 (layer 1, circuit 1, pass 1, i 1), column x: expected 100.000000, got 100.050000" in line
               for line in lines)
    assert any("total_fiber_length_mm: expected 2000.0, got 2001.0" in line for line in lines)
    assert "b.csv" in failure_line(results[1]) and "b.summary.json" in failure_line(results[1])

    results = regress(folder, update=True, workers=workers, job=fake_job)
    text = "\n".join(format_result(results[1]))
    assert "b.csv: changed, 1 difference" in text and "was 100.000000, now 100.050000" in text
    assert "b.gcode" not in text  # unchanged files are not listed
    assert regress(folder, workers=workers, job=fake_job)[1].ok


def test_regress_missing_and_unexpected_files(tmp_path):
    folder = make_samples(tmp_path, a=1.0)
    regress(folder, update=True, job=fake_job)
    ref = folder / "reference" / "a"
    (ref / "a.gcode").rename(ref / "old.gcode")
    result = regress(folder, job=fake_job)[0]
    status = {f.file: f.status for f in result.files}
    assert status == {"a.csv": "same", "a.gcode": "unexpected", "a.summary.json": "same", "old.gcode": "missing"}
    assert not result.ok
    result = regress(folder, update=True, job=fake_job)[0]
    assert {f.file: f.status for f in result.files if f.status != "same"} == {"a.gcode": "new", "old.gcode": "removed"}
    assert not (ref / "old.gcode").exists()


def test_regress_keeps_a_stored_ply(tmp_path):
    folder = make_samples(tmp_path, a=1.0)
    regress(folder, update=True, job=fake_job)
    (folder / "reference" / "a" / "a.ply").write_text("ply\n")
    result = regress(folder, job=fake_job)[0]
    assert result.ok and "a.ply" in {f.file for f in result.files}


def test_regress_failed_job(tmp_path):
    folder = make_samples(tmp_path, a=1.0)
    (folder / "bad.yaml").write_text("invalid\n")
    results = regress(folder, update=True, job=fake_job)
    assert [r.ok for r in results] == [True, False]
    assert regress_exit_status(results) == 2
    assert not (folder / "reference" / "bad").exists()
    assert "the job failed" in format_result(results[1])[0]
    assert failure_line(results[1]).endswith("mandrel: invalid")


def test_regress_fails_on_a_reference_without_its_sample(tmp_path):
    # A sample deleted while its reference stayed: the CI would stop checking it and still pass.
    folder = make_samples(tmp_path, a=1.0, b=1.0)
    regress(folder, update=True, job=fake_job)
    (folder / "b.yaml").unlink()
    results = regress(folder, job=fake_job)
    assert [r.sample.name for r in results] == ["a", "b"] and [r.ok for r in results] == [True, False]
    assert regress_exit_status(results) == 1
    assert format_result(results[1]) == [
        f"FAIL b: {folder / 'reference' / 'b'} holds the reference of b.yaml, which is not there "
        "(restore the sample, or remove its reference with `winder regress --update`)"]
    assert failure_line(results[1]) == f"{folder / 'b.yaml'}: no such sample, but {folder / 'reference' / 'b'} holds its reference"

    (folder / "reference" / "b" / "notes.txt").write_text("kept: not a winder output")
    results = regress(folder, update=True, job=fake_job)
    assert all(r.ok for r in results) and regress_exit_status(results) == 0
    assert {f.file: f.status for f in results[1].files} == {
        "b.csv": "removed", "b.gcode": "removed", "b.summary.json": "removed"}
    assert format_result(results[1])[0].startswith("removed b:")
    assert sorted(p.name for p in (folder / "reference" / "b").iterdir()) == ["notes.txt"]
    (folder / "reference" / "b" / "notes.txt").unlink()
    regress(folder, update=True, job=fake_job)
    assert not (folder / "reference" / "b").exists()
    assert [r.ok for r in regress(folder, job=fake_job)] == [True]


def test_gcode_comment_numbers_are_named_by_their_word():
    # "word s" for the circuit count of "circuits 19" sent the reader looking for an axis S.
    head = "; layer 1: helical, angle 55.000 deg (requested 55.000), circuits 19, fiber 33512.338 mm\n"
    shown, count = compare_lines(head + GCODE, head.replace("circuits 19", "circuits 18") + GCODE)
    assert count == 1 and shown[0].where == "line 1, circuits (in a comment)"
    assert (shown[0].expected, shown[0].got) == ("19", "18")
    shown, count = compare_lines(head + GCODE, head.replace("(requested 55.000)", "(requested 55.500)") + GCODE)
    assert count == 1 and shown[0].where == "line 1, requested (in a comment)"
    shown, count = compare_lines(GCODE, GCODE.replace("A36.250", "A36.260"))
    assert shown[0].where == "line 6, word A"  # axis words keep their letter


def _floats(value, path=""):
    if isinstance(value, dict):
        for key, sub in value.items():
            yield from _floats(sub, f"{path}.{key}" if path else key)
    elif isinstance(value, list):
        for i, sub in enumerate(value):
            yield from _floats(sub, f"{path}[{i}]")
    elif isinstance(value, float):
        yield path, value


def test_summary_keys_are_compared_at_the_decimals_they_are_written_with():
    # The stored summaries as the writer printed them: every float sits on the grid regress compares
    # it at (a coarser grid than written lets a real change pass, a relative 1e-6 fails a flipped last
    # digit of a value under 1000).
    from winder.export.summary import decimals_of

    stored = sorted((Path(__file__).parents[2] / "samples" / "reference").glob("*/*.summary.json"))
    assert len(stored) >= 7
    keys = set()
    for file in stored:
        for path, value in _floats(json.loads(file.read_text())):
            decimals = decimals_of(path)
            assert decimals is not None, (file.name, path)
            assert round(value, decimals) == value, (file.name, path, value, decimals)
            keys.add(path.rsplit(".", 1)[-1].split("[")[0])
    assert {"min_normal_curvature_per_mm", "max_slip", "thickness_mm", "outer_radius_mm", "yaw", "i"} <= keys


def test_summary_curvature_thickness_and_travel_at_their_printed_unit():
    summary = {"layers": [{"min_normal_curvature_per_mm": 0.0125, "max_slip": 0.452311, "thickness_mm": 3.3472}],
               "axis_travel": {"yaw": [-44.43, 44.43], "i": [-0.999871, 0.5]}}

    def changed(path, value):
        other = json.loads(json.dumps(summary))
        node = other
        for step in path[:-1]:
            node = node[step]
        node[path[-1]] = value
        return compare_json(json.dumps(summary), json.dumps(other))[1]

    assert changed(("layers", 0, "min_normal_curvature_per_mm"), 0.0134) == 1  # 7 % stiffer: was within 1e-3
    assert changed(("layers", 0, "min_normal_curvature_per_mm"), 0.01250001) == 0
    assert changed(("layers", 0, "thickness_mm"), 3.3481) == 1
    assert changed(("layers", 0, "thickness_mm"), 3.3473) == 0
    assert changed(("layers", 0, "max_slip"), 0.452312) == 0  # a flipped last digit is round-off
    assert changed(("layers", 0, "max_slip"), 0.452315) == 1
    assert changed(("axis_travel", "yaw", 1), 44.431) == 0
    assert changed(("axis_travel", "yaw", 1), 44.433) == 1
    assert changed(("axis_travel", "i", 0), -0.99987) == 0


def _ply(points, colors=(190, 190, 190, 255), faces=((0, 1, 2),)) -> bytes:
    """A binary PLY in the layout winder.export.ply writes (float32 xyz, uchar RGBA, uchar 3 + int32 faces)."""
    v = np.zeros(len(points), dtype=[("p", "<f4", 3), ("c", "u1", 4)])
    v["p"], v["c"] = points, colors
    f = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", 3)])
    f["n"], f["i"] = 3, faces
    head = ("ply\nformat binary_little_endian 1.0\ncomment winder\n"
            f"element vertex {len(points)}\nproperty float x\nproperty float y\nproperty float z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
            f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    return head.encode("ascii") + v.tobytes() + f.tobytes()


def test_ply_vertices_within_their_last_bit():
    # The vessel_hemi sample's PLY from numpy 2.0.2 and 2.4.6 differs in 7 of 31,060 vertices by one
    # float32 step (20.888504 against 20.888506): the same mesh, yet byte for byte it failed.
    points = np.array([[20.888504, 97.89631, 228.72789], [0.0, 1.0, 2.0], [-3.5, 0.25, 500.0]], np.float32)
    ref = _ply(points)
    flipped = points.copy()
    flipped[0, 0] = np.nextafter(flipped[0, 0], np.float32(100))
    assert compare_file("a.ply", ref, _ply(flipped)) == ([], 0)
    zeros = points.copy()  # a rounded zero beside 97.9 (seen: -1.29e-12 against -3.85e-12)
    zeros[0, 0], flipped[0, 0] = -1.2939653e-12, -3.8463607e-12
    assert compare_file("a.ply", _ply(zeros), _ply(flipped)) == ([], 0)
    moved = points.copy()
    moved[2, 2] += np.float32(0.001)
    shown, count = compare_file("a.ply", ref, _ply(moved))
    assert count == 1 and shown[0].where == "vertex 2, property z"
    assert compare_file("a.ply", ref, _ply(points, colors=(190, 190, 191, 255)))[1] == 3  # colors exact
    shown, count = compare_file("a.ply", ref, _ply(points, faces=((0, 2, 1),)))
    assert count == 1 and shown[0].where.startswith("faces")
    shown, count = compare_file("a.ply", ref, _ply(points[:2], faces=((0, 1, 1),)))
    assert count == 1 and shown[0].where == "header"
    assert compare_file("a.ply", ref, ref[:-5])[1] == 1  # a face cut short
    assert compare_file("a.ply", b"not a ply", b"not a ply either")[1] == 1  # unreadable: the bytes

"""winder.config.wind_file / wind_yaml: fiberpath's `.wind` job read as a winder job, refused line by line.

The .wind files here are written by the tests (fiberpath's own examples are AGPL: tests/app/
test_fiberpath_files.py reads them where the bench folder is present)."""

from __future__ import annotations

import copy
import math
import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from winder.cli import main
from winder.config.job import load_config
from winder.config.winding import LayerType
from winder.errors import ConfigError

JOB = {
    "schemaVersion": "1.1",
    "mandrelParameters": {"diameter": 100.0, "windLength": 400.0},
    "towParameters": {"width": 8.0, "thickness": 0.4},
    "defaultFeedRate": 6000,
    "layers": [
        {"windType": "hoop", "terminal": False},
        {"windType": "skip", "mandrelRotation": 90},
        {"windType": "helical", "windAngle": 50, "patternNumber": 2, "skipIndex": 1, "lockDegrees": 360,
         "leadInMM": 20, "leadOutDegrees": 30, "skipInitialNearLock": True},
        {"windType": "hoop", "terminal": True},
    ],
}


def write(tmp_path: Path, data: object, name: str = "job.wind") -> Path:
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data), encoding="utf-8")
    return path


def test_mapping(tmp_path):
    job = load_config(write(tmp_path, JOB))
    assert job.name == "job"
    assert job.mandrel.profile.radius == 50.0 and job.mandrel.axis.length == 400.0
    w = job.winding
    assert w.band_width == 8.0 and (w.dwell_start_deg, w.dwell_end_deg) == (360.0, 360.0)
    # the skip layer turns the mandrel only; a terminal hoop lays one pass, another one two
    assert [(layer.type, layer.passes) for layer in w.layers] == [(LayerType.HOOP, 2), (LayerType.HELICAL, 1),
                                                                   (LayerType.HOOP, 1)]
    assert w.layers[1].angle_deg == 50.0 and w.layers[1].pattern is None
    m = job.machine
    assert m.dialect == "marlin" and m.feed == 6000.0 and m.eye_radius == 70.0
    assert (m.axes.carriage, m.axes.rotation, m.axes.yaw) == ("X", "A", "B")


def test_a_cone_by_end_diameter(tmp_path):
    data = copy.deepcopy(JOB)
    data["mandrelParameters"]["endDiameter"] = 60.0
    profile = load_config(write(tmp_path, data)).mandrel.profile
    assert (profile.start_radius, profile.end_radius) == (50.0, 30.0)


def test_convert_writes_the_same_job(tmp_path):
    wind = write(tmp_path, JOB)
    out = tmp_path / "job.yaml"
    result = CliRunner().invoke(main, ["convert", str(wind), "-o", str(out)])
    assert result.exit_code == 0, result.output
    text = out.read_text(encoding="utf-8")
    assert "# fiberpath skip: the mandrel turns 90 deg" in text and "patternNumber 2" in text
    a, b = load_config(wind), load_config(out)
    assert (a.mandrel, a.winding, a.machine, a.name) == (b.mandrel, b.winding, b.machine, b.name)


def _bad(*path_value):
    data = copy.deepcopy(JOB)
    for path, value in zip(path_value[0::2], path_value[1::2]):
        node = data
        for key in path[:-1]:
            node = node[key]
        if value is KeyError:
            del node[path[-1]]
        else:
            node[path[-1]] = value
    return data


INVALID = [
    ("wrong_type", _bad(("mandrelParameters", "diameter"), "100"), "mandrelParameters.diameter: must be a number, got '100'"),
    ("missing_key", _bad(("towParameters", "width"), KeyError), "towParameters.width: required key missing"),
    ("unknown_wind_type", _bad(("layers", 0, "windType"), "spiral"),
     "layers[0].windType: must be one of hoop, helical, skip, got 'spiral'"),
    ("no_wind_type", _bad(("layers", 3, "windType"), KeyError), "layers[3].windType: required key missing"),
    ("helical_missing", _bad(("layers", 2, "lockDegrees"), KeyError), "layers[2].lockDegrees: required key missing"),
    ("angle_90", _bad(("layers", 2, "windAngle"), 90), "layers[2].windAngle: must be below 90 degrees"),
    ("pattern_zero", _bad(("layers", 2, "patternNumber"), 0), "layers[2].patternNumber: must be a whole number >= 1"),
    ("terminal_text", _bad(("layers", 0, "terminal"), "no"), "layers[0].terminal: must be true or false, got 'no'"),
    ("schema_2", _bad(("schemaVersion",), "2.0"), "schemaVersion: must be a 1.x version string"),
    ("unknown_key", _bad(("mandrelParameters", "diamter"), 3), "mandrelParameters.diamter: unknown key"),
    ("layers_not_list", _bad(("layers",), {}), "layers: must be a list of layers"),
    ("profile", _bad(("mandrelParameters", "profile"), {"type": "vonKarman"}), "mandrelParameters.profile: a profile"),
    ("nan_feed", _bad(("defaultFeedRate",), float("nan")), "defaultFeedRate: must be a finite number"),
    ("only_skips", _bad(("layers",), [{"windType": "skip", "mandrelRotation": 10}]), "layers: has no hoop or helical"),
    ("bad_json", '{"layers": [', "invalid JSON"),
    ("duplicate", '{"layers": [], "layers": []}', "invalid JSON: duplicate key 'layers'"),
    ("not_object", "[1, 2]", "must be a mapping with keys schemaVersion"),
]


@pytest.mark.parametrize("name,data,expected", INVALID, ids=[c[0] for c in INVALID])
def test_a_bad_wind_file_is_one_error_line_exit_2(tmp_path, name, data, expected):
    path = write(tmp_path, data)
    with pytest.raises(ConfigError) as info:
        load_config(path)
    assert str(info.value).startswith(f"{path}: ") and expected in str(info.value)
    for command in (["check", str(path)], ["run", str(path), "-o", str(tmp_path / "out")],
                    ["patterns", str(path)], ["convert", str(path), "-o", str(tmp_path / "x.yaml")]):
        result = CliRunner().invoke(main, command)
        lines = result.stderr.splitlines()
        assert result.exit_code == 2 and len(lines) == 1 and lines[0].startswith(f"Error: {path}: "), lines
        assert expected in lines[0]
    assert not (tmp_path / "x.yaml").exists()
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())


# -- read in time linear in its size (issue 45: the duplicate-key check was quadratic) ---------------
def _keys(n: int) -> str:
    return json.dumps({f"{i:x}": 1 for i in range(n)}, separators=(",", ":"))


def test_duplicate_keys_are_found_in_time_linear_in_the_keys(tmp_path: Path) -> None:
    """10,000 keys took 2.1 s, 40,000 36 s and 190,000 (1.8 MB) more than 130 s; a linear check reads
    4.75x the keys in about 4.75x the CPU time (a quadratic one in 22.6x)."""
    import time  # noqa: PLC0415

    from winder.config.wind_file import _load  # noqa: PLC0415

    def seconds(path: Path) -> float:
        best = math.inf
        for _ in range(3):
            start = time.process_time()
            _load(path, path.name)
            best = min(best, time.process_time() - start)
        return best

    small, large = write(tmp_path, _keys(40_000), "small.wind"), write(tmp_path, _keys(190_000), "large.wind")
    assert large.stat().st_size < 2_000_000
    large_s = seconds(large)
    assert large_s < 20.0  # 0.7 s here; the quadratic check took more than 130 s
    assert large_s / seconds(small) < 15.0  # 4.75 for linear, 22.6 for quadratic
    text = _keys(190_000)
    dup = write(tmp_path, text[:-1] + ',"0":2}', "dup.wind")
    with pytest.raises(ConfigError, match="invalid JSON: duplicate key '0'"):
        load_config(dup)


# -- convert: no text of the file's name read as YAML (issue 45) ------------------------------------
@pytest.mark.parametrize("name", ["j\nanalysis: {pressure: 5}\n#.wind", "j\ranalysis: {pressure: 5}\r#.wind",
                                  "j\u2028analysis: {pressure: 5}\u2028#.wind", "j\x85analysis: {pressure: 5}\x85#.wind",
                                  "j\r\nanalysis: {pressure: 5}\r\n#.wind"])
def test_a_file_name_cannot_add_keys_to_the_converted_config(tmp_path, name):
    import yaml  # noqa: PLC0415

    wind = write(tmp_path, JOB, name)
    out = tmp_path / "job.yaml"
    result = CliRunner().invoke(main, ["convert", str(wind), "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert sorted(yaml.safe_load(out.read_text(encoding="utf-8"))) == ["machine", "mandrel", "name", "winding"]
    assert load_config(out).analysis is None
    assert len(result.stdout.splitlines()) == 1  # the ok line shows the name escaped


def test_convert_to_standard_output(tmp_path):
    wind = write(tmp_path, JOB)
    result = CliRunner().invoke(main, ["convert", str(wind), "-o", "-"])
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("# Converted by `winder convert`") and "winding:" in result.stdout
    assert not (tmp_path / "-").exists()
    refused = CliRunner().invoke(main, ["convert", str(wind), "-o", str(wind)])
    assert refused.exit_code == 2 and "-o: is WIND itself" in refused.stderr

"""winder.config.mandrel: valid job files parse to the right dataclasses; invalid ones are refused with
messages naming the file, the key path and the value (docs/guide/config.md)."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest

from winder.app.validate import validate
from winder.config.job import JobConfig, load_config, parse_config
from winder.config.machine import MachineAxes, MachineConfig
from winder.config.axes import ArcAxis, PathAxis, SplineAxis
from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig, axis_length
from winder.config.profiles import ConeProfile, TableProfile
from winder.config.sections import EllipseSection, RoundedRectangleSection, SuperellipseSection
from winder.config.vessel import Dome, DomeType, VesselProfile
from winder.config.winding import LayerConfig, LayerType, WindingConfig
from winder.geometry.build import build_surface
from winder.errors import ConfigError, WinderError

ROOT = Path(__file__).resolve().parents[2]
INVALID = Path(__file__).resolve().parent / "invalid"
CONFIGS = ROOT / "configs"


def job(mandrel: dict, **sections: object) -> dict:
    return {"name": "job", "mandrel": mandrel, **sections}


def mandrel_of(mandrel: dict) -> MandrelConfig:
    return parse_config(job(mandrel), "t.yaml").mandrel


def write(tmp_path: Path, text: str, name: str = "job.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


PIPE = {"axis": {"type": "line", "length": 500}, "profile": {"type": "constant", "radius": 50}}
VESSEL = {"profile": {"type": "vessel", "radius": 100, "cylinder_length": 300,
                      "dome": {"type": "hemisphere", "polar_opening": 30}}}


# -- axes ------------------------------------------------------------------------------------------
def test_line_axis() -> None:
    m = mandrel_of(PIPE)
    assert m == MandrelConfig(LineAxis(500.0), ConstantProfile(50.0), CircleSection())
    assert isinstance(m.axis.length, float)


def test_arc_axis_keys_map_to_fields() -> None:
    m = mandrel_of({"axis": {"type": "arc", "radius": 150, "angle": 90, "toward": 30},
                    "profile": {"type": "constant", "radius": 40}})
    assert m.axis == ArcAxis(radius=150.0, angle_deg=90.0, toward_deg=30.0)
    assert axis_length(m.axis) == pytest.approx(150 * math.pi / 2)


def test_arc_toward_defaults_to_zero_and_full_circle_allowed() -> None:
    m = mandrel_of({"axis": {"type": "arc", "radius": 150, "angle": 360},
                    "profile": {"type": "constant", "radius": 40}})
    assert m.axis == ArcAxis(150.0, 360.0, 0.0)


def test_path_axis() -> None:
    m = mandrel_of({"axis": {"type": "path", "segments": [
        {"line": 100}, {"arc": {"radius": 150, "angle": 90, "toward": -45}}, {"line": 100}]},
        "profile": {"type": "constant", "radius": 40}})
    assert m.axis == PathAxis((LineAxis(100.0), ArcAxis(150.0, 90.0, -45.0), LineAxis(100.0)))
    assert axis_length(m.axis) == pytest.approx(200 + 150 * math.pi / 2)


def test_spline_axis_kept_as_given_when_starting_at_origin() -> None:
    pts = [[0, 0, 0], [0, 0, 100], [30, 10, 200]]
    m = mandrel_of({"axis": {"type": "spline", "points": pts}, "profile": {"type": "constant", "radius": 10}})
    assert m.axis == SplineAxis(((0.0, 0.0, 0.0), (0.0, 0.0, 100.0), (30.0, 10.0, 200.0)))
    assert axis_length(m.axis) is None


def test_spline_axis_moved_to_the_origin() -> None:
    pts = [[10, 20, 30], [10, 20, 130], [40, 30, 230]]
    m = mandrel_of({"axis": {"type": "spline", "points": pts}, "profile": {"type": "constant", "radius": 10}})
    assert m.axis.points == ((0.0, 0.0, 0.0), (0.0, 0.0, 100.0), (30.0, 10.0, 200.0))


# -- profiles --------------------------------------------------------------------------------------
def test_cone_profile_on_a_bent_axis() -> None:
    m = mandrel_of({"axis": {"type": "arc", "radius": 300, "angle": 60},
                    "profile": {"type": "cone", "start_radius": 60, "end_radius": 40}})
    assert m.profile == ConeProfile(60.0, 40.0)


def test_table_profile_without_axis_gets_a_line_of_its_length() -> None:
    m = mandrel_of({"profile": {"type": "table", "points": [[0, 40], [100, 45], [250.5, 40]]}})
    assert m.profile == TableProfile(((0.0, 40.0), (100.0, 45.0), (250.5, 40.0)))
    assert m.axis == LineAxis(250.5)


def test_table_profile_may_extend_beyond_the_axis() -> None:
    m = mandrel_of({"axis": {"type": "line", "length": 200},
                    "profile": {"type": "table", "points": [[0, 40], [300, 40]]}})
    assert m.axis == LineAxis(200.0)


def test_table_covering_an_arc_up_to_typing_precision() -> None:
    # 150 mm x 90 deg is 235.6194... mm; a user types 235.6194.
    mandrel_of({"axis": {"type": "arc", "radius": 150, "angle": 90},
                "profile": {"type": "table", "points": [[0, 40], [235.6194, 40]]}})


def test_vessel_profile_axis_left_out_and_end_dome_defaulted() -> None:
    m = mandrel_of(VESSEL)
    dome = Dome(DomeType.HEMISPHERE, 30.0, None)
    assert m == MandrelConfig(None, VesselProfile(100.0, 300.0, dome, dome), CircleSection())


def test_vessel_with_ellipsoid_and_isotensoid_domes_and_line_axis() -> None:
    m = mandrel_of({"axis": {"type": "line", "length": 480}, "profile": {
        "type": "vessel", "radius": 100, "cylinder_length": 0,
        "dome": {"type": "ellipsoid", "polar_opening": 25, "depth": 50},
        "end_dome": {"type": "isotensoid", "polar_opening": 35}}})
    assert m.axis == LineAxis(480.0)
    assert m.profile.dome == Dome(DomeType.ELLIPSOID, 25.0, 50.0)
    assert m.profile.end_dome == Dome(DomeType.ISOTENSOID, 35.0, None)
    assert m.profile.cylinder_length == 0.0


# -- sections --------------------------------------------------------------------------------------
@pytest.mark.parametrize(("section", "expected"), [
    ({"type": "circle"}, CircleSection()),
    ({"type": "ellipse", "a": 60, "b": 35}, EllipseSection(60.0, 35.0)),
    ({"type": "rounded_rectangle", "width": 120, "height": 80, "corner_radius": 40},
     RoundedRectangleSection(120.0, 80.0, 40.0)),
    ({"type": "superellipse", "a": 50, "b": 40, "exponent": 2}, SuperellipseSection(50.0, 40.0, 2.0)),
])
def test_sections(section: dict, expected: object) -> None:
    m = mandrel_of({"axis": {"type": "line", "length": 100}, "profile": {"type": "constant", "radius": 40},
                    "section": section})
    assert m.section == expected


def test_non_circular_section_without_profile_is_absolute() -> None:
    m = mandrel_of({"axis": {"type": "line", "length": 400}, "section": {"type": "ellipse", "a": 60, "b": 35}})
    assert m.profile is None and m.section == EllipseSection(60.0, 35.0)


def built(mandrel: dict):
    """The bend check needs the surface: it is the geometry's (winder.geometry.build)."""
    return build_surface(mandrel_of(mandrel), "t.yaml")


def test_bend_check_uses_the_section_extent_toward_the_inside() -> None:
    # An ellipse 60 x 20 bent toward e3 (toward 90) reaches only 20 mm toward the bend's centre.
    base = {"section": {"type": "ellipse", "a": 60, "b": 20}}
    built({**base, "axis": {"type": "arc", "radius": 25, "angle": 90, "toward": 90}})
    with pytest.raises(ConfigError, match=r"mandrel\.axis\.radius: must be larger than .*\(60 mm\)"):
        built({**base, "axis": {"type": "arc", "radius": 55, "angle": 90, "toward": 0}})


def test_bend_check_follows_a_cone_along_the_path() -> None:
    # A cone 80 -> 20 over 100 + 100 + pi/2*50 mm: at the bend (t in [100, 178.5]) r <= 50.
    cone = {"type": "cone", "start_radius": 80, "end_radius": 20}
    segments = [{"line": 100}, {"arc": {"radius": 60, "angle": 90}}, {"line": 100}]
    built({"axis": {"type": "path", "segments": segments}, "profile": cone})
    segments[1]["arc"]["radius"] = 40
    with pytest.raises(ConfigError, match=r"segments\[1\]\.arc\.radius"):
        built({"axis": {"type": "path", "segments": segments}, "profile": cone})


# -- winding ---------------------------------------------------------------------------------------
def test_winding_full() -> None:
    cfg = parse_config(job(PIPE, winding={
        "band_width": 10, "region": {"start": 0, "end": 500}, "tolerance": 0.01,
        "dwell": {"start": 10}, "friction": 0,
        "layers": [{"type": "helical", "angle": 55, "pattern": 3},
                   {"type": "helical", "angle": 30, "pattern": "auto"},
                   {"type": "hoop", "passes": 2, "angle": 89.5}]}), "t.yaml")
    assert cfg.winding == WindingConfig(
        band_width=10.0, region=(0.0, 500.0), points=None, tolerance=0.01, dwell_start_deg=10.0,
        dwell_end_deg=0.0, friction=0.0, layers=(
            LayerConfig(LayerType.HELICAL, 55.0, 3, 1), LayerConfig(LayerType.HELICAL, 30.0, None, 1),
            LayerConfig(LayerType.HOOP, 89.5, None, 2)))


def test_winding_defaults() -> None:
    w = parse_config(job(PIPE, winding={"band_width": 8, "layers": [{"type": "hoop"}]}), "t.yaml").winding
    assert w == WindingConfig(8.0, None, 200, None, 0.0, 0.0, 0.2, (LayerConfig(LayerType.HOOP, None, None, 1),))


def test_winding_points_whole_float_accepted() -> None:
    w = parse_config(job(PIPE, winding={"band_width": 8, "points": 300.0, "layers": [{"type": "hoop"}]}),
                     "t.yaml").winding
    assert w.points == 300 and isinstance(w.points, int)


def test_winding_absent_or_empty_is_none() -> None:
    assert parse_config(job(PIPE), "t.yaml").winding is None
    assert parse_config(job(PIPE, winding=None), "t.yaml").winding is None


def test_region_unchecked_against_a_spline_of_unknown_length() -> None:
    spline = {"axis": {"type": "spline", "points": [[0, 0, 0], [0, 0, 100]]},
              "profile": {"type": "constant", "radius": 10}}
    w = parse_config(job(spline, winding={"band_width": 5, "region": {"start": 10, "end": 1e4},
                                          "layers": [{"type": "helical", "angle": 45}]}), "t.yaml").winding
    assert w.region == (10.0, 1e4)


def test_region_end_typed_at_an_arc_length_is_clamped_to_it() -> None:
    elbow = {"axis": {"type": "arc", "radius": 150, "angle": 90}, "profile": {"type": "constant", "radius": 40}}
    w = parse_config(job(elbow, winding={"band_width": 5, "region": {"start": 0, "end": 235.6195},
                                         "layers": [{"type": "helical", "angle": 45}]}), "t.yaml").winding
    assert w.region == (0.0, pytest.approx(150 * math.pi / 2, abs=1e-12))


def test_vessel_winding_without_region() -> None:
    w = parse_config(job(VESSEL, winding={"band_width": 10, "layers": [{"type": "helical", "angle": 20}]}),
                     "t.yaml").winding
    assert w.region is None and w.dwell_start_deg == 0.0


# -- machine ---------------------------------------------------------------------------------------
def test_machine_defaults_when_left_out() -> None:
    cfg = parse_config(job(PIPE), "t.yaml")
    assert cfg.machine == MachineConfig()
    assert cfg.machine.eye_clearance == 20.0 and cfg.machine.eye_radius is None
    assert cfg.machine.feed == 3000.0 and cfg.machine.robot is False
    assert cfg.machine.axes == MachineAxes("X", "A", "Z", "B")


def test_machine_full() -> None:
    m = parse_config(job(PIPE, machine={
        "axes": {"carriage": "Y", "rotation": "C", "cross_feed": "X", "yaw": "B"},
        "eye": {"radius": 80}, "feed": 2000, "chord_tolerance": 0.02,
        "limits": {"carriage": [-10, 1200], "cross_feed": [0, 300], "yaw": [-90, 90]},
        "robot": False}), "t.yaml").machine
    assert m.axes == MachineAxes("Y", "C", "X", "B")
    assert (m.eye_radius, m.eye_clearance, m.feed, m.chord_tolerance) == (80.0, None, 2000.0, 0.02)
    assert m.limits.get("carriage") == (-10.0, 1200.0) and m.limits.get("rotation") is None
    assert m.limits.items() == (("carriage", (-10.0, 1200.0)), ("cross_feed", (0.0, 300.0)),
                                ("yaw", (-90.0, 90.0)))
    assert m.robot is False


def test_bent_axis_defaults_to_robot() -> None:
    elbow = {"axis": {"type": "arc", "radius": 150, "angle": 90}, "profile": {"type": "constant", "radius": 40}}
    assert parse_config(job(elbow), "t.yaml").machine.robot is True
    assert parse_config(job(elbow, machine={"feed": 1000}), "t.yaml").machine.robot is True
    straight_path = {"axis": {"type": "path", "segments": [{"line": 10}, {"line": 20}]},
                     "profile": {"type": "constant", "radius": 4}}
    assert parse_config(job(straight_path), "t.yaml").machine.robot is False
    straight_spline = {"axis": {"type": "spline", "points": [[1, 1, 1], [1, 1, 50], [1, 1, 90]]},
                       "profile": {"type": "constant", "radius": 4}}
    assert parse_config(job(straight_spline), "t.yaml").machine.robot is False


# -- the job file and YAML -------------------------------------------------------------------------
def test_job_fields_and_frozen() -> None:
    cfg = parse_config(job(PIPE), "pipe.yaml")
    assert isinstance(cfg, JobConfig) and (cfg.name, cfg.source) == ("job", "pipe.yaml")
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.name = "other"  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.mandrel.profile.radius = 3  # type: ignore[union-attr]


def test_yaml_core_schema_scalars(tmp_path: Path) -> None:
    # PyYAML alone reads 1e-3 as a string and `no` as false; a job file means 0.001 and the name.
    path = write(tmp_path, "name: no\nmandrel:\n  axis: {type: line, length: 5e2}\n"
                           "  profile: {type: constant, radius: 50}\n"
                           "winding: {band_width: 1e1, tolerance: 1e-3, layers: [{type: hoop}]}\n")
    cfg = load_config(path)
    assert cfg.name == "no" and cfg.mandrel.axis == LineAxis(500.0)
    assert cfg.winding.tolerance == 0.001 and cfg.winding.band_width == 10.0


def test_load_config_source_is_the_path_as_given(tmp_path: Path) -> None:
    path = write(tmp_path, "name: p\nmandrel: {axis: {type: line, length: 1}, profile: {type: constant, radius: 1}}\n")
    assert load_config(path).source == str(path)
    assert load_config(str(path)).source == str(path)


def test_missing_file_is_a_config_error(tmp_path: Path) -> None:
    path = tmp_path / "nope.yaml"
    with pytest.raises(ConfigError, match=r"nope\.yaml: cannot read the file") as info:
        load_config(path)
    assert isinstance(info.value, WinderError) and info.value.exit_code == 2


def test_yaml_syntax_error_names_file_and_line(tmp_path: Path) -> None:
    path = write(tmp_path, "name: p\nmandrel:\n  axis: [1, 2\n")
    with pytest.raises(ConfigError) as info:
        load_config(path)
    assert str(info.value).startswith(f"{path}: line ")
    assert "invalid YAML" in str(info.value)


def test_error_chains_the_yaml_error(tmp_path: Path) -> None:
    path = write(tmp_path, "a: [\n")
    with pytest.raises(ConfigError) as info:
        load_config(path)
    assert info.value.__cause__ is not None


def test_non_text_key_is_shown_as_yaml() -> None:
    with pytest.raises(ConfigError, match=r"^t\.yaml: mandrel\.null: unknown key; allowed: axis, profile"):
        parse_config(job({None: 1}), "t.yaml")


def test_parse_config_refuses_a_non_mapping() -> None:
    with pytest.raises(ConfigError, match=r"^x\.yaml: must be a mapping with keys name, mandrel"):
        parse_config(["name"], "x.yaml")  # type: ignore[arg-type]


# -- every example config loads --------------------------------------------------------------------
EXAMPLES = sorted(CONFIGS.glob("*.yaml"))


def test_all_documented_examples_exist() -> None:
    names = {p.name for p in EXAMPLES}
    assert names >= {"pipe.yaml", "elbow.yaml", "vessel.yaml", "isotensoid.yaml", "cone.yaml",
                     "elliptic_tube.yaml", "rounded_tube.yaml", "spline_tube.yaml", "table_mandrel.yaml",
                     "superellipse_tube.yaml", "ellipsoid_vessel.yaml"}


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_config_loads(path: Path) -> None:
    cfg = load_config(path)
    assert cfg.name == path.stem  # the examples name their outputs after the file
    assert cfg.winding is not None and cfg.winding.layers


def test_example_configs_parse_as_documented() -> None:
    by = {p.stem: load_config(p) for p in EXAMPLES}
    assert by["pipe"].mandrel == MandrelConfig(LineAxis(500.0), ConstantProfile(50.0), CircleSection())
    assert [layer.type for layer in by["pipe"].winding.layers] == [LayerType.HELICAL, LayerType.HOOP]
    assert by["pipe"].winding.layers[0].angle_deg == 55.0
    assert by["elbow"].mandrel.axis == PathAxis((LineAxis(100.0), ArcAxis(150.0, 90.0, 0.0), LineAxis(100.0)))
    assert by["elbow"].mandrel.profile == ConstantProfile(40.0)
    vessel = by["vessel"].mandrel.profile
    assert (vessel.radius, vessel.cylinder_length, vessel.dome.type, vessel.dome.polar_opening) == (
        100.0, 300.0, DomeType.HEMISPHERE, 30.0)
    assert by["elliptic_tube"].mandrel == MandrelConfig(LineAxis(400.0), None, EllipseSection(60.0, 35.0))
    assert by["isotensoid"].mandrel.profile.dome.type is DomeType.ISOTENSOID
    assert by["ellipsoid_vessel"].mandrel.profile.dome.type is DomeType.ELLIPSOID
    assert isinstance(by["cone"].mandrel.profile, ConeProfile)
    assert isinstance(by["rounded_tube"].mandrel.section, RoundedRectangleSection)
    assert isinstance(by["spline_tube"].mandrel.axis, SplineAxis)
    assert isinstance(by["table_mandrel"].mandrel.profile, TableProfile)
    assert isinstance(by["superellipse_tube"].mandrel.section, SuperellipseSection)


# -- every invalid config is refused with its message ----------------------------------------------
INVALID_CASES = sorted(INVALID.glob("*.yaml"))


def _expected(path: Path) -> str:
    first = path.read_text(encoding="utf-8").splitlines()[0]
    assert first.startswith("# expect: "), f"{path.name} must start with '# expect: <message part>'"
    return first.removeprefix("# expect: ")


def test_enough_invalid_cases() -> None:
    assert len(INVALID_CASES) >= 30


@pytest.mark.parametrize("path", INVALID_CASES, ids=[p.stem for p in INVALID_CASES])
def test_invalid_config_refused(path: Path) -> None:
    expected = _expected(path)
    with pytest.raises(ConfigError) as info:
        # check's one validation path: what only the built surface shows (a bend folding it) is
        # refused by the geometry stage, and what needs the surface's perimeters by the work budget.
        validate(path)
    message = str(info.value)
    assert message.startswith(f"{path}: "), message
    assert expected in message, message
    assert "\n" not in message  # one line per problem


def test_written_resolution_is_the_programs():
    """The floor of machine.feed and machine.chord_tolerance is what the program writes."""
    from winder.config.machine import WRITTEN_RESOLUTION
    from winder.machine.limits import AXIS_DECIMALS

    assert WRITTEN_RESOLUTION == 10.0 ** -AXIS_DECIMALS

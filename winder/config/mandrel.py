"""Job file (YAML) -> validated, frozen dataclasses.

Everything a user can get wrong in a job file is refused here, before any computation, with one
ConfigError reading `<file>: <key.path>: <what is wrong>, got <value>` (SPEC.md). Checks that need
the built surface (a table's interpolation dipping, a spline bending too tightly, dome depths) are
left to the modules that build it. The `winding:` and `machine:` sections live in
winder.config.winding.
"""

from __future__ import annotations

import bisect
import math
import re
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any

import yaml

from winder.config.winding import (
    LENGTH_SLACK,
    LayerConfig,
    LayerType,
    MachineAxes,
    MachineConfig,
    MachineLimits,
    WindingConfig,
    parse_machine,
    parse_winding,
)
from winder.errors import ConfigError
from winder.config.reader import Reader, YamlLoader, show_value

__all__ = [
    "ArcAxis", "CircleSection", "ConeProfile", "ConstantProfile", "Dome", "DomeType", "EllipseSection",
    "JobConfig", "LayerConfig", "LayerType", "LineAxis", "MachineAxes", "MachineConfig", "MachineLimits",
    "MandrelConfig", "PathAxis", "RoundedRectangleSection", "SplineAxis", "SuperellipseSection",
    "TableProfile", "VesselProfile", "WindingConfig", "axis_length", "load_config", "parse_config",
]


# -- the dataclasses -------------------------------------------------------------------------------
class DomeType(Enum):
    HEMISPHERE = "hemisphere"
    ELLIPSOID = "ellipsoid"
    ISOTENSOID = "isotensoid"


@dataclass(frozen=True)
class LineAxis:
    """A straight guide along +z; length in mm."""

    length: float


@dataclass(frozen=True)
class ArcAxis:
    """A circular bend: bend radius (mm), bend angle (deg, in (0, 360]), and the side it bends
    toward, measured like theta from e2 toward e3 (deg; theta = toward is the inside of the bend)."""

    radius: float
    angle_deg: float
    toward_deg: float = 0.0


@dataclass(frozen=True)
class PathAxis:
    """A tangent-continuous chain of lines and arcs; each arc's toward is in the frame at its start."""

    segments: tuple[LineAxis | ArcAxis, ...]


@dataclass(frozen=True)
class SplineAxis:
    """A C2 interpolating curve through the points (mm); the first point is the origin."""

    points: tuple[tuple[float, float, float], ...]


@dataclass(frozen=True)
class ConstantProfile:
    radius: float


@dataclass(frozen=True)
class ConeProfile:
    """Radius linear in t from start_radius at t = 0 to end_radius at t = T."""

    start_radius: float
    end_radius: float


@dataclass(frozen=True)
class TableProfile:
    """(t, r) pairs: t from 0, strictly increasing; r > 0. Interpolated smoothly by the surface."""

    points: tuple[tuple[float, float], ...]


@dataclass(frozen=True)
class Dome:
    """One end dome of a vessel.

    polar_opening: radius (not diameter) of the polar opening (boss), mm; 0 < polar_opening < R.
    depth: ellipsoid only: the ellipsoid's semi-axis along the vessel axis (mm), i.e. the depth from
        the cylinder's end to the (closed) pole; the part down to the opening is depth *
        sqrt(1 - (polar_opening / R)^2). None for hemisphere (depth R) and isotensoid (its shape
        follows from R and the polar opening).
    """

    type: DomeType
    polar_opening: float
    depth: float | None = None


@dataclass(frozen=True)
class VesselProfile:
    """A cylinder of radius R and length cylinder_length (>= 0) between two domes. t = 0 is the plane
    of the first dome's polar opening; end_dome is the dome at t = T (a copy of dome if not given)."""

    radius: float
    cylinder_length: float
    dome: Dome
    end_dome: Dome


@dataclass(frozen=True)
class CircleSection:
    """A circle; its radius is the profile's."""


@dataclass(frozen=True)
class EllipseSection:
    """Semi-axis a along e2 and b along e3 (mm)."""

    a: float
    b: float


@dataclass(frozen=True)
class RoundedRectangleSection:
    """width along e2, height along e3, corner radius <= min(width, height) / 2 (mm)."""

    width: float
    height: float
    corner_radius: float


@dataclass(frozen=True)
class SuperellipseSection:
    """|x/a|^p + |y/b|^p = 1 with p = exponent >= 2 (x along e2)."""

    a: float
    b: float
    exponent: float


Axis = LineAxis | ArcAxis | PathAxis | SplineAxis
Profile = ConstantProfile | ConeProfile | TableProfile | VesselProfile
Section = CircleSection | EllipseSection | RoundedRectangleSection | SuperellipseSection


@dataclass(frozen=True)
class MandrelConfig:
    """The mandrel. axis is None only for a vessel left without one: its length T needs the dome
    shapes, so the surface builds the line. A table profile without an axis gets LineAxis(last t).
    profile is None only for a non-circular section, whose sizes are then absolute; with a profile,
    the section is scaled by profile(t) / profile(0)."""

    axis: Axis | None
    profile: Profile | None
    section: Section = CircleSection()


@dataclass(frozen=True)
class JobConfig:
    """A whole job file. source is the file name used in messages. winding is None when the file has
    none (enough for `geodesic` and `check`); machine is the default MachineConfig when left out."""

    name: str
    source: str
    mandrel: MandrelConfig
    winding: WindingConfig | None = None
    machine: MachineConfig | None = field(default_factory=MachineConfig)


def load_config(path: str | Path) -> JobConfig:
    """Read and validate a job file; every problem is a ConfigError starting with the path."""
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise ConfigError(f"{source}: cannot read the file: {exc.strerror or exc}") from exc
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{source}: not a UTF-8 text file ({exc.reason} at byte {exc.start})") from exc
    try:
        data = yaml.load(text, Loader=YamlLoader)  # noqa: S506 (a SafeLoader subclass)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        where = f"line {mark.line + 1}, column {mark.column + 1}: " if mark is not None else ""
        problem = exc.problem or exc.context or "unreadable"
        raise ConfigError(f"{source}: {where}invalid YAML: {problem}") from exc
    except (yaml.YAMLError, ValueError) as exc:  # ValueError: an explicitly tagged !!int "x"
        raise ConfigError(f"{source}: invalid YAML: {exc}") from exc
    return parse_config(data, source)


# -- the job file ----------------------------------------------------------------------------------
_NAME = re.compile(r"[A-Za-z0-9_.-]+")


def parse_config(data: dict, source: str) -> JobConfig:
    """Validate the loaded YAML of a job file; source is the file name used in messages."""
    rd = Reader(source)
    top = rd.mapping(data, "", ("name", "mandrel", "winding", "machine"), required=("name", "mandrel"))
    name = rd.text(top["name"], "name")
    if not _NAME.fullmatch(name):
        raise rd.error("name", "must use only letters, digits, '_', '.' and '-' (it names the output "
                       "files)", name)
    mandrel = _parse_mandrel(rd, top["mandrel"], "mandrel")
    vessel = isinstance(mandrel.profile, VesselProfile)
    winding = None
    if top.get("winding") is not None:  # an empty `winding:` counts as none
        winding = parse_winding(rd, top["winding"], "winding", axis_length=axis_length(mandrel.axis),
                                vessel=vessel)
    machine = parse_machine(rd, top.get("machine"), "machine", bent=_is_bent(mandrel.axis),
                            max_radius=_reach(mandrel, 0.0, math.inf, None))
    return JobConfig(name, source, mandrel, winding, machine)


def axis_length(axis: Axis | None) -> float | None:
    """T, the axis length in mm, when known without computation (not for a spline or None)."""
    if isinstance(axis, LineAxis):
        return axis.length
    if isinstance(axis, ArcAxis):
        return axis.radius * math.radians(axis.angle_deg)
    if isinstance(axis, PathAxis):
        return sum(axis_length(seg) or 0.0 for seg in axis.segments)
    return None


# -- the mandrel -----------------------------------------------------------------------------------
_AXIS_KINDS = {
    "line": (("length",), ()),
    "arc": (("radius", "angle"), ("toward",)),
    "path": (("segments",), ()),
    "spline": (("points",), ()),
}
_PROFILE_KINDS = {
    "constant": (("radius",), ()),
    "cone": (("start_radius", "end_radius"), ()),
    "table": (("points",), ()),
    "vessel": (("radius", "cylinder_length", "dome"), ("end_dome",)),
}
# depth is allowed in every dome so that its misuse gets a message saying why, not "unknown key".
_DOME_KINDS = {
    "hemisphere": (("polar_opening",), ("depth",)),
    "ellipsoid": (("polar_opening", "depth"), ()),
    "isotensoid": (("polar_opening",), ("depth",)),
}
_SECTION_KINDS = {
    "circle": ((), ()),
    "ellipse": (("a", "b"), ()),
    "rounded_rectangle": (("width", "height", "corner_radius"), ()),
    "superellipse": (("a", "b", "exponent"), ()),
}


def _parse_mandrel(rd: Reader, value: Any, path: str) -> MandrelConfig:
    m = rd.mapping(value, path, ("axis", "profile", "section"))
    axis_path, profile_path, section_path = (rd.at(path, key) for key in ("axis", "profile", "section"))
    # Each part on its own first, in the order of the file, so the first message is the topmost.
    axis = _parse_axis(rd, m["axis"], axis_path) if "axis" in m else None
    profile = _parse_profile(rd, m["profile"], profile_path) if "profile" in m else None
    section = _parse_section(rd, m["section"], section_path) if "section" in m else CircleSection()

    if profile is None and isinstance(section, CircleSection):
        raise rd.error(profile_path, "required key missing; a circle section takes its radius from the "
                       "profile (only ellipse, rounded_rectangle and superellipse sections go without)")
    if isinstance(profile, VesselProfile):
        if axis is not None and not isinstance(axis, LineAxis):
            raise rd.error(rd.at(axis_path, "type"), "a vessel needs a straight axis (type: line)",
                           m["axis"]["type"])
        if not isinstance(section, CircleSection):
            # Domes are surfaces of revolution, and dome winding rests on Clairaut's relation.
            raise rd.error(rd.at(section_path, "type"), "a vessel needs a circle section",
                           m["section"]["type"])
    if axis is None and isinstance(profile, TableProfile):
        axis = LineAxis(profile.points[-1][0])
    elif axis is None and not isinstance(profile, VesselProfile):
        # A vessel keeps axis None: its length T needs the dome shapes, which the dome module computes.
        raise rd.error(axis_path, "required key missing; only a vessel or table profile gives the axis "
                       "its length")

    length = axis_length(axis)
    if isinstance(profile, TableProfile) and "axis" in m and length is not None:
        if profile.points[-1][0] < length - LENGTH_SLACK:
            raise rd.error(rd.at(profile_path, "points"), f"must cover the whole axis: the last t must "
                           f"be >= {length:g} (the axis length)", m["profile"]["points"][-1][0])
    mandrel = MandrelConfig(axis, profile, section)
    _check_bends(rd, mandrel, axis_path)
    return mandrel


def _parse_axis(rd: Reader, value: Any, path: str) -> Axis:
    kind, m = rd.typed(value, path, "axis", _AXIS_KINDS)
    if kind == "line":
        return LineAxis(rd.positive(m["length"], rd.at(path, "length")))
    if kind == "arc":
        return _parse_arc(rd, m, path)
    if kind == "path":
        return _parse_path(rd, m["segments"], rd.at(path, "segments"))
    return _parse_spline(rd, m["points"], rd.at(path, "points"))


def _parse_arc(rd: Reader, m: dict[str, Any], path: str) -> ArcAxis:
    radius = rd.positive(m["radius"], rd.at(path, "radius"))
    angle = rd.number(m["angle"], rd.at(path, "angle"))
    if not 0.0 < angle <= 360.0:
        raise rd.error(rd.at(path, "angle"), "must be in (0, 360] degrees", m["angle"])
    toward = rd.number(m.get("toward", 0.0), rd.at(path, "toward"))
    return ArcAxis(radius, angle, toward)


def _parse_path(rd: Reader, value: Any, path: str) -> PathAxis:
    segments: list[LineAxis | ArcAxis] = []
    for i, item in enumerate(rd.listing(value, path, 1, "segment")):
        where = rd.at(path, i)
        seg = rd.mapping(item, where, ("line", "arc"))
        if len(seg) != 1:
            raise rd.error(where, "must hold exactly one of line: L or arc: {radius, angle, toward}", item)
        if "line" in seg:
            segments.append(LineAxis(rd.positive(seg["line"], rd.at(where, "line"))))
        else:
            arc_path = rd.at(where, "arc")
            arc = rd.mapping(seg["arc"], arc_path, ("radius", "angle", "toward"), ("radius", "angle"))
            segments.append(_parse_arc(rd, arc, arc_path))
    return PathAxis(tuple(segments))


def _parse_spline(rd: Reader, value: Any, path: str) -> SplineAxis:
    points: list[tuple[float, float, float]] = []
    for i, item in enumerate(rd.listing(value, path, 2, "point")):
        where = rd.at(path, i)
        if not isinstance(item, list) or len(item) != 3:
            raise rd.error(where, "must be a point [x, y, z]", item)
        x, y, z = (rd.number(c, where, name) for c, name in zip(item, "xyz"))
        if points and (x, y, z) == points[-1]:
            raise rd.error(where, "must differ from the previous point (a zero-length span)", item)
        points.append((x, y, z))
    # SPEC: the guide starts at the origin. Points digitized in shop coordinates are moved there
    # rather than refused: a translation changes neither the surface's shape nor any path length.
    x0, y0, z0 = points[0]
    return SplineAxis(tuple((x - x0, y - y0, z - z0) for x, y, z in points))


def _parse_profile(rd: Reader, value: Any, path: str) -> Profile:
    kind, m = rd.typed(value, path, "profile", _PROFILE_KINDS)
    if kind == "constant":
        return ConstantProfile(rd.positive(m["radius"], rd.at(path, "radius")))
    if kind == "cone":
        return ConeProfile(rd.positive(m["start_radius"], rd.at(path, "start_radius")),
                           rd.positive(m["end_radius"], rd.at(path, "end_radius")))
    if kind == "table":
        return _parse_table(rd, m["points"], rd.at(path, "points"))
    radius_path = rd.at(path, "radius")
    radius = rd.positive(m["radius"], radius_path)
    cylinder = rd.number(m["cylinder_length"], rd.at(path, "cylinder_length"))
    if cylinder < 0.0:
        raise rd.error(rd.at(path, "cylinder_length"), "must be >= 0", m["cylinder_length"])
    dome = _parse_dome(rd, m["dome"], rd.at(path, "dome"), radius, radius_path)
    end_dome = dome
    if "end_dome" in m:
        end_dome = _parse_dome(rd, m["end_dome"], rd.at(path, "end_dome"), radius, radius_path)
    return VesselProfile(radius, cylinder, dome, end_dome)


def _parse_table(rd: Reader, value: Any, path: str) -> TableProfile:
    points: list[tuple[float, float]] = []
    for i, item in enumerate(rd.listing(value, path, 2, "point")):
        where = rd.at(path, i)
        if not isinstance(item, list) or len(item) != 2:
            raise rd.error(where, "must be a pair [t, r]", item)
        t = rd.number(item[0], where, "t")
        r = rd.number(item[1], where, "r")
        if not points and t != 0.0:
            raise rd.error(where, "t of the first point must be 0 (the start of the axis)", item[0])
        if points and t <= points[-1][0]:
            raise rd.error(where, f"t must increase strictly (the previous t is {show_value(points[-1][0])})",
                           item[0])
        if r <= 0.0:
            raise rd.error(where, "r must be > 0", item[1])
        points.append((t, r))
    return TableProfile(tuple(points))


_DOME_DEPTH_REASON = {
    "hemisphere": "a hemisphere's depth is the vessel radius",
    "isotensoid": "an isotensoid's shape follows from the radius and the polar opening",
}


def _parse_dome(rd: Reader, value: Any, path: str, radius: float, radius_path: str) -> Dome:
    kind, m = rd.typed(value, path, "dome", _DOME_KINDS)
    opening_path = rd.at(path, "polar_opening")
    opening = rd.positive(m["polar_opening"], opening_path)
    if opening >= radius:
        raise rd.error(opening_path, f"must be smaller than {radius_path} ({show_value(radius)})",
                       m["polar_opening"])
    depth = None
    if "depth" in m:
        if kind != "ellipsoid":
            raise rd.error(rd.at(path, "depth"), f"only an ellipsoid dome takes a depth; "
                           f"{_DOME_DEPTH_REASON[kind]}", m["depth"])
        depth = rd.positive(m["depth"], rd.at(path, "depth"))
    return Dome(DomeType(kind), opening, depth)


def _parse_section(rd: Reader, value: Any, path: str) -> Section:
    kind, m = rd.typed(value, path, "section", _SECTION_KINDS)
    if kind == "circle":
        return CircleSection()
    if kind == "ellipse":
        return EllipseSection(rd.positive(m["a"], rd.at(path, "a")), rd.positive(m["b"], rd.at(path, "b")))
    if kind == "superellipse":
        a = rd.positive(m["a"], rd.at(path, "a"))
        b = rd.positive(m["b"], rd.at(path, "b"))
        exponent = rd.number(m["exponent"], rd.at(path, "exponent"))
        if exponent < 2.0:
            raise rd.error(rd.at(path, "exponent"), "must be >= 2 (below 2 the outline has corners or "
                           "cusps, and the surface must be smooth for geodesics)", m["exponent"])
        return SuperellipseSection(a, b, exponent)
    width = rd.positive(m["width"], rd.at(path, "width"))
    height = rd.positive(m["height"], rd.at(path, "height"))
    corner = rd.positive(m["corner_radius"], rd.at(path, "corner_radius"))
    if corner > min(width, height) / 2.0:
        raise rd.error(rd.at(path, "corner_radius"), f"must be <= min(width, height) / 2 "
                       f"({show_value(min(width, height) / 2.0)})", m["corner_radius"])
    return RoundedRectangleSection(width, height, corner)


# -- cross checks that need no computation ---------------------------------------------------------
def _is_bent(axis: Axis | None) -> bool:
    """True when a straight-axis winder cannot follow the axis."""
    if axis is None or isinstance(axis, LineAxis):
        return False
    if isinstance(axis, PathAxis):
        return any(isinstance(seg, ArcAxis) for seg in axis.segments)
    if isinstance(axis, SplineAxis):  # straight only when every point lies on one line
        p0, p1 = axis.points[0], axis.points[1]
        d = [b - a for a, b in zip(p0, p1)]
        scale = max(map(abs, d))
        for p in axis.points[2:]:
            e = [b - a for a, b in zip(p0, p)]
            cross = (d[1] * e[2] - d[2] * e[1], d[2] * e[0] - d[0] * e[2], d[0] * e[1] - d[1] * e[0])
            if max(map(abs, cross)) > 1e-9 * scale * max(1.0, max(map(abs, e))):
                return True
        return False
    return True


def _arcs(axis: Axis | None, path: str) -> list[tuple[ArcAxis, float, str]]:
    """Every arc of the axis with its start station t and its key path."""
    if isinstance(axis, ArcAxis):
        return [(axis, 0.0, path)]
    arcs = []
    if isinstance(axis, PathAxis):
        t = 0.0
        for i, seg in enumerate(axis.segments):
            if isinstance(seg, ArcAxis):
                arcs.append((seg, t, Reader.at(Reader.at(Reader.at(path, "segments"), i), "arc")))
            t += axis_length(seg) or 0.0
    return arcs


def _profile_max(profile: Profile, t0: float, t1: float, length: float | None) -> float:
    """The largest profile radius on [t0, t1] (for a table: of its points and linear interpolation;
    the smooth interpolation may overshoot slightly, which the surface module checks)."""
    if isinstance(profile, ConstantProfile):
        return profile.radius
    if isinstance(profile, VesselProfile):
        return profile.radius
    if isinstance(profile, ConeProfile):
        if length is None or length <= 0.0:
            return max(profile.start_radius, profile.end_radius)
        slope = (profile.end_radius - profile.start_radius) / length
        return profile.start_radius + slope * (t0 if slope < 0.0 else min(t1, length))
    ts = [t for t, _ in profile.points]
    rs = [r for _, r in profile.points]

    def interp(t: float) -> float:
        k = min(max(bisect.bisect_right(ts, t), 1), len(ts) - 1)
        w = min(max((t - ts[k - 1]) / (ts[k] - ts[k - 1]), 0.0), 1.0)
        return rs[k - 1] + w * (rs[k] - rs[k - 1])

    inside = [r for t, r in profile.points if t0 < t < t1]
    return max([interp(t0), interp(t1), *inside])


def _section_extent(section: Section, direction_deg: float | None) -> float:
    """The section's extent from the axis in one direction (its support function: the outline is
    convex), or its largest radius when direction_deg is None. 1 for the circle (unit radius)."""
    if isinstance(section, CircleSection):
        return 1.0
    if direction_deg is None:
        if isinstance(section, EllipseSection):
            return max(section.a, section.b)
        if isinstance(section, RoundedRectangleSection):
            c = section.corner_radius
            return math.hypot(section.width / 2 - c, section.height / 2 - c) + c
        # Superellipse: the farthest point may lie between the semi-axes; sample the outline.
        q = 2.0 / section.exponent
        return max(math.hypot(section.a * math.cos(u) ** q, section.b * math.sin(u) ** q)
                   for u in (0.5 * math.pi * k / 2000 for k in range(2001)))
    cx, cy = abs(math.cos(math.radians(direction_deg))), abs(math.sin(math.radians(direction_deg)))
    if isinstance(section, EllipseSection):
        return math.hypot(section.a * cx, section.b * cy)
    if isinstance(section, RoundedRectangleSection):
        c = section.corner_radius
        return (section.width / 2 - c) * cx + (section.height / 2 - c) * cy + c
    dual = section.exponent / (section.exponent - 1.0)  # the support function is the dual norm
    return ((section.a * cx) ** dual + (section.b * cy) ** dual) ** (1.0 / dual)


def _reach(mandrel: MandrelConfig, t0: float, t1: float, direction_deg: float | None) -> float:
    """How far the surface reaches from the axis on [t0, t1] (in one direction, or in any)."""
    profile, section = mandrel.profile, mandrel.section
    extent = _section_extent(section, direction_deg)
    if profile is None:
        return extent
    rmax = _profile_max(profile, t0, t1, axis_length(mandrel.axis))
    if isinstance(section, CircleSection):
        return rmax
    start = {ConstantProfile: lambda p: p.radius, ConeProfile: lambda p: p.start_radius,
             TableProfile: lambda p: p.points[0][1]}[type(profile)](profile)
    return extent * rmax / start  # a section with a profile is scaled by profile(t) / profile(0)


def _check_bends(rd: Reader, mandrel: MandrelConfig, axis_path: str) -> None:
    """SPEC: a section reaching the centre of a bend (the surface folds onto itself) is refused."""
    for arc, t0, arc_path in _arcs(mandrel.axis, axis_path):
        t1 = t0 + (axis_length(arc) or 0.0)
        reach = _reach(mandrel, t0, t1, arc.toward_deg)
        if reach >= arc.radius:
            raise rd.error(rd.at(arc_path, "radius"), f"must be larger than the mandrel's reach toward "
                           f"the inside of the bend ({reach:.6g} mm), or the surface folds onto itself",
                           arc.radius)

"""The `mandrel:` section of a job file -> validated, frozen dataclasses.

Everything a user can get wrong in the mandrel is refused here, before any computation, with one
ConfigError naming the file, the key path and the value (SPEC.md). Checks that need the built surface
(a table's interpolation dipping, a spline bending too tightly, a bend folding the surface onto
itself, dome fits) are left to winder.geometry.build, which knows the key paths as well.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum
from typing import Any

from winder.config.reader import LENGTH_SLACK, MAX_SIZE, Reader, show_value

__all__ = [
    "ArcAxis", "Axis", "CircleSection", "ConeProfile", "ConstantProfile", "Dome", "DomeType", "EllipseSection",
    "LineAxis", "MandrelConfig", "PathAxis", "Profile", "RoundedRectangleSection", "Section", "SplineAxis",
    "SuperellipseSection", "TableProfile", "VesselProfile", "axis_length", "parse_mandrel",
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


def axis_length(axis: Axis | None) -> float | None:
    """T, the axis length in mm, when known without computation (not for a spline or None)."""
    if isinstance(axis, LineAxis):
        return axis.length
    if isinstance(axis, ArcAxis):
        return axis.radius * math.radians(axis.angle_deg)
    if isinstance(axis, PathAxis):
        return sum(axis_length(seg) or 0.0 for seg in axis.segments)
    return None


# A superellipse of exponent 100 is a rectangle whose corners have a radius of a few % of a side.
MAX_EXPONENT = 100.0
# The sharpest bend of a section outline, as a fraction of its size: an ellipse of a / b = 100 has
# radius b^2 / a = a / 10,000 at the ends of its long axis. Sharper is a knife edge, where no fiber
# path converges (and no fiber lies).
MIN_BEND_FRACTION = 1e-4


# -- parsing --------------------------------------------------------------------------------------
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


def parse_mandrel(rd: Reader, value: Any, path: str) -> MandrelConfig:
    """The mandrel section at key path `path`."""
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
    return MandrelConfig(axis, profile, section)


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
        if max(abs(x), abs(y), abs(z)) > MAX_SIZE:
            raise rd.error(where, f"coordinates must lie within +-{MAX_SIZE:g} mm", item)
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
    if cylinder > MAX_SIZE:
        raise rd.error(rd.at(path, "cylinder_length"), f"must be <= {MAX_SIZE:g}", m["cylinder_length"])
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
        if t > MAX_SIZE or r > MAX_SIZE:
            raise rd.error(where, f"t and r must be <= {MAX_SIZE:g}", item)
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
        a, b = rd.positive(m["a"], rd.at(path, "a")), rd.positive(m["b"], rd.at(path, "b"))
        small, large = sorted((a, b))
        if small * small / large < MIN_BEND_FRACTION * large:
            key = "b" if b <= a else "a"
            raise rd.error(rd.at(path, key), f"must be at least {math.sqrt(MIN_BEND_FRACTION) * large:g} "
                           f"(1/{1 / math.sqrt(MIN_BEND_FRACTION):g} of the other semi-axis): flatter, the ends "
                           "are a knife edge no fiber path can be computed over", m[key])
        return EllipseSection(a, b)
    if kind == "superellipse":
        a = rd.positive(m["a"], rd.at(path, "a"))
        b = rd.positive(m["b"], rd.at(path, "b"))
        exponent = rd.number(m["exponent"], rd.at(path, "exponent"))
        if exponent < 2.0:
            raise rd.error(rd.at(path, "exponent"), "must be >= 2 (below 2 the outline has corners or "
                           "cusps, and the surface must be smooth for geodesics)", m["exponent"])
        if exponent > MAX_EXPONENT:
            raise rd.error(rd.at(path, "exponent"), f"must be <= {MAX_EXPONENT:g} (beyond, the corners are too "
                           "sharp for a fiber path; use a rounded_rectangle)", m["exponent"])
        return SuperellipseSection(a, b, exponent)
    width = rd.positive(m["width"], rd.at(path, "width"))
    height = rd.positive(m["height"], rd.at(path, "height"))
    corner = rd.positive(m["corner_radius"], rd.at(path, "corner_radius"))
    if corner < MIN_BEND_FRACTION * max(width, height):
        raise rd.error(rd.at(path, "corner_radius"), f"must be at least {MIN_BEND_FRACTION * max(width, height):g} "
                       f"({MIN_BEND_FRACTION:g} of the larger side): sharper, the corner is a knife edge no fiber "
                       "path can be computed over", m["corner_radius"])
    if corner > min(width, height) / 2.0:
        raise rd.error(rd.at(path, "corner_radius"), f"must be <= min(width, height) / 2 "
                       f"({show_value(min(width, height) / 2.0)})", m["corner_radius"])
    return RoundedRectangleSection(width, height, corner)



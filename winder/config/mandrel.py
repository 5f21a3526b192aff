"""The `mandrel:` section of a job file -> validated, frozen dataclasses.

Everything a user can get wrong in the mandrel is refused here, before any computation, with one
ConfigError naming the file, the key path and the value (docs/guide/commands.md). Checks that need the built surface
(a table's interpolation dipping, a spline bending too tightly, a bend folding the surface onto
itself, dome fits) are left to winder.geometry.build, which knows the key paths as well.

The straight round tube's parts (line axis, constant profile, circle section) are here; the other
kinds are in winder.config.axes, .profiles, .vessel and .sections, which load only for a file that
names them (each costs its dataclasses' creation, which a small job notices).
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

from winder.config.line import LineAxis
from winder.config.reader import LENGTH_SLACK, Reader

if TYPE_CHECKING:
    from winder.config.axes import ArcAxis, PathAxis, SplineAxis
    from winder.config.profiles import ConeProfile, TableProfile
    from winder.config.sections import EllipseSection, RoundedRectangleSection, SuperellipseSection
    from winder.config.vessel import VesselProfile

    Axis = LineAxis | ArcAxis | PathAxis | SplineAxis
    Profile = ConstantProfile | ConeProfile | TableProfile | VesselProfile
    Section = CircleSection | EllipseSection | RoundedRectangleSection | SuperellipseSection

__all__ = ["CircleSection", "ConstantProfile", "LineAxis", "MandrelConfig", "axis_length", "is_vessel",
           "parse_mandrel"]


# -- the dataclasses -------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class ConstantProfile:
    radius: float


@dataclasses.dataclass(frozen=True)
class CircleSection:
    """A circle; its radius is the profile's."""


@dataclasses.dataclass(frozen=True)
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
    if axis is None:
        return None
    if isinstance(axis, LineAxis):
        return axis.length
    from winder.config.axes import bent_axis_length  # noqa: PLC0415 - loaded already: axis is one of its kinds

    return bent_axis_length(axis)


def is_vessel(mandrel: MandrelConfig) -> bool:
    """True for a vessel profile (a cylinder between domes)."""
    if mandrel.profile is None or isinstance(mandrel.profile, ConstantProfile):
        return False
    from winder.config.vessel import VesselProfile  # noqa: PLC0415

    return isinstance(mandrel.profile, VesselProfile)


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
    kind, profile = _parse_profile(rd, m["profile"], profile_path) if "profile" in m else (None, None)
    section = _parse_section(rd, m["section"], section_path) if "section" in m else CircleSection()

    if profile is None and isinstance(section, CircleSection):
        raise rd.error(profile_path, "required key missing; a circle section takes its radius from the "
                       "profile (only ellipse, rounded_rectangle and superellipse sections go without)")
    if kind == "vessel":
        if axis is not None and not isinstance(axis, LineAxis):
            raise rd.error(rd.at(axis_path, "type"), "a vessel needs a straight axis (type: line)",
                           m["axis"]["type"])
        if not isinstance(section, CircleSection):
            # Domes are surfaces of revolution, and dome winding rests on Clairaut's relation.
            raise rd.error(rd.at(section_path, "type"), "a vessel needs a circle section",
                           m["section"]["type"])
    if axis is None and kind == "table":
        axis = LineAxis(profile.points[-1][0])
    elif axis is None and kind != "vessel":
        # A vessel keeps axis None: its length T needs the dome shapes, which the dome module computes.
        raise rd.error(axis_path, "required key missing; only a vessel or table profile gives the axis "
                       "its length")

    length = axis_length(axis)
    if kind == "table" and "axis" in m and length is not None:
        if profile.points[-1][0] < length - LENGTH_SLACK:
            raise rd.error(rd.at(profile_path, "points"), f"must cover the whole axis: the last t must "
                           f"be >= {length:g} (the axis length)", m["profile"]["points"][-1][0])
    return MandrelConfig(axis, profile, section)


def _parse_axis(rd: Reader, value: Any, path: str) -> Axis:
    kind, m = rd.typed(value, path, "axis", _AXIS_KINDS)
    if kind == "line":
        return LineAxis(rd.positive(m["length"], rd.at(path, "length")))
    from winder.config.axes import parse_axis  # noqa: PLC0415

    return parse_axis(rd, kind, m, path)


def _parse_profile(rd: Reader, value: Any, path: str) -> tuple[str, Profile]:
    """(kind, profile)."""
    kind, m = rd.typed(value, path, "profile", _PROFILE_KINDS)
    if kind == "constant":
        return kind, ConstantProfile(rd.positive(m["radius"], rd.at(path, "radius")))
    if kind == "vessel":
        from winder.config.vessel import parse_vessel  # noqa: PLC0415

        return kind, parse_vessel(rd, m, path)
    from winder.config.profiles import parse_profile  # noqa: PLC0415

    return kind, parse_profile(rd, kind, m, path)


def _parse_section(rd: Reader, value: Any, path: str) -> Section:
    kind, m = rd.typed(value, path, "section", _SECTION_KINDS)
    if kind == "circle":
        return CircleSection()
    from winder.config.sections import parse_section  # noqa: PLC0415

    return parse_section(rd, kind, m, path)

"""The `vessel` profile of the `mandrel.profile` key: a cylinder between two domes.

Loads only for a file that names it.
"""

from __future__ import annotations

import dataclasses
from enum import Enum
from typing import Any

from winder.config.reader import MAX_SIZE, Reader, show_value

__all__ = ["Dome", "DomeType", "VesselProfile", "parse_vessel"]


class DomeType(Enum):
    HEMISPHERE = "hemisphere"
    ELLIPSOID = "ellipsoid"
    ISOTENSOID = "isotensoid"


@dataclasses.dataclass(frozen=True)
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


@dataclasses.dataclass(frozen=True)
class VesselProfile:
    """A cylinder of radius R and length cylinder_length (>= 0) between two domes. t = 0 is the plane
    of the first dome's polar opening; end_dome is the dome at t = T (a copy of dome if not given)."""

    radius: float
    cylinder_length: float
    dome: Dome
    end_dome: Dome


# depth is allowed in every dome so that its misuse gets a message saying why, not "unknown key".
_DOME_KINDS = {
    "hemisphere": (("polar_opening",), ("depth",)),
    "ellipsoid": (("polar_opening", "depth"), ()),
    "isotensoid": (("polar_opening",), ("depth",)),
}


def parse_vessel(rd: Reader, m: dict[str, Any], path: str) -> VesselProfile:
    """The vessel profile (its keys already checked by the reader)."""
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

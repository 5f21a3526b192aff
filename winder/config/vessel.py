"""The `vessel` profile of the `mandrel.profile` key: a cylinder between two domes.

Dome kinds: hemisphere, ellipsoid, isotensoid (shapes from a formula), torispherical (crown and knuckle
radii, ASME-style heads) and contour (a liner's meridian from a drawing: points, a CSV of z,r or a DXF;
winder.config.contours reads the files). A closed end has polar_opening 0 and the shaft_radius of the
mandrel shaft the fibers turn around (docs/math/17-vessels-as-built.md 17.5).

Loads only for a file that names it.
"""

from __future__ import annotations

import dataclasses
from enum import Enum
from typing import Any

from winder.config.contours import CONTOUR_TOLERANCE, parse_contour
from winder.config.reader import MAX_SIZE, Reader, show_value

__all__ = ["Dome", "DomeType", "VesselProfile", "parse_vessel"]



class DomeType(Enum):
    HEMISPHERE = "hemisphere"
    ELLIPSOID = "ellipsoid"
    ISOTENSOID = "isotensoid"
    TORISPHERICAL = "torispherical"
    CONTOUR = "contour"


@dataclasses.dataclass(frozen=True)
class Dome:
    """One end dome of a vessel.

    polar_opening: radius (not diameter) of the polar opening (boss), mm; 0 <= polar_opening < R, 0 a
        closed end (then shaft_radius is given). For a contour, the radius its points are trimmed at
        (None: the last point's radius).
    depth: ellipsoid only: the ellipsoid's semi-axis along the vessel axis (mm), i.e. the depth from
        the cylinder's end to the (closed) pole; the part down to the opening is depth *
        sqrt(1 - (polar_opening / R)^2). None for hemisphere (depth R) and isotensoid (its shape
        follows from R and the polar opening).
    crown_radius, knuckle_radius: torispherical only (mm).
    points: contour only: ((z, r), ...) from the junction with the cylinder (z = 0, r = R) toward the pole.
    labels: contour only: how a message names each point (`points[3]`, `liner.csv line 5`, `liner.dxf
        near (z, r) = (...)`), one per point.
    tolerance: contour only: the largest distance (mm) of the smoothed meridian from the points.
    shaft_radius: closed ends only: the radius (mm) of the mandrel shaft the fibers turn around.
    """

    type: DomeType
    polar_opening: float | None
    depth: float | None = None
    _: dataclasses.KW_ONLY
    crown_radius: float | None = None
    knuckle_radius: float | None = None
    points: tuple[tuple[float, float], ...] | None = None
    labels: tuple[str, ...] | None = None
    tolerance: float = CONTOUR_TOLERANCE
    shaft_radius: float | None = None

    @property
    def closed(self) -> bool:
        """A closed end: the fibers turn around the mandrel's shaft."""
        return self.shaft_radius is not None

    @property
    def wound_opening(self) -> float | None:
        """The radius where the wound surface ends: the shaft's on a closed end, else the opening's."""
        return self.shaft_radius if self.closed else self.polar_opening


@dataclasses.dataclass(frozen=True)
class VesselProfile:
    """A cylinder of radius R and length cylinder_length (>= 0) between two domes. t = 0 is the plane
    of the first dome's polar opening; end_dome is the dome at t = T (a copy of dome if not given)."""

    radius: float
    cylinder_length: float
    dome: Dome
    end_dome: Dome


# depth is allowed in every dome so that its misuse gets a message saying why, not "unknown key".
_CLOSED = ("shaft_radius",)
_DOME_KINDS = {
    "hemisphere": (("polar_opening",), ("depth", *_CLOSED)),
    "ellipsoid": (("polar_opening", "depth"), _CLOSED),
    "isotensoid": (("polar_opening",), ("depth", *_CLOSED)),
    "torispherical": (("crown_radius", "knuckle_radius", "polar_opening"), ("depth", *_CLOSED)),
    "contour": ((), ("points", "file", "layer", "tolerance", "polar_opening", "depth", *_CLOSED)),
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
    "torispherical": "a torispherical head's depth follows from its crown and knuckle radii",
    "contour": "a contour's depth is its last point's z",
}


def _parse_dome(rd: Reader, value: Any, path: str, radius: float, radius_path: str) -> Dome:
    kind, m = rd.typed(value, path, "dome", _DOME_KINDS)
    opening_path = rd.at(path, "polar_opening")
    opening = None
    if "polar_opening" in m:
        opening = rd.number(m["polar_opening"], opening_path)
        if opening < 0.0:
            raise rd.error(opening_path, "must be >= 0 (0 is a closed end, with shaft_radius)", m["polar_opening"])
        if opening >= radius:
            raise rd.error(opening_path, f"must be smaller than {radius_path} ({show_value(radius)})",
                           m["polar_opening"])
    shaft = _parse_shaft(rd, m, path, opening, radius, radius_path)
    depth = None
    if "depth" in m:
        if kind != "ellipsoid":
            raise rd.error(rd.at(path, "depth"), f"only an ellipsoid dome takes a depth; "
                           f"{_DOME_DEPTH_REASON[kind]}", m["depth"])
        depth = rd.positive(m["depth"], rd.at(path, "depth"))
    if kind == "torispherical":
        return _torispherical(rd, m, path, radius, radius_path, opening, shaft)
    if kind == "contour":
        points, labels, tolerance = parse_contour(rd, m, path, radius, radius_path, opening, shaft)
        return Dome(DomeType.CONTOUR, opening, points=points, labels=labels, tolerance=tolerance,
                    shaft_radius=shaft)
    return Dome(DomeType(kind), opening, depth, shaft_radius=shaft)


def _parse_shaft(rd: Reader, m: dict, path: str, opening: float | None, radius: float,
                 radius_path: str) -> float | None:
    """A closed end's shaft radius: required with polar_opening 0, refused otherwise."""
    key = rd.at(path, "shaft_radius")
    if "shaft_radius" not in m:
        if opening == 0.0:
            raise rd.error(key, "required key missing; a closed end (polar_opening: 0) needs the radius of the "
                           "mandrel shaft the fibers turn around")
        return None
    if opening != 0.0:
        raise rd.error(key, "applies to a closed end only (polar_opening: 0); a boss's opening is where the "
                       "fibers turn", m["shaft_radius"])
    shaft = rd.positive(m["shaft_radius"], key)
    if shaft >= radius:
        raise rd.error(key, f"must be smaller than {radius_path} ({show_value(radius)})", m["shaft_radius"])
    return shaft


def _torispherical(rd: Reader, m: dict, path: str, radius: float, radius_path: str, opening: float,
                   shaft: float | None) -> Dome:
    """A torispherical head: knuckle_radius < radius <= crown_radius (the crown reaches the knuckle)."""
    knuckle = rd.positive(m["knuckle_radius"], rd.at(path, "knuckle_radius"))
    if knuckle >= radius:
        raise rd.error(rd.at(path, "knuckle_radius"), f"must be smaller than {radius_path} ({show_value(radius)})",
                       m["knuckle_radius"])
    crown = rd.positive(m["crown_radius"], rd.at(path, "crown_radius"))
    if crown < radius:
        raise rd.error(rd.at(path, "crown_radius"), f"must be at least {radius_path} ({show_value(radius)}): a "
                       f"smaller crown cannot reach the knuckle (ASME heads: crown radius about the diameter)",
                       m["crown_radius"])
    return Dome(DomeType.TORISPHERICAL, opening, crown_radius=crown, knuckle_radius=knuckle, shaft_radius=shaft)

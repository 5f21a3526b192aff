"""Bent guide curves of the `mandrel.axis` key: arc, path (lines and arcs) and spline.

The straight line is winder.config.line's; these load only for a file that names them.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from winder.config.line import LineAxis
from winder.config.reader import MAX_SIZE, Reader

__all__ = ["MAX_SEGMENTS", "MAX_SPLINE_POINTS", "ArcAxis", "PathAxis", "SplineAxis", "bent_axis_length", "parse_axis"]

# A bent mandrel's guide has a few to a few dozen pieces; the geometry's checks (folds, the mandrel
# running into itself) compare pieces and points pairwise: 1,000 take `check` about 6 s and 300 MB
# (a spline of 20,000 points took 6 GB), so past these a list is no mandrel's.
MAX_SEGMENTS = 1000
MAX_SPLINE_POINTS = 1000


@dataclasses.dataclass(frozen=True)
class ArcAxis:
    """A circular bend: bend radius (mm), bend angle (deg, in (0, 360]), and the side it bends
    toward, measured like theta from e2 toward e3 (deg; theta = toward is the inside of the bend)."""

    radius: float
    angle_deg: float
    toward_deg: float = 0.0


@dataclasses.dataclass(frozen=True)
class PathAxis:
    """A tangent-continuous chain of lines and arcs; each arc's toward is in the frame at its start."""

    segments: tuple[LineAxis | ArcAxis, ...]


@dataclasses.dataclass(frozen=True)
class SplineAxis:
    """A C2 interpolating curve through the points (mm); the first point is the origin."""

    points: tuple[tuple[float, float, float], ...]


def bent_axis_length(axis: ArcAxis | PathAxis | SplineAxis) -> float | None:
    """T, the axis length in mm, when known without computation (not for a spline)."""
    if isinstance(axis, ArcAxis):
        return axis.radius * math.radians(axis.angle_deg)
    if isinstance(axis, PathAxis):
        return sum(seg.length if isinstance(seg, LineAxis) else bent_axis_length(seg) for seg in axis.segments)
    return None


def parse_axis(rd: Reader, kind: str, m: dict[str, Any], path: str) -> ArcAxis | PathAxis | SplineAxis:
    """The axis of kind arc, path or spline (its keys already checked by the reader)."""
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
    for i, item in enumerate(_bounded(rd, rd.listing(value, path, 1, "segment"), path, MAX_SEGMENTS, "segments")):
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


def _bounded(rd: Reader, items: list[Any], path: str, limit: int, noun: str) -> list[Any]:
    if len(items) > limit:
        raise rd.error(path, f"must have at most {limit:,} {noun} (a mandrel's guide has a few dozen), got "
                       f"{len(items):,}")
    return items


def _parse_spline(rd: Reader, value: Any, path: str) -> SplineAxis:
    points: list[tuple[float, float, float]] = []
    for i, item in enumerate(_bounded(rd, rd.listing(value, path, 2, "point"), path, MAX_SPLINE_POINTS, "points")):
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

"""Varying radius profiles of the `mandrel.profile` key: cone and table.

The constant radius is winder.config.mandrel's own, the vessel winder.config.vessel's; these load
only for a file that names them.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from winder.config.reader import MAX_SIZE, Reader, show_value

__all__ = ["ConeProfile", "TableProfile", "parse_profile"]


@dataclasses.dataclass(frozen=True)
class ConeProfile:
    """Radius linear in t from start_radius at t = 0 to end_radius at t = T."""

    start_radius: float
    end_radius: float


@dataclasses.dataclass(frozen=True)
class TableProfile:
    """(t, r) pairs: t from 0, strictly increasing; r > 0. Interpolated smoothly by the surface."""

    points: tuple[tuple[float, float], ...]


def parse_profile(rd: Reader, kind: str, m: dict[str, Any], path: str) -> ConeProfile | TableProfile:
    """The profile of kind cone or table (its keys already checked by the reader)."""
    if kind == "cone":
        return ConeProfile(rd.positive(m["start_radius"], rd.at(path, "start_radius")),
                           rd.positive(m["end_radius"], rd.at(path, "end_radius")))
    return _parse_table(rd, m["points"], rd.at(path, "points"))


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

"""Non-circular sections of the `mandrel.section` key: ellipse, superellipse, rounded rectangle.

The circle is winder.config.mandrel's own; these load only for a file that names them.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from winder.config.reader import Reader, show_value

__all__ = ["EllipseSection", "MAX_EXPONENT", "MIN_BEND_FRACTION", "RoundedRectangleSection",
           "SuperellipseSection", "parse_section"]


@dataclasses.dataclass(frozen=True)
class EllipseSection:
    """Semi-axis a along e2 and b along e3 (mm)."""

    a: float
    b: float


@dataclasses.dataclass(frozen=True)
class RoundedRectangleSection:
    """width along e2, height along e3, corner radius <= min(width, height) / 2 (mm)."""

    width: float
    height: float
    corner_radius: float


@dataclasses.dataclass(frozen=True)
class SuperellipseSection:
    """|x/a|^p + |y/b|^p = 1 with p = exponent >= 2 (x along e2)."""

    a: float
    b: float
    exponent: float


# A superellipse of exponent 100 is a rectangle whose corners have a radius of a few % of a side.
MAX_EXPONENT = 100.0
# The sharpest bend of a section outline, as a fraction of its size: an ellipse of a / b = 100 has
# radius b^2 / a = a / 10,000 at the ends of its long axis. Sharper is a knife edge, where no fiber
# path converges (and no fiber lies).
MIN_BEND_FRACTION = 1e-4


def parse_section(rd: Reader, kind: str, m: dict[str, Any],
                  path: str) -> EllipseSection | RoundedRectangleSection | SuperellipseSection:
    """The section of kind ellipse, superellipse or rounded_rectangle (its keys already checked by the
    reader)."""
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

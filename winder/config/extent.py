"""What a mandrel config tells without computation: whether its axis is bent, how far it reaches
from its axis (the machine section checks the eye against it)."""

from __future__ import annotations

import bisect
import math
from typing import TYPE_CHECKING

from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig, axis_length

if TYPE_CHECKING:
    from winder.config.mandrel import Axis, Profile, Section

# Each function below settles the straight round tube first; the other kinds' config modules are
# loaded by then (the config holds one of them), so importing their classes costs nothing.


def is_bent(axis: Axis | None) -> bool:
    """True when a straight-axis winder cannot follow the axis."""
    if axis is None or isinstance(axis, LineAxis):
        return False
    from winder.config.axes import ArcAxis, PathAxis, SplineAxis  # noqa: PLC0415

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


def profile_max(profile: Profile, t0: float, t1: float, length: float | None) -> float:
    """The largest profile radius on [t0, t1] (for a table: of its points and linear interpolation;
    the smooth interpolation may overshoot slightly, which the surface module checks)."""
    if isinstance(profile, ConstantProfile):
        return profile.radius
    from winder.config.profiles import ConeProfile  # noqa: PLC0415
    from winder.config.vessel import VesselProfile  # noqa: PLC0415

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


def section_extent(section: Section, direction_deg: float | None) -> float:
    """The section's extent from the axis in one direction (its support function: the outline is
    convex), or its largest radius when direction_deg is None. 1 for the circle (unit radius)."""
    if isinstance(section, CircleSection):
        return 1.0
    from winder.config.sections import EllipseSection, RoundedRectangleSection  # noqa: PLC0415

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


def mandrel_reach(mandrel: MandrelConfig, t0: float, t1: float, direction_deg: float | None) -> float:
    """How far the surface reaches from the axis on [t0, t1] (in one direction, or in any)."""
    profile, section = mandrel.profile, mandrel.section
    extent = section_extent(section, direction_deg)
    if profile is None:
        return extent
    rmax = profile_max(profile, t0, t1, axis_length(mandrel.axis))
    if isinstance(section, CircleSection):
        return rmax
    from winder.config.profiles import ConeProfile, TableProfile  # noqa: PLC0415

    start = {ConstantProfile: lambda p: p.radius, ConeProfile: lambda p: p.start_radius,
             TableProfile: lambda p: p.points[0][1]}[type(profile)](profile)
    return extent * rmax / start  # a section with a profile is scaled by profile(t) / profile(0)

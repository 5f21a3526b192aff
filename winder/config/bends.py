"""The closed-form refusal of a helical angle no friction can hold on a bend (docs/math/07-friction.md), checked with
the config, before any computation.

At the inside of a bend (phi = 0) a circular tube of radius a on bend radius R_b has
k_n = sin^2(alpha) / a - cos^2(alpha) / (R_b - a): a fiber at alpha presses there only if
tan^2(alpha) > a / (R_b - a). Every pass of a helical layer crosses the inside of every bend, so a
layer angle at or below that bridges whatever the friction (R_b 150, a 40: 31.1 deg). Geodesic
layers (slip 0) keep their angle into the bend and are refused here; friction-held ones (auto or a
number) may raise it through the bend, so the planner decides for them.
"""

from __future__ import annotations

import math

from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.config.winding import LayerType, WindingConfig
from winder.errors import InfeasibleConfigError


def least_pressing_angle_deg(bend_radius: float, tube_radius: float) -> float:
    """The angle (deg) at or below which a fiber bridges at the inside of the bend."""
    return math.degrees(math.atan(math.sqrt(tube_radius / (bend_radius - tube_radius))))


def _bends(axis) -> list[tuple[float, float]]:
    """(bend radius, station of the bend's middle) of every arc of a line-and-arc axis."""
    if axis is None or isinstance(axis, LineAxis):
        return []
    from winder.config.axes import ArcAxis, PathAxis  # noqa: PLC0415 - loaded already: axis is one of its kinds

    segments = (axis,) if isinstance(axis, ArcAxis) else axis.segments if isinstance(axis, PathAxis) else ()
    out, t = [], 0.0
    for seg in segments:
        if isinstance(seg, ArcAxis):
            length = seg.radius * math.radians(seg.angle_deg)
            out.append((seg.radius, t + 0.5 * length))
            t += length
        elif isinstance(seg, LineAxis):
            t += seg.length
    return out


def check_bend_angles(mandrel: MandrelConfig, winding: WindingConfig | None, source: str) -> None:
    """Refuse (exit 1) a helical layer whose angle bridges at the inside of a bend of a circular tube."""
    if winding is None or not isinstance(mandrel.profile, ConstantProfile) or not isinstance(
            mandrel.section, CircleSection):
        return
    a = mandrel.profile.radius
    for radius, t_mid in _bends(mandrel.axis):
        if radius <= a:  # the surface folds onto itself: winder.geometry.build refuses it, naming the key
            continue
        least = least_pressing_angle_deg(radius, a)
        for i, layer in enumerate(winding.layers):
            if layer.type is LayerType.HELICAL and layer.slip == 0.0 and layer.angle_deg <= least:
                raise InfeasibleConfigError(
                    f"{source}: {layer.label(i)}: the fiber bridges at the inside of the bend (t = {t_mid:.0f} "
                    f"mm) at {layer.angle_deg:g} deg: below {least:.1f} deg on this bend no friction holds it")

"""Which helical layers are friction-held (docs/guide/config.md): `slip` and
`turnaround_radius` choose between the geodesic planners and the friction-held ones."""

from __future__ import annotations

import math

import numpy as np

from winder.config.winding import SLIP_AUTO, LayerConfig
from winder.errors import ConfigError, SolverError
from winder.geometry.vessel import VesselMeridian
from winder.winding.passes import PlanContext, winding_region
from winder.winding.results import LayerPlan

STEP_BACK_SAMPLES = 4001  # meridian samples to find where a dome reaches a radius
AUTO_MARGIN_MM = 5e-6  # slip auto turns this far outside the polar opening plus half a band (5 solve tolerances)
# Where the pattern cannot be closed that close to an opening (a lambda change would run the fiber
# into it), auto moves the turnaround out by these shares of a band, in turn.
AUTO_STEPS = (0.0, 0.25, 0.5, 1.0)


def friction_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float) -> LayerPlan | None:
    """The friction-held plan of a helical layer, or None where the geodesic planner serves.

    Vessels: a turnaround_radius (per dome), or a slip number, or auto where the geodesic's turnaround
    R sin(alpha) falls inside a dome's own opening plus half a band (auto then turns that dome just
    outside it, docs/math/17 17.6).
    Bent tubes: auto or a number (the largest |lambda| the bends may use). Cones, tables, tapered
    poles: auto holds the angle by friction where the geodesic turns around inside the region
    (docs/math/09). Elsewhere geodesics cover evenly; a slip number there is refused.
    """
    mu, slip = ctx.winding.friction, cfg.slip
    surf = ctx.surface
    # The friction planners load only for the jobs that wind with friction (start-up of small jobs).
    if isinstance(surf.profile, VesselMeridian):
        from winder.winding.layers.friction_vessel import friction_vessel_layer  # noqa: PLC0415
        prof = surf.profile
        floors = dome_floors(ctx, cfg)
        if cfg.turnaround_radius is not None:
            radii = tuple(r if r is not None else floors[d] for d, r in enumerate(cfg.turnaround_radius))
            return friction_vessel_layer(ctx, cfg, index, theta0, mu, radii, 0.0)
        if slip == SLIP_AUTO:
            if prof.radius * math.sin(math.radians(cfg.angle_deg)) > max(floors):
                return None
            return _auto_vessel(ctx, cfg, index, theta0, mu, floors)
        return friction_vessel_layer(ctx, cfg, index, theta0, mu, (None, None), slip) if slip > 0.0 else None
    if slip == 0.0:
        return None
    if not surf.curve.is_straight:  # a bent tube has an arc
        from winder.winding.layers.friction_open import bend_helical_layer, is_bent_tube  # noqa: PLC0415
        if is_bent_tube(ctx):
            return bend_helical_layer(ctx, cfg, index, theta0, mu if slip == SLIP_AUTO else float(slip))
    if slip == SLIP_AUTO and surf.curve.is_straight:
        from winder.winding.layers.friction_revolution import (geodesic_reaches, held_angle_layer,  # noqa: PLC0415
                                                               is_open_revolution)

        if is_open_revolution(surf) and not geodesic_reaches(surf, *winding_region(ctx), cfg.angle_deg):
            return held_angle_layer(ctx, cfg, index, theta0, mu)
    if slip != SLIP_AUTO and surf.curve.is_straight:
        from winder.winding.layers.slip_revolution import slip_layer, tapers  # noqa: PLC0415

        if tapers(surf, *winding_region(ctx)):
            return slip_layer(ctx, cfg, index, theta0)
    if slip != SLIP_AUTO:
        raise ConfigError(f"{ctx.key(index, 'slip')}: a number applies to vessels, bent tubes of lines and arcs, "
                          f"and tapered surfaces of revolution (cones, poles); geodesics cover this mandrel evenly: "
                          f"use 0 or auto, got {slip:g}")
    return None


def dome_floors(ctx: PlanContext, cfg: LayerConfig) -> tuple[float, float]:
    """The least turnaround radius on each dome (first, end): its own opening plus half a band, and a
    step_back from the previous helical layer's turnaround on that dome (docs/math/17 17.6, 08 8.8)."""
    prof = ctx.surface.profile
    half = 0.5 * ctx.winding.band_width
    out = []
    for d, dome in enumerate((prof.dome, prof.end_dome)):
        floor = dome.end_radius + half
        if cfg.step_back > 0.0 and ctx.previous_turnaround is not None:
            floor = max(floor, stepped_back(dome, ctx.previous_turnaround[d], cfg.step_back))
        out.append(floor)
    return out[0], out[1]


def _auto_vessel(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float, mu: float,
                 floors: tuple[float, float]) -> LayerPlan:
    """slip auto on a vessel whose geodesic turns inside a dome's floor: each dome friction-held at its
    own floor (its opening plus half a band, docs/math/17 17.6), just outside it (the solved turnaround
    lands within its tolerance of the target, either side: a small margin); where that needs more than
    the friction on a dome the geodesic clears, that dome stays geodesic; further out by AUTO_STEPS where
    the pattern does not close."""
    from winder.winding.layers.friction_vessel import friction_vessel_layer  # noqa: PLC0415

    band = ctx.winding.band_width
    c_geo = ctx.surface.profile.radius * math.sin(math.radians(cfg.angle_deg))
    tries = []
    for share in AUTO_STEPS:
        held = tuple(f + AUTO_MARGIN_MM + share * band for f in floors)
        tries.append(held)
        if c_geo > min(floors):
            tries.append(tuple(None if c_geo > f else r for f, r in zip(floors, held)))
    for i, radii in enumerate(tries):
        last = i == len(tries) - 1
        try:
            return friction_vessel_layer(ctx, cfg, index, theta0, mu, radii, 0.0, least_mu=last)
        except SolverError:
            if last:
                raise
    raise AssertionError("unreachable")


def stepped_back(dome, c_prev: float, step: float) -> float:
    """The radius `step` mm along the dome's meridian toward the equator from where r = c_prev
    (docs/math/08-laminate-edges.md 8.8)."""
    sigma = np.linspace(0.0, dome.length, STEP_BACK_SAMPLES)
    r = dome.evaluate(sigma).r  # falling from the equator to the opening
    at = float(np.interp(c_prev, r[::-1], sigma[::-1]))
    return max(c_prev, float(dome.evaluate(np.array([max(at - step, 0.0)])).r[0]))

"""A geodesic vessel layer's pattern closed within `winding.angle_tolerance` (docs/math/17 17.7).

Closing a geodesic layer's pattern moves its turnaround radius, hence its angle. Where the planner's own
closure moves the angle past the tolerance, in order: another circuit count (up to EXTRA_COUNTS more)
whose nearest closure is within it; the angle kept and the pattern closed by friction on the domes at
the geodesic's own turnaround radius (winder.winding.layers.friction_vessel); else a refusal naming the
choices `winder patterns` shows and the key to set.
"""

from __future__ import annotations

import math
from dataclasses import replace

from winder.config.winding import LayerConfig
from winder.errors import SolverError
from winder.winding.layers.helical_vessel import vessel_closed_pattern, vessel_closure, vessel_helical_layer
from winder.winding.passes import PlanContext
from winder.winding.pattern import vessel_closures
from winder.winding.results import LayerPlan

EXTRA_COUNTS = 3  # circuit counts tried beyond the planner's
LISTED = 6  # choices a refusal lists
WINDOW_DEG = 3.0  # choices within this of the angle asked are listed
SLACK_DEG = 1e-9


def _angle(c: float, big_r: float) -> float:
    return math.degrees(math.asin(min(1.0, c / big_r)))


def tolerant_vessel_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float) -> LayerPlan:
    """The geodesic layer, its pattern closed within the angle tolerance (module docstring)."""
    tol = ctx.winding.angle_tolerance
    big_r = ctx.surface.profile.radius
    n_c, k, c = vessel_closed_pattern(ctx, cfg, index)
    moved = _angle(c, big_r) - cfg.angle_deg
    if abs(moved) <= tol + SLACK_DEG:
        return vessel_helical_layer(ctx, cfg, index, theta0, (n_c, k, c))
    advance, c0, c_min, c_hi = vessel_closure(ctx, cfg, index)
    if cfg.circuits is None:
        counts = list(range(n_c + 1, n_c + 1 + EXTRA_COUNTS))
        found = [(abs(_angle(cc, big_r) - cfg.angle_deg), n, kk, cc)
                 for n, kk, cc in vessel_closures(advance, c0, c_min, c_hi, counts, cfg.pattern)]
        within = sorted(f for f in found if f[0] <= tol + SLACK_DEG)
        if within:
            _, n, kk, cc = within[0]
            note = (f"{n} circuits instead of {n_c}: with {n_c} the pattern closes only {moved:+.3f} deg from the "
                    f"angle asked, beyond winding.angle_tolerance ({tol:g} deg)")
            return vessel_helical_layer(ctx, cfg, index, theta0, (n, kk, cc), note)
    held = _friction_closed(ctx, cfg, index, theta0, c0)
    if isinstance(held, LayerPlan):
        return held
    raise SolverError(_refusal(ctx, cfg, index, (n_c, moved), held, (advance, c0, c_min, c_hi)))


def _friction_closed(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float, c0: float) -> LayerPlan | str:
    """The layer at its angle, the pattern closed by friction on the domes at the geodesic's turnaround
    radius; else why not (one clause)."""
    from winder.winding.layers.friction_vessel import friction_vessel_layer  # noqa: PLC0415

    mu = ctx.winding.friction
    try:
        done = friction_vessel_layer(ctx, cfg, index, theta0, mu, (c0, c0), 0.0)
    except SolverError as exc:
        return f"friction cannot close it at the angle asked ({str(exc).rsplit(': ', 1)[-1]})"
    note = (f"the pattern closed by friction on the domes at the angle asked: as a geodesic it closes only "
            f"beyond winding.angle_tolerance ({ctx.winding.angle_tolerance:g} deg)")
    return replace(done, notes=done.notes + (note,))


def _refusal(ctx: PlanContext, cfg: LayerConfig, index: int, own: tuple[int, float], why: str, closure) -> str:
    """The refusal: how far the planner's closure moves the angle, what else was tried, the choices."""
    n_c, moved = own
    advance, c0, c_min, c_hi = closure
    big_r = ctx.surface.profile.radius
    tol = ctx.winding.angle_tolerance
    counts = list(range(n_c, n_c + 1 + EXTRA_COUNTS))
    lo = big_r * math.sin(math.radians(max(cfg.angle_deg - WINDOW_DEG, 0.1)))
    hi = big_r * math.sin(math.radians(min(cfg.angle_deg + WINDOW_DEG, 89.0)))
    found = vessel_closures(advance, c0, max(c_min, lo), min(c_hi, hi), counts, None)
    found.sort(key=lambda f: (abs(_angle(f[2], big_r) - cfg.angle_deg), f[0]))
    listed = [f"{_angle(c, big_r):.2f} deg (circuits {n}, pattern {k})" for n, k, c in found[:LISTED]]
    first = found[0] if found else None
    example = ("" if first is None else f"; write one as {{type: helical, angle: {_angle(first[2], big_r):.2f}, "
               f"circuits: {first[0]}, pattern: {first[1]}}}")
    tried = "" if cfg.circuits is not None else f", no count of {n_c + 1} to {n_c + EXTRA_COUNTS} circuits closes within it"
    return (f"{ctx.key(index, 'angle')}: closing the pattern of {n_c} circuits moves the angle {moved:+.3f} deg, "
            f"beyond winding.angle_tolerance ({tol:g} deg){tried}, and {why}; the choices (winder patterns): "
            f"{', '.join(listed) if listed else 'none within ' + format(WINDOW_DEG, 'g') + ' deg'}{example}, or raise "
            f"winding.angle_tolerance, got {cfg.angle_deg:g}")

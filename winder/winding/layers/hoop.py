"""Hoop layers: constant-pitch turns over the cylindrical region, one band width of advance per turn.

A constant-pitch path is a geodesic only where the mandrel is developable along it (straight tubes of
any section); elsewhere it is held by friction alone, so it is refused where |k_g / k_n| > mu.

The band closes when two turns lie at most a band apart across the fiber: on a section of perimeter
P, turns dm apart along the surface (across the circumference) do for dm <= b P / sqrt(P^2 - b^2),
largest P first. A station step dt moves the surface by |Phi_t| across the circumference, 1 on a
straight tube, sqrt(1 + r'^2) on a cone, 1 + r kappa on a bend's outside: the axial pitch is the
allowed dm over the largest such stretch, or the turns spread by it (a 160 -> 85 cone over 500 mm:
0.11 mm bare a turn, 1.1 % of the surface, at the bare pitch).
"""

from __future__ import annotations

import math

import numpy as np

from winder.config.winding import LayerConfig
from winder.winding.coverage import layer_coverage
from winder.winding.layers.hoop_joints import traverse
from winder.geometry.vessel import VesselMeridian
from winder.errors import SolverError
from winder.winding.slip import check_slip
from winder.winding.passes import (
    COVERAGE_STATIONS,
    PlanContext,
    finish_layer,
    make_pass,
    turnaround_passes,
    reference_section,
    winding_region,
)
from winder.winding.results import FiberPass, LayerPlan, PassKind
from winder.winding.turnaround import SWING_MIN_DEG, heading_deg, trace_leg
from winder.geometry.measure import row_norms

HOOP_STEP_DEG = 5.0  # sampling of hoop turns (the machine interpolates A and X linearly)
# A pitch this much above the band's axial width is a gap, not round-off (the angle is read in degrees).
PITCH_GAP_REL = 1e-9
# The grid the largest stretch is sought on: stations a twentieth of a band apart (within these counts;
# a table profile's 20 mm ramp peaks narrowly: a quarter band missed 3 % of it, a 0.3 mm gap), 72 angles.
STRETCH_STEP_BANDS, STRETCH_STATIONS, STRETCH_ANGLES = 0.05, (41, 20001), 72
STRETCH_BLOCK = 50_000  # grid points evaluated at once (a few MB), however long the region
STRETCH_TOL = 1e-12  # a straight tube's stretch is 1 to round-off: its pitch is left exact


def _cylinder_region(ctx: PlanContext) -> tuple[float, float]:
    prof = ctx.surface.profile
    if isinstance(prof, VesselMeridian):
        return prof.equator_t
    return winding_region(ctx)


def _stretch(ctx: PlanContext, t_a: float, t_b: float) -> float:
    """The largest surface distance across the circumference per unit station over the region
    (module docstring): |Phi_t| less its part along Phi_theta, on a grid of stations and angles (one
    angle on a surface of revolution, where it does not depend on theta). The region is an open
    mandrel's (s = t) or a vessel's cylinder (s = t there, up to a shift)."""
    surf = ctx.surface
    n = int(np.clip(math.ceil((t_b - t_a) / (STRETCH_STEP_BANDS * ctx.winding.band_width)) + 1, *STRETCH_STATIONS))
    angles = np.linspace(0.0, 2.0 * math.pi, 1 if surf.is_revolution else STRETCH_ANGLES, endpoint=False)
    ss, tt = (a.ravel() for a in np.meshgrid(surf.s_of_t(np.linspace(t_a, t_b, n)), angles, indexing="ij"))
    worst = 0.0
    for k in range(0, ss.size, STRETCH_BLOCK):
        ev = surf.evaluate(ss[k:k + STRETCH_BLOCK], tt[k:k + STRETCH_BLOCK], order=1, with_point=False)
        along = np.einsum("ij,ij->i", ev.ps, ev.pt) / np.einsum("ij,ij->i", ev.pt, ev.pt)
        worst = max(worst, float(np.max(row_norms(ev.ps - along[:, None] * ev.pt))))
    return 1.0 if worst <= 1.0 + STRETCH_TOL else worst


def _traverses(ctx: PlanContext, cfg: LayerConfig, index: int, t_a: float, t_b: float) -> list[tuple[float, float]]:
    """(start, end) stations of each traverse: from where the last one ended to its far end moved in
    by k taper / P (traverse k of P; docs/math/08-laminate-edges.md 8.9). Without a taper, the region."""
    step = cfg.taper / cfg.passes
    spans, at = [], t_a
    for k in range(cfg.passes):
        end = t_b - k * step if k % 2 == 0 else t_a + k * step
        if (end - at) * (1.0 if k % 2 == 0 else -1.0) <= 0.0:
            raise SolverError(f"{ctx.key(index, 'taper')}: steps the hoop's reversals in by "
                              f"{2.0 * cfg.taper * (cfg.passes - 1) / cfg.passes:g} mm in all, more than the "
                              f"cylindrical region ({t_b - t_a:g} mm), got {cfg.taper:g}")
        spans.append((at, end))
        at = end
    return spans


def hoop_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float) -> LayerPlan:
    surf, w = ctx.surface, ctx.winding
    t_a, t_b = _cylinder_region(ctx)
    s_ref, perimeter = reference_section(ctx, t_a, t_b)
    closed = w.band_width < perimeter
    if cfg.angle_deg is None:
        if not closed:
            raise SolverError(f"{ctx.key(index)}: the band ({w.band_width:g} mm) is wider than the perimeter "
                              f"({perimeter:.3f} mm): a hoop layer cannot be laid")
        alpha = math.degrees(math.acos(w.band_width / perimeter))
    else:
        alpha = cfg.angle_deg
    stretch = _stretch(ctx, t_a, t_b)
    pitch = perimeter / math.tan(math.radians(alpha)) / stretch  # axial advance per turn
    turns = (t_b - t_a) / pitch
    spans = _traverses(ctx, cfg, index, t_a, t_b)
    passes: list[FiberPass] = []
    theta_start = theta0
    for k in range(cfg.passes):
        ctx.report(index, k / cfg.passes, f"hoop traverse {k + 1} of {cfg.passes}")
        f0 = float(ctx.arcs.fraction(np.array([theta_start]))[0])
        turns_k = abs(spans[k][1] - spans[k][0]) / pitch
        m = max(3, int(math.ceil(turns_k * 360.0 / HOOP_STEP_DEG)) + 1)
        forward = k % 2 == 0
        over = traverse(surf, ctx.arcs, *spans[k], f0, pitch * stretch, HOOP_STEP_DEG)  # a bent axis's joints
        if over is None:
            frac = f0 + np.linspace(0.0, turns_k, m)
            t = np.linspace(spans[k][0], spans[k][1], m)
        else:
            t, frac, rates = over
        s = surf.s_of_t(t)
        th = ctx.arcs.theta(frac)
        th[0] = theta_start
        ev = surf.evaluate(s, th, order=1)
        if over is None:
            # Exact tangent of the constant-pitch path: d/dk Phi(s(t), theta(f)), both linear in k
            # (s = t on the cylindrical region).
            vel = ev.ps * (t[1] - t[0]) + ev.pt * (ctx.arcs.dtheta_dfrac(th) * (frac[1] - frac[0]))[:, None]
            speed = row_norms(vel)
            length = float(np.sum(0.5 * (speed[1:] + speed[:-1])))
        else:  # per unit |t|, each piece at its own pitch (winder.winding.layers.hoop_joints)
            sign = 1.0 if spans[k][1] > spans[k][0] else -1.0
            vel = ev.ps * sign + ev.pt * (ctx.arcs.dtheta_dfrac(th) * rates)[:, None]
            speed = row_norms(vel)
            length = float(np.sum(0.5 * (speed[1:] + speed[:-1]) * np.abs(np.diff(t))))
        direction = vel / speed[:, None]
        passes.append(make_pass(surf, index + 1, k + 1, len(passes) + 1, PassKind.HOOP, s, th, direction, length,
                                ev))
        theta_start = float(th[-1])
        if k + 1 < cfg.passes:
            # The carriage reverses while the mandrel turns on (winder.winding.turnaround). The way in
            # leaves with the pass's own last heading: alpha holds on the reference section only (a
            # constant pitch turns steeper where the section is larger, on a cone), and any other
            # heading would kink the fiber and swing the eye back.
            heading = float(heading_deg(surf, s[-1:], th[-1:], direction[-1:])[0])
            leg = trace_leg(surf, float(s[-1]), heading, 1.0 if forward else -1.0, w.friction)
            turn = math.radians(SWING_MIN_DEG) if leg.held_by_end else 0.0
            passes += turnaround_passes(ctx, index + 1, k + 1, len(passes) + 1, leg, float(s[-1]), theta_start,
                                        theta_start + leg.turn + turn,
                                        (leg.apex_heading_deg, 180.0 - leg.apex_heading_deg))
            theta_start = float(passes[-1].theta[-1])
    check_slip(ctx, index, passes[0], turns)
    stations = np.linspace(t_a, t_b, COVERAGE_STATIONS + 2)[1:-1]
    coverage = layer_coverage(surf, ctx.arcs, passes, w.band_width, stations)
    notes = []
    axial = w.band_width / math.sin(math.radians(alpha)) / stretch  # the band's width along the axis
    if pitch > axial * (1.0 + PITCH_GAP_REL):
        # Planned as asked (a spaced hoop can be meant), but a program that leaves most of the surface
        # bare must say so where the engineer reads the layer, as incomplete helical coverage does.
        hint = (f"; leave the angle out ({math.degrees(math.acos(w.band_width / perimeter)):.3f} deg here) "
                f"for a closed hoop" if closed else "")
        notes.append(f"the hoop at {alpha:g} deg advances {pitch:.3f} mm per turn, more than the band covers "
                     f"along the axis ({axial:.3f} mm): coverage stays incomplete ({coverage.covered_fraction:.4f}, "
                     f"gap {coverage.max_gap_mm:.3f} mm){hint}")
    return finish_layer(ctx, cfg, index, alpha, cfg.passes, 1, 0.0, 0.0, None, passes, stations, notes,
                        coverage=coverage)

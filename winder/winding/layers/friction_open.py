"""Helical layers on bent tubes (lines and arcs) held by friction: even bands, closing pattern.

The passes are the closed-form curves of bend_paths: slots evenly spaced on the end sections, the
angle turned on the straight pieces to each arc's whole-period angle, constant through the arcs.
Every forward (and every return) pass advances alike, so the dwells close the pattern as on a straight
tube (docs/math/05-winding.md). The circuit count covers the widest spacing inside the arcs; coverage is measured.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from winder.paths.bend_paths import circuits_needed, design, pass_curves, region_pieces, tube_radius
from winder.config.winding import LayerConfig
from winder.winding.coverage import layer_coverage
from winder.errors import SolverError
from winder.winding.passes import COVERAGE_STATIONS, PlanContext, dwell_pass, finish_layer, make_pass, winding_region
from winder.winding.pattern import close_open_pattern
from winder.winding.results import FiberPass, LayerPlan, PassKind
from winder.winding.turnaround import SWING_MIN_DEG, heading_deg
from winder.geometry.measure import row_norms

MIN_POINTS = 200  # points per pass at the least: the slip is measured from them
COVERED_TARGET = 0.999
GAP_TARGET = 0.02  # of the band width
MAX_EXTRA_CIRCUITS = 8


def is_bent_tube(ctx: PlanContext) -> bool:
    """A circular tube of constant radius on a line-and-arc axis with at least one arc."""
    surf = ctx.surface
    return tube_radius(surf) is not None and not surf.curve.is_straight and any(
        p.is_arc for p in region_pieces(surf, *winding_region(ctx)))


def _directions(ctx: PlanContext, t: np.ndarray, th: np.ndarray, d1: np.ndarray, forward: bool) -> np.ndarray:
    ev = ctx.surface.evaluate(t, th, order=1)
    sign = 1.0 if forward else -1.0
    v = sign * (ev.ps + ev.pt * d1[:, None])
    return v / row_norms(v)[:, None]


def _length(ctx: PlanContext, t: np.ndarray, th: np.ndarray, d1: np.ndarray) -> float:
    ev = ctx.surface.evaluate(t, th, order=1)
    speed = row_norms(ev.ps + ev.pt * d1[:, None])
    return float(abs(np.trapezoid(speed, t)))


def bend_helical_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float, mu: float) -> LayerPlan:
    surf, w = ctx.surface, ctx.winding
    t_a, t_b = winding_region(ctx)
    a = tube_radius(surf)
    alpha = math.radians(cfg.angle_deg)
    try:
        pieces, worst = design(region_pieces(surf, t_a, t_b), alpha, a, mu)
    except SolverError as exc:
        raise SolverError(f"{ctx.key(index)}: {exc}") from exc
    points = max(MIN_POINTS, (w.points or 0) + 2)
    perimeter = 2.0 * math.pi * a
    # The angle at the end sections: the layer's, unless a bend reaches an end (then the bend's).
    ends = (pieces[0].alpha0, pieces[-1].alpha1)
    n_c = cfg.circuits or circuits_needed(pieces, perimeter, min(ends), w.band_width)
    stations = np.linspace(t_a, t_b, COVERAGE_STATIONS + 2)[1:-1]
    # The advance is the same for every pass: one reference pass gives it.
    adv_f = pass_curves(pieces, a, np.zeros(1), 8, True)[4]
    adv_r = pass_curves(pieces, a, np.zeros(1), 8, False)[4]
    for _ in range(MAX_EXTRA_CIRCUITS + 1):
        pat = close_open_pattern(n_c, (adv_f + adv_r) / (2.0 * math.pi), max(w.dwell_start_deg, SWING_MIN_DEG) / 360.0,
                                 max(w.dwell_end_deg, SWING_MIN_DEG) / 360.0, cfg.pattern, ctx.key(index, "pattern"))
        passes = _passes(ctx, index, pieces, a, pat, theta0, points)
        cov = layer_coverage(surf, ctx.arcs, passes, w.band_width, stations)
        if (cfg.pattern is not None or cfg.circuits is not None or cov.covered_fraction >= COVERED_TARGET
                and cov.max_gap_mm <= GAP_TARGET * w.band_width):
            break
        n_c += 1
    angles = ", ".join(f"{math.degrees(p.alpha0):.2f} deg ({p.rounds} rounds) on the bend at t = {p.t0:.4g} mm"
                       for p in pieces if p.is_arc)
    notes = [f"friction-held through the bends: {angles}; the passes turn their angle on the straight pieces; "
             f"designed |k_g / k_n| <= {worst:.3f} (friction {mu:g})"]
    if (pat.dwell_start * 360.0 > max(w.dwell_start_deg, SWING_MIN_DEG) + 1e-9
            or pat.dwell_end * 360.0 > max(w.dwell_end_deg, SWING_MIN_DEG) + 1e-9):
        notes.append(f"dwells lengthened to {pat.dwell_start * 360:.3f} / {pat.dwell_end * 360:.3f} deg to close "
                     f"the pattern (k = {pat.pattern} of {n_c})")
    n_c0 = max(1, math.ceil(perimeter * math.cos(min(ends)) / w.band_width - 1e-9))  # docs/math/05-winding.md, straight tube
    if n_c > n_c0:
        # Without this a count above the closed form the engineer checks against reads as an error.
        notes.append(f"{n_c} circuits instead of {n_c0}: the bands spread apart on the outside of a bend, so "
                     f"more circuits close the gaps there (the straight pieces are covered more than once)")
    if abs(ends[0] - alpha) > 1e-12:
        notes.append(f"the bend reaches the end of the winding region: the angle there is the bend's, "
                     f"{math.degrees(ends[0]):.4f} deg instead of {cfg.angle_deg:g}")
    return finish_layer(ctx, cfg, index, math.degrees(ends[0]), n_c, pat.pattern, pat.dwell_start * 360.0,
                        pat.dwell_end * 360.0, None, passes, stations, notes, cov)


def _passes(ctx: PlanContext, index: int, pieces, a: float, pat, theta0: float, points: int) -> list[FiberPass]:
    """Every pass of the layer in winding order: forward, dwell, return, dwell per circuit."""
    surf = ctx.surface
    t_a, t_b = winding_region(ctx)
    n_c = pat.circuits
    starts = theta0 + 2.0 * math.pi * pat.advance * np.arange(n_c)
    t_f, th_f, d1_f, _, adv_f = pass_curves(pieces, a, starts, points, True)
    ret_starts = starts + adv_f + 2.0 * math.pi * pat.dwell_end
    t_r, th_r, d1_r, _, adv_r = pass_curves(pieces, a, ret_starts, points, False)
    laid: list[FiberPass] = []
    layer = index + 1
    for j in range(n_c):
        ctx.report(index, j / n_c, f"circuit {j + 1} of {n_c}")
        for kind, t, th, d1 in ((PassKind.FORWARD, t_f, th_f[j], d1_f[j]), (PassKind.RETURN, t_r, th_r[j], d1_r[j])):
            direction = _directions(ctx, t, th, d1, kind is PassKind.FORWARD)
            laid.append(make_pass(surf, layer, j + 1, 0, kind, t, th, direction, _length(ctx, t, th, d1)))
    return with_dwells(ctx, layer, laid, lambda k: float(ret_starts[k // 2]) if laid[k].kind is PassKind.FORWARD
                       else theta0 + 2.0 * math.pi * pat.advance * (k // 2 + 1), (t_a, t_b))


def with_dwells(ctx: PlanContext, layer: int, laid: list[FiberPass], end_of, stations: tuple[float, float]) -> list[FiberPass]:
    """The laid passes (forward, return per circuit) in winding order, each followed by its dwell: at
    stations[1] (s) after a forward pass, stations[0] after a return, the mandrel turning to end_of(k)
    (rad) for laid pass k. Between passes the ends hold the fiber while it swings round
    (winder.winding.turnaround)."""
    surf = ctx.surface
    passes: list[FiberPass] = []
    for k, p in enumerate(laid):
        passes.append(replace(p, number=len(passes) + 1))
        nxt = laid[k + 1] if k + 1 < len(laid) else None
        h_in = float(heading_deg(surf, p.s[-1:], p.theta[-1:], p.direction[-1:])[0])
        h_out = float(heading_deg(surf, nxt.s[:1], nxt.theta[:1], nxt.direction[:1])[0]) if nxt else 180.0 - h_in
        passes.append(dwell_pass(ctx, layer, p.circuit, len(passes) + 1,
                                 stations[1] if p.kind is PassKind.FORWARD else stations[0],
                                 float(p.theta[-1]), end_of(k), h_in, h_out))
    return passes

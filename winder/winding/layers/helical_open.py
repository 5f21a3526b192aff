"""Helical layers on open mandrels (tubes, cones, elbows, non-circular sections).

Each circuit is a forward and a return pass, two-point (N-round) geodesics solved by the variational
method between slot end points evenly spaced by arc length along the end sections; dwells at the
ends close the pattern (docs/math/05-winding.md, paper 6.1). On a surface of revolution the circuits are rotated
copies of the first; elsewhere every pass is solved on its own.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from winder.config.winding import DEFAULT_POINTS, LayerConfig
from winder.winding.coverage import layer_coverage
from winder.errors import SolverError
from winder.winding.passes import (
    COVERAGE_STATIONS,
    PlanContext,
    turnaround_passes,
    finish_layer,
    make_pass,
    turned_copies,
    reference_section,
    fine_geodesic,
    pass_points,
    SolvedPass,
    solved_passes,
    winding_region,
)
from winder.winding.pattern import OpenPattern, circuits_for_coverage, close_open_pattern
from winder.winding.results import FiberPass, LayerPlan, PassKind
from winder.winding.slip import check as check_held
from winder.geometry.surface import SweepSurface
from winder.winding.clairaut import revolution_pass
from winder.winding.layers.friction_revolution import is_open_revolution, turn_remedies
from winder.winding.turnaround import SWING_MIN_DEG, Leg, end_note, heading_deg, trace_leg
from winder.winding.advance import (LAMINATE_SPREAD, cylinder_pass, cylinder_reach, near_cylinder, reach_theta,
                                    turnaround_error)

TRACE_RTOL = 1e-10


def _reach(surface: SweepSurface, s_ref: float, starts: np.ndarray, heading_deg: float, s_target: float,
           span: float) -> np.ndarray:
    """theta where the geodesics from (s_ref, starts) (k,) at heading_deg reach station s_target."""
    # 1e-10 is plenty for a pattern advance, and tight tolerances crawl on guides whose third
    # derivative is only piecewise smooth (splines).
    from winder.paths.ode import reach_station  # noqa: PLC0415 - only where winding.advance has no closed form

    th, farthest = reach_station(surface, s_ref, starts, heading_deg, s_target, span, rtol=TRACE_RTOL, atol=TRACE_RTOL)
    for i in np.flatnonzero(np.isnan(th)).tolist():  # a ray that turned around before the target
        raise turnaround_error(surface, float(farthest[i]), heading_deg)
    return th


def _natural_advance(ctx: PlanContext, s_ref: float, s_a: float, s_b: float, alpha_deg: float) -> float:
    """Turns a forward pass advances when it holds the layer angle at the reference station.

    The geodesic through the reference station at the layer angle, followed both ways to the region
    ends: in closed form on surfaces of revolution and general cylinders (winding.advance), traced
    elsewhere. On a surface of revolution one start angle suffices; elsewhere the advance is averaged
    over four start angles (the passes themselves are then solved between their slots).
    """
    surf = ctx.surface
    span = 4.0 * (s_b - s_a) / max(math.cos(math.radians(alpha_deg)), 0.05) + 10.0
    starts = np.array([0.0] if surf.is_revolution else [0.0, 0.5 * math.pi, math.pi, 1.5 * math.pi])
    ends = []
    cylinder = near_cylinder(surf, *(float(v) for v in surf.t_of_s(np.array([s_a, s_b]))), LAMINATE_SPREAD)
    for heading, s_end in ((alpha_deg, s_b), (alpha_deg + 180.0, s_a)):
        if s_end == s_ref:
            th = starts
        elif cylinder:
            th = cylinder_reach(surf, s_ref, starts, math.radians(alpha_deg), s_end)
        else:
            th = reach_theta(surf, s_ref, starts, heading, s_end)
        if th is None:
            th = _reach(surf, s_ref, starts, heading, s_end, span)
        ends.append(th)
    return float(np.mean(ctx.arcs.fraction(ends[0]) - ctx.arcs.fraction(ends[1])))


COVERED_TARGET = 0.999  # covered fraction a helical layer must reach
GAP_TARGET = 0.02  # widest gap allowed, as a fraction of the band width
MAX_CIRCUIT_FACTOR = 4  # at most this many times the closed-form circuit count


def _end_headings(surf: SweepSurface, solved: list) -> np.ndarray:
    """Headings (deg) of solved passes (k) at their first and last points, in one evaluation: (k, 2)."""
    if not solved:
        return np.zeros((0, 2))
    s = np.array([item.s[e] for item in solved for e in (0, -1)])
    th = np.array([item.theta[e] for item in solved for e in (0, -1)])
    d = np.array([item.direction[e] for item in solved for e in (0, -1)])
    return heading_deg(surf, s, th, d).reshape(-1, 2)


def _exact_pass(ctx: PlanContext, a: tuple[float, float], b: tuple[float, float], clairaut: tuple[float, float],
                cylinder: bool, rounds: float) -> SolvedPass | None:
    """The pass from a to b ((t, theta) each) where its geodesic is known without a solve: on a surface
    of revolution by Clairaut's quadrature (clairaut: its constant c and the layer's angle, deg), on a
    cylinder the unrolled line; None elsewhere."""
    surf = ctx.surface
    n = pass_points(ctx.winding, rounds) or DEFAULT_POINTS
    if surf.is_revolution:
        s0, s1 = (float(v) for v in surf.s_of_t(np.array([a[0], b[0]])))
        return SolvedPass(*revolution_pass(surf, s0, s1, a[1], clairaut[0], n, clairaut[1]), None)
    if cylinder:
        return SolvedPass(*cylinder_pass(surf, ctx.arcs, a, b, n), None)
    return None


def _open_passes(ctx: PlanContext, index: int, pat: OpenPattern, natural_fwd: float, theta0: float,
                 ends: tuple[float, float, float, float], legs: tuple[Leg, Leg],
                 clairaut: tuple[float, float]) -> list[FiberPass]:
    """The passes of an open-mandrel helical layer with the pattern `pat`, in winding order: per
    circuit forward, the far end's turnaround, return, the near end's turnaround. clairaut: the
    geodesic's Clairaut constant (mm) and the layer's angle (deg), for a surface of revolution."""
    surf = ctx.surface
    t_a, t_b, s_a, s_b = ends
    leg_a, leg_b = legs
    half_b = leg_b.turn / (4.0 * math.pi)  # turns of the far end's way in (the near end's: in pat.advance)
    f0 = float(ctx.arcs.fraction(np.array([theta0]))[0])
    layer = index + 1
    solved = []
    cylinder = near_cylinder(surf, t_a, t_b, LAMINATE_SPREAD)
    for j in range(pat.circuits if not surf.is_revolution else 1):
        ctx.report(index, j / pat.circuits, f"circuit {j + 1} of {pat.circuits}")
        f_start = f0 + j * pat.advance
        f_fwd_end = f_start + natural_fwd
        f_ret_start = f_fwd_end + 2.0 * half_b + pat.dwell_end
        f_ret_end = f_ret_start + natural_fwd
        th = ctx.arcs.theta(np.array([f_start, f_fwd_end, f_ret_start, f_ret_end]))
        exact = [_exact_pass(ctx, a, b, clairaut, cylinder, natural_fwd)
                 for a, b in (((t_a, th[0]), (t_b, th[1])), ((t_b, th[2]), (t_a, th[3])))]
        if exact[0] is not None:  # known without a solve: its points and tangents as they are
            solved += exact
            continue
        # Cold starts: consecutive circuits lie k / N_c of a turn apart, where the geodesic can look
        # nothing alike (inside vs outside of a bend); coarse-to-fine is robust and as fast.
        solved += [fine_geodesic(ctx, (t_a, th[0]), (t_b, th[1]), None),
                   fine_geodesic(ctx, (t_b, th[2]), (t_a, th[3]), None)]
    # The tangents of all the passes together (solved_passes).
    done = solved if isinstance(solved[0], SolvedPass) else solved_passes(surf, solved)
    solved = list(zip(done[0::2], done[1::2]))
    # Where an end holds the fiber, the swing there runs between the passes' own end headings.
    ends_at = _end_headings(surf, done if not (leg_a.s.size and leg_b.s.size) else []).tolist()
    passes: list[FiberPass] = []
    for j, (fwd, ret) in enumerate(solved):
        nxt = solved[j + 1][0] if j + 1 < len(solved) else None
        nxt_head = ends_at[2 * j + 2][0] if ends_at and j + 1 < len(solved) else None
        if surf.is_revolution:  # every circuit a turned copy: the next one starts as this one
            nxt = fwd
            nxt_head = ends_at[2 * j][0] if ends_at else None
        # The swing joins the directions on either side exactly (a way in and out mirror each other).
        heads_b = ((leg_b.apex_heading_deg, 180.0 - leg_b.apex_heading_deg) if leg_b.s.size
                   else (ends_at[2 * j][1], ends_at[2 * j + 1][0]))
        if leg_a.s.size:
            heads_a = (leg_a.apex_heading_deg, 180.0 - leg_a.apex_heading_deg)
        else:
            h_a = ends_at[2 * j + 1][1]
            heads_a = (h_a, nxt_head if nxt is not None else 180.0 - h_a)
        circuit = j + 1
        passes.append(make_pass(surf, layer, circuit, len(passes) + 1, PassKind.FORWARD, fwd.s, fwd.theta,
                                fwd.direction, fwd.length))
        passes += turnaround_passes(ctx, layer, circuit, len(passes) + 1, leg_b, s_b, float(fwd.theta[-1]),
                                    float(ret.theta[0]), heads_b, (fwd.direction[-1], ret.direction[0]))
        passes.append(make_pass(surf, layer, circuit, len(passes) + 1, PassKind.RETURN, ret.s, ret.theta,
                                ret.direction, ret.length))
        th_next = float(ctx.arcs.theta(np.array([f0 + (j + 1) * pat.advance]))[0])
        # The next circuit's forward pass starts as this one's, turned by the circuit advance.
        if nxt is None:
            joints = None
        elif surf.is_revolution:
            joints = (ret.direction[-1], _turned(fwd.direction[:1], th_next - float(fwd.theta[0]))[0])
        else:
            joints = (ret.direction[-1], nxt.direction[0])
        passes += turnaround_passes(ctx, layer, circuit, len(passes) + 1, leg_a, s_a, float(ret.theta[-1]),
                                    th_next, heads_a, joints)
    if surf.is_revolution:
        # A surface of revolution: circuit j is the first one turned by j circuit advances.
        # The copies' points and angles in one surface evaluation.
        first = list(passes)
        th_first = float(first[0].theta[0])
        shifts = []
        for j in range(1, pat.circuits):
            ctx.report(index, j / pat.circuits, f"circuit {j + 1} of {pat.circuits}")
            shifts.append(float(ctx.arcs.theta(np.array([f0 + j * pat.advance]))[0]) - th_first)
        heads = [(layer, j + 2, len(first) * (j + 1) + i + 1, p.kind, p.length)
                 for j in range(len(shifts)) for i, p in enumerate(first)]
        passes += turned_copies(surf, heads, [(p.s, p.theta, p.direction) for p in first], shifts)
    return passes


def _legs(ctx: PlanContext, s_ref: float, s_a: float, s_b: float, alpha: float) -> tuple[Leg, Leg]:
    """The ways into the end zones past s_a and s_b of a layer at alpha on the reference section; on a
    surface of revolution the pass ends' headings follow from Clairaut (r sin(h) constant)."""
    surf = ctx.surface
    mu = ctx.winding.friction
    if not surf.is_revolution:  # no ways traced: the ends hold the fiber (the heading is only a flag)
        return (trace_leg(surf, s_a, 180.0 - alpha, -1.0, mu), trace_leg(surf, s_b, alpha, 1.0, mu))
    r = surf.radius(np.array([s_ref, s_a, s_b]), np.zeros(3))
    c = float(r[0]) * math.sin(math.radians(alpha))
    h_a, h_b = (math.degrees(math.asin(min(1.0, c / float(v)))) for v in r[1:])
    return trace_leg(surf, s_a, 180.0 - h_a, -1.0, mu), trace_leg(surf, s_b, h_b, 1.0, mu)


def _least_dwells(ctx: PlanContext, legs: tuple[Leg, Leg]) -> tuple[float, float]:
    """The least dwells (turns) at the start and far end: the config's, and where the end holds the
    fiber at least SWING_MIN_DEG for the free fiber to swing round."""
    w = ctx.winding
    return tuple(max(d, SWING_MIN_DEG if leg.held_by_end else 0.0) / 360.0
                 for d, leg in ((w.dwell_start_deg, legs[0]), (w.dwell_end_deg, legs[1])))


class OpenClosure(NamedTuple):
    """What closes an open helical layer's pattern: the region (t_a, t_b, s_a, s_b), the reference
    section (s_ref, perimeter), a forward pass's natural advance (turns), the end legs and the least
    dwells (turns)."""

    t_a: float
    t_b: float
    s_a: float
    s_b: float
    s_ref: float
    perimeter: float
    natural_fwd: float
    legs: tuple[Leg, Leg]
    least: tuple[float, float]

    @property
    def natural(self) -> float:
        """A circuit's advance (turns) before the dwells: both passes and both turnarounds."""
        return 2.0 * self.natural_fwd + (self.legs[0].turn + self.legs[1].turn) / (2.0 * math.pi)


def open_closure(ctx: PlanContext, cfg: LayerConfig, index: int) -> OpenClosure:
    """The quantities an open helical layer's pattern is closed with (close_open_pattern), without its passes."""
    t_a, t_b = winding_region(ctx)
    s_a, s_b = (float(v) for v in ctx.surface.s_of_t(np.array([t_a, t_b])))
    s_ref, perimeter = reference_section(ctx, t_a, t_b)
    try:
        natural_fwd = _natural_advance(ctx, s_ref, s_a, s_b, cfg.angle_deg)
    except SolverError as exc:
        hint = ""
        if "turns around" in exc.message and is_open_revolution(ctx.surface):
            hint = turn_remedies(ctx.surface, (t_a, t_b), cfg.angle_deg, ctx.winding.friction)
        raise SolverError(f"{ctx.key(index, 'angle')}: {exc}{hint}") from exc
    legs = _legs(ctx, s_ref, s_a, s_b, cfg.angle_deg)
    return OpenClosure(t_a, t_b, s_a, s_b, s_ref, perimeter, natural_fwd, legs, _least_dwells(ctx, legs))


def open_helical_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float) -> LayerPlan:
    """Open mandrels. On a surface of revolution N_c = ceil(P cos(alpha) / B) covers by construction.
    Elsewhere (bends, non-circular sections) geodesics between evenly spaced slots drift apart
    (toward the inside of a bend, which is shorter); the circuit count is then raised until the
    measured coverage is complete, and the note says by how much."""
    surf, w = ctx.surface, ctx.winding
    closure = open_closure(ctx, cfg, index)
    t_a, t_b, s_a, s_b, s_ref, perimeter, natural_fwd, legs, least = closure
    alpha = cfg.angle_deg
    clairaut = (float(surf.radius(np.array([s_ref]), np.zeros(1))[0]) * math.sin(math.radians(alpha)), alpha)
    n_c0 = n_c = circuits_for_coverage(perimeter, math.radians(alpha), w.band_width)
    notes: list[str] = []
    if cfg.circuits is not None:  # the engineer's count (winder patterns): wound as given, never raised
        if cfg.circuits < n_c0:
            notes.append(f"{cfg.circuits} circuits as given, fewer than the {n_c0} whose bands span the perimeter "
                         f"(P cos(alpha) / B): the layer leaves gaps")
        n_c0 = n_c = cfg.circuits
    stations = np.linspace(t_a, t_b, COVERAGE_STATIONS + 2)[1:-1]
    ends = (t_a, t_b, s_a, s_b)
    last_cov = None
    cov = None
    held = None
    # passes known without a solve (_exact_pass) are geodesics: the slip check takes their curvature exactly
    lines = not surf.is_revolution and near_cylinder(surf, t_a, t_b, LAMINATE_SPREAD)
    exact = frozenset((PassKind.FORWARD, PassKind.RETURN)) if surf.is_revolution or lines else frozenset()
    while True:
        pat = close_open_pattern(n_c, closure.natural, *least, cfg.pattern, ctx.key(index, "pattern"))
        passes = _open_passes(ctx, index, pat, natural_fwd, theta0, ends, legs, clairaut)
        # A fiber that bridges or slips is refused before more circuits are tried (they would too).
        held = check_held(surf, [p for p in passes if p.kind is not PassKind.DWELL], w.friction, ctx.key(index),
                          alpha, ctx.bridging_tolerance(index), exact, w.region, lines)
        if surf.is_revolution or cfg.pattern is not None or cfg.circuits is not None:
            break
        cov = layer_coverage(surf, ctx.arcs, passes, w.band_width, stations)
        if cov.covered_fraction >= COVERED_TARGET and cov.max_gap_mm <= GAP_TARGET * w.band_width:
            break
        grow = max(n_c + 1, math.ceil(n_c * min(2.0, 1.1 / max(cov.covered_fraction, 0.05))))
        # Stop when more circuits no longer close the gaps: the passes bunch whatever their number.
        stuck = last_cov is not None and 1.0 - cov.covered_fraction > 0.75 * (1.0 - last_cov)
        last_cov = cov.covered_fraction
        if grow > MAX_CIRCUIT_FACTOR * n_c0 or stuck:
            notes.append(f"coverage stays incomplete ({cov.covered_fraction:.4f}, gap {cov.max_gap_mm:.3f} mm) "
                         f"up to {n_c} circuits: the geodesic passes at {alpha:g} deg bunch on this mandrel "
                         f"(toward the inside of a bend, the shorter way) and more circuits do not close the "
                         f"gaps; a gentler bend, or friction-held non-geodesic winding, is needed")
            break
        n_c = grow
    if n_c > n_c0:
        notes.append(f"{n_c} circuits instead of {n_c0}: the geodesic passes between evenly spaced end slots "
                     f"drift together on this mandrel, and the closed-form count would leave gaps")
    notes += [end_note(surf, leg, name) for leg, name in zip(legs, ("start", "far end"))]
    if pat.dwell_start > least[0] + 1e-12 or pat.dwell_end > least[1] + 1e-12:
        notes.append(f"dwells lengthened to {pat.dwell_start * 360:.3f} / {pat.dwell_end * 360:.3f} deg to close "
                     f"the pattern (k = {pat.pattern} of {n_c})")
    return finish_layer(ctx, cfg, index, alpha, n_c, pat.pattern, pat.dwell_start * 360.0, pat.dwell_end * 360.0,
                  None, passes, stations, notes, cov, held)


def _turned(d: np.ndarray, shift: float) -> np.ndarray:
    """Directions (m, 3) turned with a circuit by shift (rad) about the straight axis (+z)."""
    c, s = math.cos(shift), math.sin(shift)
    return np.column_stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1], d[:, 2]])



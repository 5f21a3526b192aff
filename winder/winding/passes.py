"""Shared pieces of layer planning: the planning context, fiber passes, dwells, layer assembly."""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from winder.config.job import JobConfig
from winder.config.winding import DEFAULT_POINTS, LayerConfig, WindingConfig
from winder.winding.coverage import layer_coverage
from winder.errors import ConfigError, SolverError
from winder.progress import Progress
from winder.winding.results import Coverage, FiberPass, LayerPlan, PassKind, winding_angle_of
from winder.winding.slip import LayerSlip, check as check_held
from winder.winding.turnaround import HOOP_HEADING_TOL, Leg, directions_of_heading, leg_way, swing_headings
from winder.geometry.interp import interp_spline
from winder.paths.resolution import POINTS_PER_ROUND
from winder.winding.advance import is_cylinder
from winder.geometry.sections import ArcMap, polar_arcs
from winder.geometry.surface import SurfaceEval, SweepSurface
from winder.geometry.measure import row_norms

if TYPE_CHECKING:
    from winder.paths.geodesic import GeodesicResult

COVERAGE_STATIONS = 21
DWELL_STEP_DEG = 2.0  # sampling of a dwell arc
DWELL_MIN_RAD = 1e-12  # a shorter dwell is round-off between a way in and its way out: none
# A pass is re-solved on this many times finer segments (warm-started, Richardson-refined) for its
# points and tangents: at 30 points per pass a spline through the vertices alone misses the tangent
# by up to 1 deg next to a dome turnaround; 4x brings r sin(alpha) to 1e-6 of Clairaut there.
TANGENT_REFINE = 4
# A pass is refined (for a tolerance, or when it does not converge) up to this many points, then it
# fails (exit 1): its tangent solve on TANGENT_REFINE times finer segments, with its Richardson twin,
# then stays within ~0.5 GB (winder.winding.budget holds the rest).
REFINE_MAX_POINTS = 20_000
# Fine vertices of the passes whose tangent splines are solved together (one banded system, many
# right-hand sides): bounds the right-hand sides' memory at 2 x 8 bytes a vertex (16 MB).
TANGENT_BATCH_POINTS = 1 << 20


class SolvedPass(NamedTuple):
    """A solved pass: s, theta (m,) float vertices; direction (m, 3) unit tangents; length (mm)."""

    s: np.ndarray
    theta: np.ndarray
    direction: np.ndarray
    length: float
    result: GeodesicResult

@dataclasses.dataclass(frozen=True)
class PlanContext:
    job: JobConfig
    winding: WindingConfig
    surface: SweepSurface
    arcs: ArcMap
    feed: float  # mm/min
    progress: Progress | None = None  # (fraction of the whole job, label); see winder.progress
    # the last helical layer's turnaround radius on each dome (first, end) (mm), for step_back
    previous_turnaround: tuple[float, float] | None = None

    def key(self, index: int, field: str | None = None) -> str:
        """`file: layer 5 (helical 16 deg)` (and `.field`): layer `index` (0-based) in a message."""
        base = f"{self.job.source}: {self.winding.layers[index].label(index)}"
        return f"{base}.{field}" if field else base

    def bridging_tolerance(self, index: int) -> float:
        """The lift-off (mm) layer `index` may bridge: winding.bridging_tolerance, else one ply of its
        material, else 0 (docs/math/08-laminate-edges.md 8.10)."""
        w = self.winding
        if w.bridging_tolerance is not None:
            return w.bridging_tolerance
        material = w.material_of(index)
        if material is None:
            return 0.0
        from dataclasses import asdict  # noqa: PLC0415

        from winder.winding.laminate import Material  # noqa: PLC0415 - jobs with a material only
        return Material(**asdict(material)).ply(w.band_width)

    def report(self, index: int, done: float, what: str = "") -> None:
        """Progress of layer index (0-based): done in [0, 1] of it, what it is doing now."""
        if self.progress is None:
            return
        n = max(len(self.winding.layers), 1)
        label = f"layer {index + 1} of {n}" + (f": {what}" if what else "")
        self.progress((index + min(max(done, 0.0), 1.0)) / n, label)


# -- passes ---------------------------------------------------------------------------------------
def directions(surface: SweepSurface, s: np.ndarray, theta: np.ndarray, ev: SurfaceEval | None = None) -> np.ndarray:
    """Unit tangents (m, 3) of the smooth curve through the vertices, in laying order; ev: the surface
    there (order >= 1), when the caller has it."""
    i = np.arange(s.shape[0], dtype=float)
    # Quintic: the cubic's end slopes are O(h^3) off, visible next to a turnaround.
    k = min(5, s.shape[0] - 1 - (s.shape[0] % 2 == 1 and s.shape[0] < 7))
    arcs = polar_arcs(surface.section)  # a flat meeting a corner: the spline against arc length
    along = theta if arcs is None else arcs.fraction(theta)
    ds, dth = interp_spline(i, np.column_stack([s, along]), k)(i, 1).T
    if arcs is not None:
        dth = dth * arcs.dtheta_dfrac(theta)
    if ev is None:
        ev = surface.evaluate(s, theta, order=1)
    v = ev.ps * ds[:, None] + ev.pt * dth[:, None]
    return v / row_norms(v)[:, None]


def make_pass(surface: SweepSurface, layer: int, circuit: int, number: int, kind: PassKind,
               s: np.ndarray, theta: np.ndarray, direction: np.ndarray | None, length: float,
               ev: SurfaceEval | None = None) -> FiberPass:
    """A pass of the vertices (s, theta); ev: the surface there (order >= 1, with its points), when
    the caller has it."""
    # One evaluation of order 1 gives the points too (the same arithmetic as order 0's).
    if ev is None:
        ev = surface.evaluate(s, theta, order=1)
    if direction is None:
        direction = directions(surface, s, theta, ev)
    return FiberPass(layer, circuit, number, kind, surface.t_of_s(s), s, theta, ev.p, direction,
                     winding_angle_of(ev, direction), float(length))


def make_passes(surface: SweepSurface, heads: list[tuple[int, int, int, PassKind, float]], sizes: list[int],
                s: np.ndarray, theta: np.ndarray, direction: np.ndarray) -> list[FiberPass]:
    """make_pass of many passes with their directions given, from one surface evaluation: stations,
    points and winding angles are pointwise, so each pass gets what make_pass would give it.

    heads : per pass (layer, circuit, number, kind, length); sizes : per pass its point count m_i;
    s, theta : (sum m_i,) float and direction (sum m_i, 3) float, the passes one after the other.
    """
    if not heads:
        return []
    t = surface.t_of_s(s)
    ev = surface.evaluate(s, theta, order=1)
    alpha = winding_angle_of(ev, direction)
    stop = np.cumsum(sizes).tolist()
    spans = list(zip([0] + stop[:-1], stop))
    parts = ([a[i:j] for i, j in spans] for a in (t, s, theta, ev.p, direction, alpha))
    return [FiberPass(layer, circuit, number, kind, *arrays, float(length))
            for (layer, circuit, number, kind, length), *arrays in zip(heads, *parts)]


def turned_copies(surface: SweepSurface, heads: list[tuple[int, int, int, PassKind, float]],
                  templates: list[tuple[np.ndarray, np.ndarray, np.ndarray]], shifts: list[float]) -> list[FiberPass]:
    """make_passes of the templates (s, theta, direction) turned about the straight axis (+z) by each
    shift (rad) in turn: theta + shift, the directions turned with it (math.cos / sin of the shift, as
    a copy made one at a time would). heads: one per copy, shift-major (len(shifts) * len(templates))."""
    if not shifts or not templates:
        return []
    s = np.concatenate([t[0] for t in templates])
    theta = np.concatenate([t[1] for t in templates])
    d = np.concatenate([t[2] for t in templates])
    c = np.array([math.cos(v) for v in shifts])[:, None]
    sn = np.array([math.sin(v) for v in shifts])[:, None]
    x = c * d[:, 0] - sn * d[:, 1]
    y = sn * d[:, 0] + c * d[:, 1]
    turned = np.stack([x, y, np.broadcast_to(d[:, 2], x.shape)], axis=-1).reshape(-1, 3)
    return make_passes(surface, heads, [t[0].size for t in templates] * len(shifts), np.tile(s, len(shifts)),
                       (theta + np.array(shifts)[:, None]).reshape(-1), turned)


def pass_points(w: WindingConfig, rounds: float) -> int:
    """Interior points of a pass sweeping `rounds` turns: winding.points where the config writes it
    (or None in tolerance mode: the solver chooses), else DEFAULT_POINTS and at least POINTS_PER_ROUND a
    round, so that a long thin pass is not refused for the points winder chose itself."""
    if w.points_given or w.points is None:
        return w.points
    return max(DEFAULT_POINTS, math.ceil(POINTS_PER_ROUND * abs(rounds)))


def solve_pass(ctx: PlanContext, a: tuple[float, float], b: tuple[float, float],
               warm: tuple[np.ndarray, np.ndarray] | None, n: int | None = None) -> SolvedPass:
    """A two-point geodesic pass at n points (default: the config's), with exact-to-print tangents.

    The pass is solved at n, then re-solved at TANGENT_REFINE times finer segments from it; the
    returned vertices are the fine solution's (Richardson-refined) at the n + 2 shared fractions and
    the directions the tangents of the smooth curve through all the fine vertices.
    """
    return solved_passes(ctx.surface, [fine_geodesic(ctx, a, b, warm, n)])[0]


def fine_geodesic(ctx: PlanContext, a: tuple[float, float], b: tuple[float, float],
                  warm: tuple[np.ndarray, np.ndarray] | None, n: int | None = None) -> GeodesicResult:
    """The fine solve of solve_pass (its tangents are solved_passes')."""
    from winder.paths.geodesic import geodesic  # noqa: PLC0415 - the solver loads with the first geodesic pass

    w = ctx.winding
    n = n or pass_points(w, (b[1] - a[1]) / (2.0 * math.pi)) or DEFAULT_POINTS
    if warm is None and not ctx.arcs.identity and ctx.surface.curve.is_straight:
        warm = unrolled_line(ctx, a, b, n)
    res = _solve(ctx, a, b, n, warm, max(REFINE_MAX_POINTS, n))
    for _ in range(2):
        if res.converged or 2 * n + 1 > max(REFINE_MAX_POINTS, n):
            break
        # Too coarse for a sharp stretch (a turnaround close to a small dome's hook): halve the
        # segments, warm-started from the path so far.
        n = 2 * n + 1
        res = _solve(ctx, a, b, n, (res.s, res.theta), REFINE_MAX_POINTS)
    _check_converged(ctx, a, b, res)
    fine = geodesic(ctx.surface, a, b, n=TANGENT_REFINE * (res.n + 1) - 1, init=(res.refined_s, res.refined_theta))
    _check_converged(ctx, a, b, fine)
    return fine


def unrolled_line(ctx: PlanContext, a: tuple[float, float], b: tuple[float, float], n: int) -> tuple[np.ndarray, np.ndarray]:
    """The geodesic from a to b ((t, theta) each) on a general cylinder, n interior points: unrolled,
    a straight line, so the section's arc-length fraction runs linearly with the station (docs/math/04-checks.md;
    winder.winding.advance). A start path the solver only polishes: from the straight (s, theta)
    segment a long pass over a rounded rectangle's corners (five turns over 1900 mm) did not converge."""
    s0, s1 = (float(v) for v in ctx.surface.s_of_t(np.array([a[0], b[0]])))
    f = np.linspace(0.0, 1.0, n + 2)
    frac = ctx.arcs.fraction(np.array([a[1], b[1]]))
    return s0 + (s1 - s0) * f, ctx.arcs.theta(frac[0] + (frac[1] - frac[0]) * f)


def _solve(ctx: PlanContext, a: tuple[float, float], b: tuple[float, float], n: int,
           init: tuple[np.ndarray, np.ndarray] | None, max_points: int) -> GeodesicResult:
    """The geodesic of a pass to winding.tolerance; the solver's refusal of the tolerance names that key."""
    from winder.paths.geodesic import geodesic  # noqa: PLC0415 - the solver loads with the first geodesic pass

    try:
        return geodesic(ctx.surface, a, b, n=n, tolerance=ctx.winding.tolerance, init=init, max_points=max_points)
    except SolverError as exc:
        if exc.key_path != "tolerance":
            raise
        raise SolverError(exc.message, file=ctx.job.source, key_path="winding.tolerance") from exc
    except ConfigError as exc:  # too few points for the rounds a pass sweeps
        if exc.key_path != "points":
            raise
        raise ConfigError(exc.message, file=ctx.job.source, key_path="winding.points") from exc


def solved_passes(surface: SweepSurface, fines: list[GeodesicResult]) -> list[SolvedPass]:
    """The passes of fine solves (fine_geodesic): every TANGENT_REFINE-th refined vertex, with the
    tangent there of the smooth curve through all of them (directions). Solves of one size share one
    spline system (the sites are the index), so their splines come from one banded solve, and every
    tangent from one surface evaluation; values pointwise the same as directions' (the spline's and
    the surface's arithmetic is per point and per column)."""
    k = TANGENT_REFINE
    out: list[SolvedPass | None] = [None] * len(fines)
    groups: dict[int, list[int]] = {}
    for j, f in enumerate(fines):
        groups.setdefault(f.refined_s.size, []).append(j)
    for m, members in groups.items():
        step = max(1, TANGENT_BATCH_POINTS // m)
        for lo in range(0, len(members), step):
            chunk = members[lo:lo + step]
            d = _tangents(surface, [(fines[j].refined_s, fines[j].refined_theta) for j in chunk], k)
            for j, dj in zip(chunk, d):
                f = fines[j]
                out[j] = SolvedPass(f.refined_s[::k], f.refined_theta[::k], dj, f.length, f)
    return out


def _tangents(surface: SweepSurface, paths: list[tuple[np.ndarray, np.ndarray]], every: int) -> list[np.ndarray]:
    """directions(surface, s, theta)[::every] of each path (s, theta), all (m,): (q, 3) each."""
    m = paths[0][0].size
    i = np.arange(m, dtype=float)
    # the degree directions takes
    k = min(5, m - 1 - (m % 2 == 1 and m < 7))
    arcs = polar_arcs(surface.section)  # as directions: against arc length on a non-circular section
    columns = [a if j == 0 or arcs is None else arcs.fraction(a) for path in paths for j, a in enumerate(path)]
    rate = interp_spline(i, np.column_stack(columns), k)(i[::every], 1)
    q = rate.shape[0]
    s = np.concatenate([path[0][::every] for path in paths])
    th = np.concatenate([path[1][::every] for path in paths])
    if arcs is not None:
        rate[:, 1::2] *= arcs.dtheta_dfrac(th).reshape(len(paths), q).T
    ev = surface.evaluate(s, th, order=1)
    v = ev.ps * rate[:, 0::2].T.reshape(-1)[:, None] + ev.pt * rate[:, 1::2].T.reshape(-1)[:, None]
    v = v / row_norms(v)[:, None]
    return [v[j * q:(j + 1) * q] for j in range(len(paths))]


def _check_converged(ctx: PlanContext, a: tuple[float, float], b: tuple[float, float],
                     res: GeodesicResult) -> None:
    if not res.converged:
        raise SolverError(f"{ctx.job.source}: a pass from t = {a[0]:.3f} to t = {b[0]:.3f} did not converge "
                          f"({res.reason.value})")


def dwell_pass(ctx: PlanContext, layer: int, circuit: int, number: int, s: float, th0: float,
              th1: float, heading_in: float = 90.0, heading_out: float = 90.0) -> FiberPass:
    """A dwell: the mandrel turns from th0 to th1 with the fiber on the parallel at station s. Where
    the fiber arrives or leaves off the parallel (heading_in / heading_out deg, 90: along it), the end
    holds it and the free fiber swings through the hoop meanwhile (winder.winding.turnaround)."""
    m = max(2, int(math.ceil(abs(math.degrees(th1 - th0)) / DWELL_STEP_DEG)) + 1)
    th = np.linspace(th0, th1, m)
    ss = np.full(m, s)
    ev = ctx.surface.evaluate(ss, th, order=1)  # its points are order 0's, bit for bit
    if abs(heading_in - 90.0) <= HOOP_HEADING_TOL and abs(heading_out - 90.0) <= HOOP_HEADING_TOL:
        direction = ev.pt / row_norms(ev.pt)[:, None]
    else:
        swing = swing_headings(np.linspace(0.0, 1.0, m), heading_in, heading_out)
        direction = directions_of_heading(ctx.surface, ss, th, swing)
    length = float(np.sum(row_norms(np.diff(ev.p, axis=0))))
    return make_pass(ctx.surface, layer, circuit, number, PassKind.DWELL, ss, th, direction, length, ev)


def turnaround_passes(ctx: PlanContext, layer: int, circuit: int, number: int, leg: Leg, s_end: float,
                      th_in: float, th_next: float, headings: tuple[float, float],
                      joints: tuple[np.ndarray, np.ndarray] | None = None) -> list[FiberPass]:
    """One end's turnaround (winder.winding.turnaround) from th_in, where a pass ended at station
    s_end, to th_next, where the next one starts: the way in, the dwell at the apex (a swing between
    `headings` where the end holds the fiber), the way out; passes numbered from `number`. joints:
    the directions (3,) the pass before ends with and the pass after starts with; the ways take them
    at the joints (they agree to ~1e-6 rad, and the eye must not step between them). A way's length
    is its traced arc length."""
    surf = ctx.surface
    th_apex = th_in + 0.5 * leg.turn
    turn = th_next - th_in - leg.turn
    passes: list[FiberPass] = []
    if leg.s.size:
        s, th, d = leg_way(surf, leg, th_in, False)
        if joints is not None:
            d[0] = joints[0]
        passes.append(make_pass(surf, layer, circuit, number, PassKind.TURNAROUND, s, th, d, leg.length))
    if turn > DWELL_MIN_RAD:
        s_apex = float(leg.s[-1]) if leg.s.size else s_end
        passes.append(dwell_pass(ctx, layer, circuit, number + len(passes), s_apex, th_apex, th_apex + turn,
                                 *headings))
    if leg.s.size:
        s, th, d = leg_way(surf, leg, th_apex + max(turn, 0.0), True)
        if joints is not None:
            d[-1] = joints[1]
        passes.append(make_pass(surf, layer, circuit, number + len(passes), PassKind.TURNAROUND, s, th, d,
                                leg.length))
    return passes


def winding_region(ctx: PlanContext) -> tuple[float, float]:
    if ctx.winding.region is not None:
        return ctx.winding.region
    return 0.0, ctx.surface.axial_length


def reference_section(ctx: PlanContext, t_a: float, t_b: float) -> tuple[float, float]:
    """Station (s) and perimeter of the largest section of the region: the reference section."""
    ts = np.linspace(t_a, t_b, 41)
    ss = ctx.surface.s_of_t(ts)
    per = ctx.surface.perimeter(ss)
    k = int(np.argmax(per))
    return float(ss[k]), float(per[k])

def finish_layer(ctx: PlanContext, cfg: LayerConfig, index: int, alpha: float, circuits: int, pattern: int,
           dwell_a: float, dwell_b: float, c: float | None, passes: list[FiberPass], stations: np.ndarray,
           notes: list[str], coverage: Coverage | None = None, held: LayerSlip | None = None) -> LayerPlan:
    """The layer's plan from its passes; coverage and held (the slip check of its laid passes), when the
    caller measured them on these passes already, are not measured again."""
    laid = [p for p in passes if p.kind is not PassKind.DWELL]
    # The angle range is the winding region's: turnarounds run through every angle up to the hoop.
    # A pass's ends are laid too: a cone's angle is extreme at the region's ends, a vessel's (90) at c.
    wound = [p for p in laid if p.kind is not PassKind.TURNAROUND]
    folded = np.concatenate([np.abs(p.alpha_deg) for p in wound]) if wound else np.zeros(1)
    length = float(sum(p.length for p in passes))
    if coverage is None:
        coverage = layer_coverage(ctx.surface, ctx.arcs, passes, ctx.winding.band_width, stations)
    if held is None:
        held = check_held(ctx.surface, laid, ctx.winding.friction, ctx.key(index), float(alpha),
                          ctx.bridging_tolerance(index), wound=ctx.winding.region)
    return LayerPlan(index=index + 1, type=cfg.type, angle_deg=float(alpha),
                     requested_angle_deg=float(cfg.angle_deg if cfg.angle_deg is not None else alpha),
                     circuits=int(circuits), pattern=int(pattern), dwell_start_deg=float(dwell_a),
                     dwell_end_deg=float(dwell_b), turnaround_radius=c, fiber_length_mm=length,
                     alpha_min_deg=float(folded.min()), alpha_max_deg=float(folded.max()),
                     time_s=length / ctx.feed * 60.0, passes=tuple(passes), coverage=coverage,
                     notes=tuple(notes), max_slip=held.max_slip, min_normal_curvature=held.min_normal_curvature,
                     max_lift_off_mm=held.max_lift_off, lift_off_t=held.lift_t, lift_off_pass=held.lift_pass)


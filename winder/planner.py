"""The winding planner: `plan(job) -> WindingPlan` (MATH.md 5; paper 6.1).

Helical layers are circuits of a forward and a return pass, each a two-point (N-round) geodesic
solved by the variational method between its slot end points:
- open mandrels (tubes, cones, elbows, non-circular tubes): the passes run between the ends of the
  winding region; dwells at the ends close the pattern;
- domed vessels: each pass runs between the turnarounds on the two domes, where the geodesic is
  tangent to the parallel r = c (Clairaut); c is moved to close the pattern.
On a surface of revolution the circuits are rotated copies of the first; elsewhere every pass is
solved on its own, warm-started from its neighbour. Hoop layers are constant-pitch turns on the
cylindrical region, refused where friction cannot hold them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import make_interp_spline
from scipy.optimize import brentq

from winder.config import JobConfig
from winder.config_job import LayerConfig, LayerType, WindingConfig
from winder.coverage import layer_coverage
from winder.domes import VesselMeridian
from winder.errors import ConfigError, SolverError
from winder.geodesic import GeodesicResult, geodesic
from winder.pattern import circuits_for_coverage, close_open_pattern, close_vessel_pattern
from winder.plan import FiberPass, LayerPlan, PassKind, WindingPlan, winding_angle_deg
from winder.sections import ArcMap, arc_map
from winder.shooting import trace
from winder.surface import SweepSurface, build_surface

COVERAGE_STATIONS = 21
DWELL_STEP_DEG = 2.0  # sampling of a dwell arc
HOOP_STEP_DEG = 5.0  # sampling of hoop turns (the machine interpolates A and X linearly)
TRACE_RTOL = 1e-10
QUAD_NODES = 200  # Gauss-Legendre nodes per dome for the turnaround advance
FEED_MM_PER_S = 1.0 / 60.0


@dataclass(frozen=True)
class _Context:
    job: JobConfig
    winding: WindingConfig
    surface: SweepSurface
    arcs: ArcMap
    feed: float  # mm/min

    def key(self, index: int, field: str | None = None) -> str:
        base = f"{self.job.source}: winding.layers[{index}]"
        return f"{base}.{field}" if field else base


# -- passes ---------------------------------------------------------------------------------------
def _directions(surface: SweepSurface, s: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Unit tangents (m, 3) of the smooth curve through the vertices, in laying order."""
    i = np.arange(s.shape[0], dtype=float)
    # Quintic: the cubic's end slopes are O(h^3) off, visible next to a turnaround.
    k = min(5, s.shape[0] - 1 - (s.shape[0] % 2 == 1 and s.shape[0] < 7))
    ds, dth = make_interp_spline(i, s, k=k)(i, 1), make_interp_spline(i, theta, k=k)(i, 1)
    ev = surface.evaluate(s, theta, order=1)
    v = ev.ps * ds[:, None] + ev.pt * dth[:, None]
    return v / np.linalg.norm(v, axis=1)[:, None]


def _make_pass(surface: SweepSurface, layer: int, circuit: int, number: int, kind: PassKind,
               s: np.ndarray, theta: np.ndarray, direction: np.ndarray | None, length: float) -> FiberPass:
    if direction is None:
        direction = _directions(surface, s, theta)
    return FiberPass(layer, circuit, number, kind, surface.t_of_s(s), s, theta, surface.points(s, theta),
                     direction, winding_angle_deg(surface, s, theta, direction), float(length))


def _solve(ctx: _Context, a: tuple[float, float], b: tuple[float, float],
           warm: tuple[np.ndarray, np.ndarray] | None,
           n: int | None = None) -> tuple[np.ndarray, np.ndarray, float, GeodesicResult]:
    """A two-point geodesic pass: vertices (Richardson-refined), length. n: points (default config)."""
    w = ctx.winding
    n = n or w.points or 200
    res = geodesic(ctx.surface, a, b, n=n, tolerance=w.tolerance, init=warm)
    for _ in range(2):
        if res.converged:
            break
        # Too coarse for a sharp stretch (a turnaround close to a small dome's hook): halve the
        # segments, warm-started from the path so far.
        n = 2 * n + 1
        res = geodesic(ctx.surface, a, b, n=n, tolerance=w.tolerance, init=(res.s, res.theta))
    if not res.converged:
        raise SolverError(f"{ctx.job.source}: a pass from t = {a[0]:.3f} to t = {b[0]:.3f} did not converge "
                          f"({res.reason.value})")
    return res.refined_s, res.refined_theta, res.length, res


def _arc_pass(ctx: _Context, layer: int, circuit: int, number: int, s: float, th0: float,
              th1: float) -> FiberPass:
    """A dwell: the mandrel turns from th0 to th1 at a fixed station."""
    m = max(2, int(math.ceil(abs(math.degrees(th1 - th0)) / DWELL_STEP_DEG)) + 1)
    th = np.linspace(th0, th1, m)
    ss = np.full(m, s)
    pt = ctx.surface.evaluate(ss, th, order=1).pt
    direction = pt / np.linalg.norm(pt, axis=1)[:, None]
    pts = ctx.surface.points(ss, th)
    length = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    return _make_pass(ctx.surface, layer, circuit, number, PassKind.DWELL, ss, th, direction, length)


# -- open mandrels ----------------------------------------------------------------------------------
def _reach(surface: SweepSurface, start: tuple[float, float], heading_deg: float, s_target: float,
           span: float) -> float:
    """theta where the geodesic from start at heading_deg reaches station s_target."""
    # 1e-10 is plenty for a pattern advance, and tight tolerances crawl on guides whose third
    # derivative is only piecewise smooth (splines).
    tr = trace(surface, start, heading_deg, span, rtol=TRACE_RTOL, atol=TRACE_RTOL)
    ls = np.linspace(0.0, tr.length, 4001)
    ss = tr.sol(ls)[0]
    sign = 1.0 if s_target >= start[0] else -1.0
    # The trace stops on the mandrel's end by an event located to ~1e-12: an end at the target counts.
    reach = ss.max() if sign > 0 else ss.min()
    if abs(reach - s_target) <= 1e-9 * (1.0 + abs(s_target)):
        s_target = reach
    hit = np.nonzero(sign * (ss - s_target) >= 0.0)[0]
    if hit.size == 0:
        turn = float(surface.t_of_s(np.array([ss.max() if sign > 0 else ss.min()]))[0])
        raise SolverError(f"the geodesic at {heading_deg:.4g} deg turns around at t = {turn:.4g} mm before "
                          f"reaching the end of the winding region (Clairaut: r sin(alpha) is constant, so "
                          f"it cannot reach a smaller radius); lower the angle or shorten the region")
    k = int(hit[0])
    if k == 0:
        return float(start[1])
    if ss[k] == s_target:
        return float(tr.sol(ls[k:k + 1])[1][0])
    l_hit = brentq(lambda l: tr.sol(np.array([l]))[0][0] - s_target, ls[k - 1], ls[k], xtol=1e-12)
    return float(tr.sol(np.array([l_hit]))[1][0])


def _natural_advance(ctx: _Context, s_ref: float, s_a: float, s_b: float, alpha_deg: float) -> float:
    """Turns a forward pass advances when it holds the layer angle at the reference station.

    The geodesic through the reference station at the layer angle, traced both ways to the region
    ends. On a surface of revolution one start angle suffices; elsewhere the advance is averaged
    over four start angles (the passes themselves are then solved between their slots).
    """
    surf = ctx.surface
    span = 4.0 * (s_b - s_a) / max(math.cos(math.radians(alpha_deg)), 0.05) + 10.0
    starts = [0.0] if surf.is_revolution else [0.0, 0.5 * math.pi, math.pi, 1.5 * math.pi]
    adv = []
    for th0 in starts:
        th_b = _reach(surf, (s_ref, th0), alpha_deg, s_b, span) if s_b > s_ref else th0
        th_a = _reach(surf, (s_ref, th0), alpha_deg + 180.0, s_a, span) if s_a < s_ref else th0
        adv.append(float(ctx.arcs.fraction(np.array([th_b]))[0] - ctx.arcs.fraction(np.array([th_a]))[0]))
    return float(np.mean(adv))


def _region(ctx: _Context) -> tuple[float, float]:
    if ctx.winding.region is not None:
        return ctx.winding.region
    return 0.0, ctx.surface.axial_length


def _reference(ctx: _Context, t_a: float, t_b: float) -> tuple[float, float]:
    """Station (s) and perimeter of the largest section of the region: the reference section."""
    ts = np.linspace(t_a, t_b, 41)
    ss = ctx.surface.s_of_t(ts)
    per = ctx.surface.perimeter(ss)
    k = int(np.argmax(per))
    return float(ss[k]), float(per[k])


COVERED_TARGET = 0.999  # covered fraction a helical layer must reach
GAP_TARGET = 0.02  # widest gap allowed, as a fraction of the band width
MAX_CIRCUIT_FACTOR = 4  # at most this many times the closed-form circuit count


def _open_passes(ctx: _Context, index: int, pat, natural_fwd: float, theta0: float,
                 ends: tuple[float, float, float, float]) -> list[FiberPass]:
    """The passes of an open-mandrel helical layer with the pattern `pat`, in winding order."""
    surf = ctx.surface
    t_a, t_b, s_a, s_b = ends
    f0 = float(ctx.arcs.fraction(np.array([theta0]))[0])
    passes: list[FiberPass] = []
    number = 0
    layer = index + 1
    for j in range(pat.circuits):
        f_start = f0 + j * pat.advance
        f_fwd_end = f_start + natural_fwd
        f_ret_start = f_fwd_end + pat.dwell_end
        f_ret_end = f_ret_start + natural_fwd
        th = ctx.arcs.theta(np.array([f_start, f_fwd_end, f_ret_start, f_ret_end, f0 + (j + 1) * pat.advance]))
        if surf.is_revolution and j > 0:
            # A surface of revolution: the circuit is the first one turned by the circuit advance.
            shift = th[0] - passes[0].theta[0]
            for p in passes[:4]:
                number += 1
                passes.append(_make_pass(surf, layer, j + 1, number, p.kind, p.s, p.theta + shift,
                                         None if p.kind is not PassKind.DWELL else _turned(p, surf, shift),
                                         p.length))
            continue
        # Cold starts: consecutive circuits lie k / N_c of a turn apart, where the geodesic can look
        # nothing alike (inside vs outside of a bend); coarse-to-fine is robust and as fast.
        s_f, th_f, len_f, _ = _solve(ctx, (t_a, th[0]), (t_b, th[1]), None)
        s_r, th_r, len_r, _ = _solve(ctx, (t_b, th[2]), (t_a, th[3]), None)
        for kind, item in ((PassKind.FORWARD, (s_f, th_f, len_f)), (PassKind.DWELL, (s_b, th[1], th[2])),
                           (PassKind.RETURN, (s_r, th_r, len_r)), (PassKind.DWELL, (s_a, th[3], th[4]))):
            number += 1
            if kind is PassKind.DWELL:
                passes.append(_arc_pass(ctx, layer, j + 1, number, *item))
            else:
                passes.append(_make_pass(surf, layer, j + 1, number, kind, item[0], item[1], None, item[2]))
    return passes


def _helical_open(ctx: _Context, cfg: LayerConfig, index: int, theta0: float) -> LayerPlan:
    """Open mandrels. On a surface of revolution N_c = ceil(P cos(alpha) / B) covers by construction.
    Elsewhere (bends, non-circular sections) geodesics between evenly spaced slots drift apart
    (toward the inside of a bend, which is shorter); the circuit count is then raised until the
    measured coverage is complete, and the note says by how much."""
    surf, w = ctx.surface, ctx.winding
    t_a, t_b = _region(ctx)
    s_a, s_b = (float(v) for v in surf.s_of_t(np.array([t_a, t_b])))
    s_ref, perimeter = _reference(ctx, t_a, t_b)
    alpha = cfg.angle_deg
    n_c0 = n_c = circuits_for_coverage(perimeter, math.radians(alpha), w.band_width)
    try:
        natural_fwd = _natural_advance(ctx, s_ref, s_a, s_b, alpha)
    except SolverError as exc:
        raise SolverError(f"{ctx.key(index, 'angle')}: {exc}") from exc
    stations = np.linspace(t_a, t_b, COVERAGE_STATIONS + 2)[1:-1]
    notes: list[str] = []
    ends = (t_a, t_b, s_a, s_b)
    last_cov = None
    cov = None
    while True:
        pat = close_open_pattern(n_c, 2.0 * natural_fwd, w.dwell_start_deg / 360.0, w.dwell_end_deg / 360.0,
                                 cfg.pattern, ctx.key(index, "pattern"))
        passes = _open_passes(ctx, index, pat, natural_fwd, theta0, ends)
        if surf.is_revolution or cfg.pattern is not None:
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
                         f"up to {n_c} circuits: geodesics at {alpha:g} deg bunch on this mandrel; a larger "
                         f"angle spreads them")
            break
        n_c = grow
    if n_c > n_c0:
        notes.append(f"{n_c} circuits instead of {n_c0}: the geodesic passes between evenly spaced end slots "
                     f"drift together on this mandrel, and the closed-form count would leave gaps")
    if pat.dwell_start * 360.0 > w.dwell_start_deg + 1e-9 or pat.dwell_end * 360.0 > w.dwell_end_deg + 1e-9:
        notes.append(f"dwells lengthened to {pat.dwell_start * 360:.3f} / {pat.dwell_end * 360:.3f} deg to close "
                     f"the pattern (k = {pat.pattern} of {n_c})")
    return _layer(ctx, cfg, index, alpha, n_c, pat.pattern, pat.dwell_start * 360.0, pat.dwell_end * 360.0,
                  None, passes, stations, notes, cov)


def _turned(p: FiberPass, surf: SweepSurface, shift: float) -> np.ndarray:
    pt = surf.evaluate(p.s, p.theta + shift, order=1).pt
    return pt / np.linalg.norm(pt, axis=1)[:, None]


def _shifted(warm: tuple[np.ndarray, np.ndarray] | None, theta_start: float):
    if warm is None:
        return None
    return warm[0], warm[1] - warm[1][0] + theta_start


# -- vessels ----------------------------------------------------------------------------------------
def _turnaround_s(prof: VesselMeridian, c: float) -> tuple[float, float]:
    """Stations s where r = c on the first and the end dome."""
    e1, e2 = prof.equator_s

    def r_minus_c(s: float) -> float:
        return float(prof.evaluate(np.array([s])).r[0]) - c

    return brentq(r_minus_c, 0.0, e1, xtol=1e-13), brentq(r_minus_c, e2, prof.length, xtol=1e-13)


def _advances(prof: VesselMeridian, c: float) -> tuple[float, float, float]:
    """theta advances (rad) of the geodesic of Clairaut constant c: over the first dome (turnaround
    to equator), the cylinder, and the end dome (equator to turnaround).

    dtheta/ds = c / (r sqrt(r^2 - c^2)), s the meridian arc length. On each dome the substitution
    s = s_c + (s_eq - s_c)(1 - cos tau) removes the inverse-square-root singularity at the turnaround;
    the cylinder is exact.
    """
    s1, s2 = _turnaround_s(prof, c)
    e1, e2 = prof.equator_s
    x, w = np.polynomial.legendre.leggauss(QUAD_NODES)
    tau = 0.25 * np.pi * (x + 1.0)  # [0, pi/2]
    domes = []
    for s_c, s_eq in ((s1, e1), (s2, e2)):
        span = s_eq - s_c
        s = s_c + span * (1.0 - np.cos(tau))
        r = prof.evaluate(s).r
        f = c / (r * np.sqrt(np.maximum(r * r - c * c, 1e-300))) * abs(span) * np.sin(tau)
        domes.append(0.25 * np.pi * float(f @ w))
    cylinder = c * prof.cylinder_length / (prof.radius * math.sqrt(prof.radius**2 - c * c))
    return domes[0], cylinder, domes[1]


def _half_advance(prof: VesselMeridian, c: float) -> float:
    """theta advance (rad) from one turnaround to the other."""
    return float(sum(_advances(prof, c)))


def _vessel_pass(ctx: _Context, prof: VesselMeridian, c: float, forward: bool,
                 theta0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """One pole-to-pole pass, solved piece by piece between the equators.

    The meridian's curvature jumps where a dome meets the cylinder; a polyline vertex straddling
    the jump carries an O(h^3) error that Richardson cannot remove and that tilts the whole helix on
    the cylinder (1e-5 of the Clairaut constant at 200 points). The geodesic's equator crossings
    are known by quadrature, so each smooth piece is solved on its own, with vertices on the joints.
    Returns s, theta ((m,) float, laying order), the unit directions ((m, 3) float, from each piece's
    own spline) and the length.
    """
    s1, s2 = _turnaround_s(prof, c)
    e1, e2 = prof.equator_s
    d1, cyl, d2 = _advances(prof, c)
    knots, steps = ([s1, e1, e2, s2], [d1, cyl, d2]) if forward else ([s2, e2, e1, s1], [d2, cyl, d1])
    thetas = theta0 + np.concatenate([[0.0], np.cumsum(steps)])
    guide_s, guide_th = _clairaut_start(prof, c, knots[0], knots[-1], theta0, m=4001)
    n_total = ctx.winding.points or 200
    s_out, th_out, d_out, length = [], [], [], 0.0
    for i in range(3):
        lo, hi = sorted((knots[i], knots[i + 1]))
        if hi - lo <= 1e-12:
            continue  # no cylinder
        inside = (guide_s >= lo) & (guide_s <= hi)
        n_i = max(5, int(round(n_total * np.count_nonzero(inside) / guide_s.size)))
        warm = (np.concatenate([[knots[i]], guide_s[inside], [knots[i + 1]]]),
                np.concatenate([[thetas[i]], guide_th[inside], [thetas[i + 1]]]))
        t_a, t_b = (float(v) for v in prof.t_of_s(np.array([knots[i], knots[i + 1]])))
        s, th, ln, _ = _solve(ctx, (t_a, thetas[i]), (t_b, thetas[i + 1]), warm, n_i)
        d = _directions(ctx.surface, s, th)
        s_out.append(s if not s_out else s[1:])
        th_out.append(th if not th_out else th[1:])
        d_out.append(d if not d_out else d[1:])
        length += ln
    return np.concatenate(s_out), np.concatenate(th_out), np.concatenate(d_out), length


def _clairaut_start(prof: VesselMeridian, c: float, s_from: float, s_to: float, theta0: float,
                    m: int = 401) -> tuple[np.ndarray, np.ndarray]:
    """The geodesic of Clairaut constant c between two turnarounds, by quadrature: the Newton solve's
    starting path (m points, equally spaced by arc length), so it needs one or two steps.

    dtheta/ds = c / (r sqrt(r^2 - c^2)) and dl/ds = r / sqrt(r^2 - c^2) on a cosine grid in s that
    clusters at both turnarounds, where both have an integrable inverse square root.
    """
    tau = np.linspace(0.0, 1.0, 4001)
    s = s_from + (s_to - s_from) * 0.5 * (1.0 - np.cos(np.pi * tau))
    ds_dtau = abs(s_to - s_from) * 0.5 * np.pi * np.sin(np.pi * tau)
    r = prof.evaluate(s).r
    root = np.sqrt(np.maximum(r * r - c * c, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        dth = np.where(root > 0, c / (r * root) * ds_dtau, 0.0)
        dl = np.where(root > 0, r / root * ds_dtau, 0.0)
    # The integrands are finite in tau; at the two ends the limits are taken from the neighbours.
    for arr in (dth, dl):
        arr[0], arr[-1] = arr[1], arr[-2]
    steps = np.diff(tau)
    th = theta0 + np.concatenate([[0.0], np.cumsum(0.5 * (dth[1:] + dth[:-1]) * steps)])
    ell = np.concatenate([[0.0], np.cumsum(0.5 * (dl[1:] + dl[:-1]) * steps)])
    target = np.linspace(0.0, ell[-1], m)
    return np.interp(target, ell, s), np.interp(target, ell, th)


def _helical_vessel(ctx: _Context, cfg: LayerConfig, index: int, theta0: float) -> LayerPlan:
    surf, w = ctx.surface, ctx.winding
    prof = surf.profile
    big_r = prof.radius
    r_open = max(prof.dome.end_radius, prof.end_dome.end_radius)
    c_min = r_open + 0.5 * w.band_width
    c0 = big_r * math.sin(math.radians(cfg.angle_deg))
    if c0 <= c_min:
        least = math.degrees(math.asin(min(1.0, c_min / big_r)))
        raise SolverError(f"{ctx.key(index, 'angle')}: {cfg.angle_deg:g} deg turns around at r = {c0:.3f} mm, "
                          f"inside the polar opening ({r_open:.3f} mm) plus half a band ({c_min:.3f} mm); "
                          f"the least angle on this vessel is {least:.3f} deg")
    c_hi = big_r * math.sin(math.radians(89.0))
    perimeter = 2.0 * math.pi * big_r

    def advance(c: float) -> float:
        return 2.0 * _half_advance(prof, c) / (2.0 * math.pi)

    n_c = circuits_for_coverage(perimeter, math.radians(cfg.angle_deg), w.band_width)
    for _ in range(4):
        k, c = close_vessel_pattern(advance, c0, c_min, c_hi, n_c, cfg.pattern, ctx.key(index, "pattern"))
        need = circuits_for_coverage(perimeter, math.asin(c / big_r), w.band_width)
        if need <= n_c:
            break
        n_c = need
    alpha = math.degrees(math.asin(c / big_r))
    half = _half_advance(prof, c)
    fwd = _vessel_pass(ctx, prof, c, True, theta0)
    ret = _vessel_pass(ctx, prof, c, False, theta0 + half)
    passes: list[FiberPass] = []
    number = 0
    for j in range(n_c):
        shift = j * 2.0 * half
        for kind, (s, th, d, ln) in ((PassKind.FORWARD, fwd), (PassKind.RETURN, ret)):
            number += 1
            # A rotated copy: the directions turn with it (about the straight axis, +z).
            c_, s_ = math.cos(shift), math.sin(shift)
            turned = np.column_stack([c_ * d[:, 0] - s_ * d[:, 1], s_ * d[:, 0] + c_ * d[:, 1], d[:, 2]])
            passes.append(_make_pass(surf, index + 1, j + 1, number, kind, s, th + shift, turned, ln))
    notes = [f"turnaround radius c = {c:.4f} mm on the domes (polar opening {r_open:.4g} mm); angle moved "
             f"{alpha - cfg.angle_deg:+.4f} deg to close the pattern (k = {k} of {n_c})"]
    e1, e2 = prof.equator_t
    stations = np.linspace(e1, e2, COVERAGE_STATIONS + 2)[1:-1]
    return _layer(ctx, cfg, index, alpha, n_c, k, 0.0, 0.0, c, passes, stations, notes)


# -- hoop -----------------------------------------------------------------------------------------------
SLIP_SAMPLES_PER_TURN = 72


def _cylinder_region(ctx: _Context) -> tuple[float, float]:
    prof = ctx.surface.profile
    if isinstance(prof, VesselMeridian):
        return prof.equator_t
    return _region(ctx)


def _hoop(ctx: _Context, cfg: LayerConfig, index: int, theta0: float) -> LayerPlan:
    surf, w = ctx.surface, ctx.winding
    t_a, t_b = _cylinder_region(ctx)
    s_ref, perimeter = _reference(ctx, t_a, t_b)
    if cfg.angle_deg is None:
        if w.band_width >= perimeter:
            raise SolverError(f"{ctx.key(index)}: the band ({w.band_width:g} mm) is wider than the perimeter "
                              f"({perimeter:.3f} mm): a hoop layer cannot be laid")
        alpha = math.degrees(math.acos(w.band_width / perimeter))
    else:
        alpha = cfg.angle_deg
    pitch = perimeter / math.tan(math.radians(alpha))  # axial advance per turn
    turns = (t_b - t_a) / pitch
    m = max(3, int(math.ceil(turns * 360.0 / HOOP_STEP_DEG)) + 1)
    f0 = float(ctx.arcs.fraction(np.array([theta0]))[0])
    passes: list[FiberPass] = []
    for k in range(cfg.passes):
        frac = f0 + k * turns + np.linspace(0.0, turns, m)
        t = np.linspace(t_a, t_b, m) if k % 2 == 0 else np.linspace(t_b, t_a, m)
        s = surf.s_of_t(t)
        th = ctx.arcs.theta(frac)
        ev = surf.evaluate(s, th, order=1)
        # Exact tangent of the constant-pitch path: d/dk Phi(s(t), theta(f)), both linear in k
        # (s = t on the cylindrical region).
        vel = ev.ps * (t[1] - t[0]) + ev.pt * (ctx.arcs.dtheta_dfrac(th) * (frac[1] - frac[0]))[:, None]
        speed = np.linalg.norm(vel, axis=1)
        direction = vel / speed[:, None]
        length = float(np.sum(0.5 * (speed[1:] + speed[:-1])))
        passes.append(_make_pass(surf, index + 1, k + 1, k + 1, PassKind.HOOP, s, th, direction, length))
    _check_slip(ctx, index, passes[0], turns)
    stations = np.linspace(t_a, t_b, COVERAGE_STATIONS + 2)[1:-1]
    return _layer(ctx, cfg, index, alpha, cfg.passes, 1, 0.0, 0.0, None, passes, stations, [])


def _check_slip(ctx: _Context, index: int, p: FiberPass, turns: float) -> None:
    """Refuse a hoop path whose geodesic curvature friction cannot hold: |k_g / k_n| <= mu."""
    surf = ctx.surface
    m = max(50, int(turns * SLIP_SAMPLES_PER_TURN))
    i = np.linspace(0.0, p.s.size - 1.0, m)
    idx = np.arange(p.s.size, dtype=float)
    s, th = np.interp(i, idx, p.s), np.interp(i, idx, p.theta)
    ev = surf.evaluate(s, th, order=2)
    ds, dth = np.gradient(s), np.gradient(th)
    vel = ev.ps * ds[:, None] + ev.pt * dth[:, None]
    acc = ev.pss * (ds * ds)[:, None] + 2.0 * ev.pst * (ds * dth)[:, None] + ev.ptt * (dth * dth)[:, None]
    nrm = np.cross(ev.pt, ev.ps)
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    speed2 = np.einsum("ij,ij->i", vel, vel)
    k_n = np.einsum("ij,ij->i", acc, nrm) / speed2
    k_g = np.einsum("ij,ij->i", np.cross(vel, acc), nrm) / speed2**1.5
    ratio = np.abs(k_g) / np.maximum(np.abs(k_n), 1e-300)
    worst = int(np.argmax(ratio))
    if ratio[worst] > ctx.winding.friction:
        t = float(surf.t_of_s(s[worst:worst + 1])[0])
        raise SolverError(f"{ctx.key(index)}: a hoop layer would slip here: |k_g / k_n| reaches "
                          f"{ratio[worst]:.3g} at t = {t:.3f} mm, above the friction coefficient "
                          f"{ctx.winding.friction:g} (winding.friction); hoop layers hold on cylindrical "
                          f"regions")


# -- layers -------------------------------------------------------------------------------------------
def _layer(ctx: _Context, cfg: LayerConfig, index: int, alpha: float, circuits: int, pattern: int,
           dwell_a: float, dwell_b: float, c: float | None, passes: list[FiberPass], stations: np.ndarray,
           notes: list[str], coverage=None) -> LayerPlan:
    laid = [p for p in passes if p.kind is not PassKind.DWELL]
    folded = np.concatenate([np.abs(p.alpha_deg[1:-1]) for p in laid]) if laid else np.zeros(1)
    length = float(sum(p.length for p in passes))
    if coverage is None:
        coverage = layer_coverage(ctx.surface, ctx.arcs, passes, ctx.winding.band_width, stations)
    for p in laid:
        if p.kind is not PassKind.HOOP:
            _bridging_note(ctx, p, notes)
            break
    return LayerPlan(index=index + 1, type=cfg.type, angle_deg=float(alpha),
                     requested_angle_deg=float(cfg.angle_deg if cfg.angle_deg is not None else alpha),
                     circuits=int(circuits), pattern=int(pattern), dwell_start_deg=float(dwell_a),
                     dwell_end_deg=float(dwell_b), turnaround_radius=c, fiber_length_mm=length,
                     alpha_min_deg=float(folded.min()), alpha_max_deg=float(folded.max()),
                     time_s=length / ctx.feed * 60.0, passes=tuple(passes), coverage=coverage,
                     notes=tuple(notes))


def _bridging_note(ctx: _Context, p: FiberPass, notes: list[str]) -> None:
    """A fiber under tension bridges where the surface is concave along it (k_n <= 0)."""
    d2 = np.diff(p.points, 2, axis=0)
    nrm = ctx.surface.normals(p.s[1:-1], p.theta[1:-1])
    k_n = np.einsum("ij,ij->i", d2, nrm)
    if np.any(k_n > 1e-12 * np.max(np.abs(k_n))):
        where = float(p.t[1:-1][np.argmax(k_n)])
        notes.append(f"the fiber bridges over a concave region near t = {where:.3f} mm (k_n <= 0): it will "
                     f"not lie on the mandrel there")


def plan(job: JobConfig) -> WindingPlan:
    """Plan every layer of a job; raises ConfigError for what the config cannot do, SolverError for
    what cannot be computed (infeasible winding, no convergence)."""
    if job.winding is None:
        raise ConfigError(f"{job.source}: winding: missing; `winder run` needs the winding plan (band_width, "
                          f"layers)")
    surface = build_surface(job.mandrel, job.source, job.name)
    ctx = _Context(job, job.winding, surface, arc_map(surface.section), job.machine.feed)
    layers = []
    theta0 = 0.0
    for index, cfg in enumerate(job.winding.layers):
        if cfg.type is LayerType.HOOP:
            layer = _hoop(ctx, cfg, index, theta0)
        elif isinstance(surface.profile, VesselMeridian):
            layer = _helical_vessel(ctx, cfg, index, theta0)
        else:
            layer = _helical_open(ctx, cfg, index, theta0)
        layers.append(layer)
        theta0 = float(layer.passes[-1].theta[-1])
    return WindingPlan(job.name, job.source, surface, tuple(layers))

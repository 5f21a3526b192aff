"""Helical layers on domed vessels: turnarounds on the domes (Clairaut), pattern closed by moving c.

A geodesic on a surface of revolution keeps r sin(alpha) = c; it turns around on each dome where
r = c, tangent to that parallel. The circuit advance is a function of c (by quadrature); c is moved
slightly from R sin(alpha) so the pattern closes, and the angle change is reported (docs/math/05-winding.md).
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace
from typing import Callable

import numpy as np

from winder.config.winding import LayerConfig
from winder.geometry.vessel import VesselMeridian
from winder.errors import ConfigError, SolverError
from winder.winding.passes import (
    COVERAGE_STATIONS,
    PlanContext,
    finish_layer,
    turned_copies,
    solve_pass,
)
from winder.winding.pattern import circuits_for_coverage, close_vessel_pattern
from winder.winding.layers.vessel_advance import (advances, circuit_advance, dome_advance_to, half_advance,
                                                  turnaround_stations)
from winder.winding.results import LayerPlan, PassKind
from winder.geometry.measure import row_norms

PIECE_MIN_POINTS = 5  # the least points of a pass's piece (a dome or the cylinder)


def _vessel_pass(ctx: PlanContext, prof: VesselMeridian, c: float, forward: bool,
                 theta0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """One pole-to-pole pass, solved piece by piece between the equators (and a dome's own joints).

    The meridian's curvature jumps where a dome meets the cylinder (and inside a torispherical head); a polyline vertex straddling
    the jump carries an O(h^3) error that Richardson cannot remove and that tilts the whole helix on
    the cylinder (1e-5 of the Clairaut constant at 200 points). The geodesic's equator crossings
    are known by quadrature, so each smooth piece is solved on its own, with vertices on the joints.
    Returns s, theta ((m,) float, laying order), the unit directions ((m, 3) float, from each piece's
    own spline) and the length.
    """
    knots, thetas, cyl_piece = _pass_knots(prof, c, forward, theta0)
    guide_s, guide_th = clairaut_path(prof, c, knots[0], knots[-1], theta0, m=4001)
    n_total = ctx.winding.points or 200
    s_out, th_out, d_out, length = [], [], [], 0.0
    for i in range(len(knots) - 1):
        lo, hi = sorted((knots[i], knots[i + 1]))
        if hi - lo <= 1e-12:
            continue  # no cylinder
        inside = (guide_s >= lo) & (guide_s <= hi)
        n_i = max(PIECE_MIN_POINTS, int(round(n_total * np.count_nonzero(inside) / guide_s.size)))
        warm = (np.concatenate([[knots[i]], guide_s[inside], [knots[i + 1]]]),
                np.concatenate([[thetas[i]], guide_th[inside], [thetas[i + 1]]]))
        t_a, t_b = (float(v) for v in prof.t_of_s(np.array([knots[i], knots[i + 1]])))
        s, th, d, ln, _ = solve_pass(ctx, (t_a, thetas[i]), (t_b, thetas[i + 1]), warm, n_i)
        if i == cyl_piece and d_out:
            # The first joint's direction from the cylinder's piece (a helix: a line in (t, theta),
            # which its spline holds exactly; the second joint's already is), not from a dome's spline
            # end: on a 2.5:1 ellipsoid that end is 3e-5 rad off, past the exact eye's landing test
            # (winder.machine.exact), which would put the eye there on the smooth path's direction
            # (0.025 mm off the fiber's tangent).
            d_out[-1] = d_out[-1].copy()
            d_out[-1][-1] = d[0]
        s_out.append(s if not s_out else s[1:])
        th_out.append(th if not th_out else th[1:])
        d_out.append(d if not d_out else d[1:])
        length += ln
    s, th, d = np.concatenate(s_out), np.concatenate(th_out), np.concatenate(d_out)
    # Both ends lie on the turnaround parallels r = c, where the geodesic runs along the parallel
    # (Clairaut): exactly, so that the pass turning back there leaves in the same direction.
    pt = ctx.surface.evaluate(s[[0, -1]], th[[0, -1]], order=1).pt
    d[[0, -1]] = pt / row_norms(pt)[:, None]
    return s, th, d, length


def _pass_knots(prof: VesselMeridian, c: float, forward: bool, theta0: float) -> tuple[list, np.ndarray, int]:
    """(stations, thetas, index of the cylinder's piece) where a pass's smooth pieces meet: the
    turnarounds, the equators and the domes' own curvature joints (a torispherical head's knuckle and
    crown) between them, each theta by the Clairaut advance (vessel_advance)."""
    s1, s2 = turnaround_stations(prof, c)
    e1, e2 = prof.equator_s
    d1, cyl, d2 = advances(prof, c)
    j1 = sorted(j for j in prof.joints if s1 < j < e1)
    j2 = sorted(j for j in prof.joints if e2 < j < s2)
    stations = [s1, *j1, e1, e2, *j2, s2]
    th = np.concatenate([[0.0], [dome_advance_to(prof, c, s1, j) for j in j1], [d1, d1 + cyl],
                         [d1 + cyl + d2 - dome_advance_to(prof, c, s2, j) for j in j2], [d1 + cyl + d2]])
    cyl_piece = len(j1) + 1
    if not forward:
        stations, th, cyl_piece = stations[::-1], th[-1] - th[::-1], len(j2) + 1
    return stations, theta0 + th, cyl_piece


def clairaut_path(prof: VesselMeridian, c: float, s_from: float, s_to: float, theta0: float,
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


def turnaround_refusal(prof: VesselMeridian, angle_deg: float, band_width: float) -> str | None:
    """Why a geodesic layer at angle_deg cannot wind on this vessel, or None: its Clairaut turnaround
    R sin(alpha) must clear the larger polar opening by half a band."""
    r_open = max(prof.dome.end_radius, prof.end_dome.end_radius)
    c_min = r_open + 0.5 * band_width
    c0 = prof.radius * math.sin(math.radians(angle_deg))
    if c0 > c_min:
        return None
    least = math.degrees(math.asin(min(1.0, c_min / prof.radius)))
    return (f"{angle_deg:g} deg turns around at r = {c0:.3f} mm, inside the polar opening ({r_open:.3f} mm) "
            f"plus half a band ({c_min:.3f} mm); the least angle on this vessel is {least:.3f} deg")


def vessel_closure(ctx: PlanContext, cfg: LayerConfig, index: int) -> tuple[Callable[[float], float], float, float,
                                                                          float]:
    """(a circuit's advance in turns as a function of the turnaround radius c, c at the layer's angle, the
    least and the largest c): what close_vessel_pattern closes a vessel layer's pattern with."""
    prof, w = ctx.surface.profile, ctx.winding
    big_r = prof.radius
    r_open = max(prof.dome.end_radius, prof.end_dome.end_radius)
    if (why := turnaround_refusal(prof, cfg.angle_deg, w.band_width)) is not None:
        # check refuses it on the bare mandrel (winder.winding.budget); here, a laminate's grown one
        raise SolverError(f"{ctx.key(index, 'angle')}: {why}")

    return (functools.partial(circuit_advance, prof), big_r * math.sin(math.radians(cfg.angle_deg)), r_open + 0.5 * w.band_width,
            big_r * math.sin(math.radians(89.0)))


def vessel_closed_pattern(ctx: PlanContext, cfg: LayerConfig, index: int) -> tuple[int, int, float]:
    """(N_c, k, c): the circuits, skip and turnaround radius that close a geodesic layer's pattern with
    the least move of c from R sin(alpha) (more circuits where the moved angle needs them to cover)."""
    w = ctx.winding
    big_r = ctx.surface.profile.radius
    advance, c0, c_min, c_hi = vessel_closure(ctx, cfg, index)
    perimeter = 2.0 * math.pi * big_r
    n_c = cfg.circuits or circuits_for_coverage(perimeter, math.radians(cfg.angle_deg), w.band_width)
    for attempt in range(4):
        try:
            k, c = close_vessel_pattern(advance, c0, c_min, c_hi, n_c, cfg.pattern, ctx.key(index, "pattern"))
        except ConfigError as exc:
            if attempt == 0:  # the config's own circuit count: check refuses it the same way
                raise
            # The closed pattern moved the angle and needs more circuits, which share a factor with
            # the given pattern: a result of the computation, not of the config alone.
            raise SolverError(str(exc)) from exc
        need = circuits_for_coverage(perimeter, math.asin(c / big_r), w.band_width)
        if need <= n_c or cfg.circuits is not None:  # the engineer's count is wound as given
            break
        n_c = need
    return n_c, k, c


def vessel_helical_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float,
                         closed: tuple[int, int, float] | None = None, note: str = "") -> LayerPlan:
    """A geodesic layer with its pattern closed by moving c (closed: (N_c, k, c) already chosen, else
    vessel_closed_pattern's); note: a line added to the layer's notes."""
    surf = ctx.surface
    prof = surf.profile
    big_r = prof.radius
    r_open = max(prof.dome.end_radius, prof.end_dome.end_radius)
    n_c, k, c = closed if closed is not None else vessel_closed_pattern(ctx, cfg, index)
    alpha = math.degrees(math.asin(c / big_r))
    half = half_advance(prof, c)
    ctx.report(index, 0.0, "the forward pass")
    fwd = _vessel_pass(ctx, prof, c, True, theta0)
    ctx.report(index, 0.5, "the return pass")
    ret = _vessel_pass(ctx, prof, c, False, theta0 + half)
    # Every circuit a rotated copy of the first: the directions turn with it (about the straight axis, +z).
    heads = [(index + 1, j + 1, 2 * j + i + 1, kind, pas[3])
             for j in range(n_c) for i, (kind, pas) in enumerate(((PassKind.FORWARD, fwd), (PassKind.RETURN, ret)))]
    passes = turned_copies(surf, heads, [fwd[:3], ret[:3]], [j * 2.0 * half for j in range(n_c)])
    notes = [f"turnaround radius c = {c:.4f} mm on the domes (polar opening {r_open:.4g} mm); angle moved "
             f"{alpha - cfg.angle_deg:+.4f} deg to close the pattern (k = {k} of {n_c})"] + ([note] if note else [])
    e1, e2 = prof.equator_t
    stations = np.linspace(e1, e2, COVERAGE_STATIONS + 2)[1:-1]
    done = finish_layer(ctx, cfg, index, alpha, n_c, k, 0.0, 0.0, c, passes, stations, notes)
    return replace(done, turnaround_radii=(c, c))

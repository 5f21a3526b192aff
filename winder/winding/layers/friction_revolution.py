"""Helical layers held at their angle by friction on open surfaces of revolution (docs/math/09).

A cone, a table profile or a tapered pole: where the geodesic at the layer's angle turns around
inside the winding region (Clairaut), `slip: auto` holds the angle over the whole region with the
slip lambda(t) that cancels the Clairaut drift. Every pass is a rotated copy of one quadrature, so
forward and return passes advance alike and the pattern closes with the dwells (docs/math/05-winding.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from winder.config.winding import LayerConfig
from winder.errors import SolverError
from winder.geometry.profiles import AxialProfile
from winder.geometry.sections import Circle
from winder.geometry.surface import SweepSurface
from winder.winding.coverage import layer_coverage
from winder.winding.layers.friction_open import with_dwells
from winder.winding.passes import COVERAGE_STATIONS, PlanContext, finish_layer, make_pass, winding_region
from winder.winding.pattern import close_open_pattern
from winder.winding.results import FiberPass, LayerPlan, PassKind
from winder.winding.turnaround import SWING_MIN_DEG

MIN_POINTS = 200  # points per pass at the least: the slip is measured from them
FINE = 16  # quadrature stations per pass point (composite trapezoid on the profile's exact values)
NEED_SAMPLES = 2001  # stations where the closed-form lambda(t) is taken over the region
COVERED_TARGET = 0.999
GAP_TARGET = 0.02  # of the band width
MAX_EXTRA_CIRCUITS = 8
ANGLE_SEARCH_STEPS = 30  # bisection steps for the least angle friction holds


def is_open_revolution(surface: SweepSurface) -> bool:
    """A straight axis, a circular section and an axial profile (cone, table, constant)."""
    return (surface.curve.is_straight and isinstance(surface.section, Circle)
            and isinstance(surface.profile, AxialProfile))


def _profile(surface: SweepSurface, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    ev = surface.profile.evaluate(surface.profile.s_of_t(t))
    return ev.r, ev.r1, ev.r2


def geodesic_reaches(surface: SweepSurface, t_a: float, t_b: float, angle_deg: float) -> bool:
    """Whether the geodesic at angle_deg from either end of [t_a, t_b] reaches the other (Clairaut:
    r(t) sin(alpha) stays below r along the way)."""
    t = np.linspace(t_a, t_b, NEED_SAMPLES)
    r = _profile(surface, t)[0]
    s = math.sin(math.radians(angle_deg))
    return bool(np.all(r > r[0] * s) and np.all(r > r[-1] * s))


def held_slip(surface: SweepSurface, t: np.ndarray, angle_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """(lambda, press) at stations t (m,) of a forward pass (t increasing) holding angle_deg:
    lambda = r' tan(a) (1 + r'^2) / press, press = sin(a) tan(a) (1 + r'^2) - r r'' cos(a), which has
    k_n's sign (docs/math/09); a return pass needs -lambda."""
    a = math.radians(angle_deg)
    r, r1, r2 = _profile(surface, t)
    q = 1.0 + r1 * r1
    press = math.sin(a) * math.tan(a) * q - r * r2 * math.cos(a)
    return r1 * math.tan(a) * q / np.where(press > 0.0, press, 1.0), press


def held_need(surface: SweepSurface, t_a: float, t_b: float, angle_deg: float) -> tuple[float, float, bool]:
    """(the least mu that holds the angle, the station where it is needed, whether the fiber presses
    everywhere) over the region; at a bridge the station is where it bridges."""
    t = np.linspace(t_a, t_b, NEED_SAMPLES)
    lam, press = held_slip(surface, t, angle_deg)
    if np.any(press <= 0.0):
        return math.inf, float(t[int(np.argmin(press))]), False
    k = int(np.argmax(np.abs(lam)))
    return float(abs(lam[k])), float(t[k]), True


def need_message(surface: SweepSurface, region: tuple[float, float], angle_deg: float, mu: float, need: float,
                 at: float, presses: bool) -> str | None:
    """Why friction mu cannot hold angle_deg on the region (None where it can), with what would: a
    steeper angle presses harder (k_n grows with sin(alpha) tan(alpha)) and needs less friction (on a
    cone lambda = r' / sin(alpha)), so the remedy is the least angle above that holds, and the friction
    the angle needs (exact: the held path does not depend on it)."""
    fixes = [] if not presses or need > 1.0 else [f"winding.friction: {math.ceil(need * 100.0 - 1e-9) / 100.0:.2f}"]
    steeper = least_held_angle(surface, region, angle_deg, mu)
    if steeper is not None:
        fixes.append(f"angle: {steeper:g} (friction {mu:g} holds it)")
    hint = "; what plans it: " + "; ".join(fixes) if fixes else "; no angle below 89 deg holds it"
    if not presses:
        return (f"held at {angle_deg:g} deg the fiber bridges at t = {at:.4g} mm (the profile curves away faster "
                f"than the fiber): no friction holds it{hint}")
    if need > mu:
        return (f"slip: auto holds {angle_deg:g} deg where the geodesic cannot reach (Clairaut) only with friction "
                f"{need:.3g} (|k_g / k_n| at t = {at:.4g} mm), above winding.friction {mu:g}{hint}")
    return None


def turn_remedies(surface: SweepSurface, region: tuple[float, float], angle_deg: float, mu: float) -> str:
    """What lays a layer whose geodesic at angle_deg turns around inside the region (Clairaut, on the
    widest section), each from a closed form: the largest angle whose geodesic reaches every station,
    slip: auto where friction holds the angle (the friction it needs), the region ended short of the
    turnaround."""
    t = np.linspace(*region, NEED_SAMPLES)
    r = _profile(surface, t)[0]
    k = int(np.argmax(r))
    reach = math.degrees(math.asin(min(1.0, float(np.min(r)) / float(r[k]))))
    fixes = [f"angle: {math.floor(reach * 10.0 - 1e-6) / 10.0:g} (its geodesic reaches both ends)"]
    need, _, presses = held_need(surface, *region, angle_deg)
    if presses and need <= 1.0:
        fixes.append("slip: auto" + (f" (friction {need:.3g} holds {angle_deg:g} deg)" if need <= mu else
                                     f" with winding.friction: {math.ceil(need * 100.0 - 1e-9) / 100.0:.2f}"))
    c = float(r[k]) * math.sin(math.radians(angle_deg))
    beyond = np.flatnonzero(r <= c)  # stations past a turnaround, on either side of the widest
    after, before = beyond[beyond > k], beyond[beyond < k]
    ends = ([f"start at t = {t[before[-1] + 1]:.5g}"] if before.size else []) + (
        [f"end at t = {t[after[0] - 1]:.5g}"] if after.size else [])
    if ends:
        fixes.append("winding.region " + " and ".join(ends) + " (short of the turnaround)")
    return "; what plans it: " + "; ".join(fixes)


def least_held_angle(surface: SweepSurface, region: tuple[float, float], angle_deg: float, mu: float) -> float | None:
    """The least angle above angle_deg (to 0.1 deg, rounded up) that friction mu holds over the region
    and at which the fiber presses everywhere; None below 89 deg."""
    def holds(a: float) -> bool:
        need, _, presses = held_need(surface, *region, a)
        return presses and need <= mu

    lo, hi = angle_deg, 89.0
    if not holds(hi):
        return None
    for _ in range(ANGLE_SEARCH_STEPS):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if holds(mid) else (mid, hi)
    return math.ceil(hi * 10.0) / 10.0


def _pass(surface: SweepSurface, t_a: float, t_b: float, alpha: Callable[[np.ndarray], np.ndarray], points: int,
          forward: bool):
    """(t (m,) in travel order, theta - theta0 (m,), dtheta/dt (m,)): one pass at the winding angle
    alpha(t) (rad, of stations (k,))."""
    fine = np.linspace(t_a, t_b, FINE * (points - 1) + 1)
    r, r1, _ = _profile(surface, fine)
    rate = np.tan(alpha(fine)) * np.sqrt(1.0 + r1 * r1) / r
    theta = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(fine))])[::FINE]
    t, d1 = fine[::FINE], rate[::FINE]
    if not forward:  # theta increases along the travel either way
        t, theta, d1 = t[::-1], theta[-1] - theta[::-1], -d1[::-1]
    return t, theta, d1


def _directions(surface: SweepSurface, t: np.ndarray, th: np.ndarray, d1: np.ndarray, forward: bool) -> np.ndarray:
    ev = surface.evaluate(surface.profile.s_of_t(t), th, order=1)
    v = (1.0 if forward else -1.0) * (ev.ps + ev.pt * d1[:, None])
    return v / np.linalg.norm(v, axis=1)[:, None]


def _length(surface: SweepSurface, t: np.ndarray, th: np.ndarray, d1: np.ndarray) -> float:
    ev = surface.evaluate(surface.profile.s_of_t(t), th, order=1)
    return float(abs(np.trapezoid(np.linalg.norm(ev.ps + ev.pt * d1[:, None], axis=1), t)))


def held_angle_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float, mu: float) -> LayerPlan:
    """The layer at its angle over the whole region, friction-held (module docstring)."""
    t_a, t_b = winding_region(ctx)
    need, at, presses = held_need(ctx.surface, t_a, t_b, cfg.angle_deg)
    why = need_message(ctx.surface, (t_a, t_b), cfg.angle_deg, mu, need, at, presses)
    if why is not None:
        raise SolverError(f"{ctx.key(index)}: {why}")
    a = math.radians(cfg.angle_deg)
    notes = [f"friction-held at {cfg.angle_deg:g} deg over the region (the geodesic turns around before the "
             f"narrow end: Clairaut); designed |k_g / k_n| <= {need:.3f} at t = {at:.4g} mm (friction {mu:g})"]
    return revolution_layer(ctx, cfg, index, theta0, lambda t: np.full_like(t, a), notes)


def revolution_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float,
                     alpha: Callable[[np.ndarray], np.ndarray], notes: list[str]) -> LayerPlan:
    """A layer on an open surface of revolution whose passes lie at the winding angle alpha(t) (rad),
    every pass a rotated copy of one quadrature (module docstring)."""
    surf, w = ctx.surface, ctx.winding
    t_a, t_b = winding_region(ctx)
    points = max(MIN_POINTS, (w.points or 0) + 2)
    t = np.linspace(t_a, t_b, NEED_SAMPLES)
    # the bands must span the perimeter where it is widest across the fiber
    across = float(np.max(_profile(surf, t)[0] * np.cos(alpha(t))))
    n_c = max(1, math.ceil(2.0 * math.pi * across / w.band_width - 1e-9))
    curves = {fwd: _pass(surf, t_a, t_b, alpha, points, fwd) for fwd in (True, False)}
    adv = curves[True][1][-1] + curves[False][1][-1]
    stations = np.linspace(t_a, t_b, COVERAGE_STATIONS + 2)[1:-1]
    for _ in range(MAX_EXTRA_CIRCUITS + 1):
        pat = close_open_pattern(n_c, adv / (2.0 * math.pi), max(w.dwell_start_deg, SWING_MIN_DEG) / 360.0,
                                 max(w.dwell_end_deg, SWING_MIN_DEG) / 360.0, cfg.pattern, ctx.key(index, "pattern"))
        passes = _passes(ctx, index, curves, pat, theta0, (t_a, t_b))
        cov = layer_coverage(surf, ctx.arcs, passes, w.band_width, stations)
        if (cfg.pattern is not None or cov.covered_fraction >= COVERED_TARGET
                and cov.max_gap_mm <= GAP_TARGET * w.band_width):
            break
        n_c += 1
    return finish_layer(ctx, cfg, index, cfg.angle_deg, n_c, pat.pattern, pat.dwell_start * 360.0,
                        pat.dwell_end * 360.0, None, passes, stations, notes, cov)


def _passes(ctx: PlanContext, index: int, curves: dict, pat, theta0: float, region: tuple[float, float]) -> list[FiberPass]:
    """Every pass of the layer in winding order: forward, dwell, return, dwell per circuit."""
    surf = ctx.surface
    t_a, t_b = region
    layer = index + 1
    laid: list[FiberPass] = []
    ends: list[float] = []
    for j in range(pat.circuits):
        ctx.report(index, j / pat.circuits, f"circuit {j + 1} of {pat.circuits}")
        start = theta0 + 2.0 * math.pi * pat.advance * j
        for kind, fwd in ((PassKind.FORWARD, True), (PassKind.RETURN, False)):
            t, th, d1 = curves[fwd]
            th = start + th
            laid.append(make_pass(surf, layer, j + 1, 0, kind, surf.profile.s_of_t(t), th,
                                  _directions(surf, t, th, d1, fwd), _length(surf, t, th, d1)))
            start = float(th[-1]) + 2.0 * math.pi * (pat.dwell_end if fwd else 0.0)
        ends.append(theta0 + 2.0 * math.pi * pat.advance * (j + 1))
    s_a, s_b = (float(v) for v in surf.profile.s_of_t(np.array([t_a, t_b])))
    return with_dwells(ctx, layer, laid, lambda k: float(laid[k + 1].theta[0]) if laid[k].kind is PassKind.FORWARD
                       else ends[k // 2], (s_a, s_b))

"""Helical layers on domed vessels held by friction on the domes: a given cylinder angle turning at a
given radius (`turnaround_radius`), or at the radius a given slip leads to (docs/math/07-friction.md).

On the cylinder the fiber is the geodesic helix at the layer angle; on each dome it is friction-held
(dome_paths) so that it turns at r = c, which a geodesic reaches only at c = R sin(alpha). The
circuits are rotated copies (a surface of revolution). The pattern closes without moving the angle
or c: each dome's lambda gets a small linear term in the fiber length that changes its advance.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from winder.config.winding import LayerConfig
from winder.paths.dome_paths import Leg, close_leg, dome_meridian, solve_slip, trace_leg
from winder.errors import SolverError
from winder.winding.passes import COVERAGE_STATIONS, PlanContext, finish_layer, make_pass
from winder.winding.pattern import circuits_for_coverage, coprime_skips
from winder.winding.results import FiberPass, LayerPlan, PassKind
from winder.geometry.measure import row_norms

LEG_POINTS = 120  # samples per dome leg (the turnaround is inside it)


def _pattern(advance: float, circuits: int, pattern: int | None) -> tuple[int, float]:
    """The skip k and the advance change (turns, least |.|) making the circuit advance k / N_c."""
    best = None
    for k in ([pattern % circuits or 1] if pattern is not None else coprime_skips(circuits)):
        delta = (k / circuits - advance + 0.5) % 1.0 - 0.5
        if best is None or abs(delta) < abs(best[1]):
            best = (k, delta)
    return best


def _up(value: float) -> str:
    """A friction to suggest: value rounded up to 3 decimals (so that it holds, not just rounds near)."""
    return f"{math.ceil(value * 1000.0 - 1e-9) / 1000.0:g}"


def _leg_points(surface, leg: Leg, s_eq: float, theta_eq: float, outward: bool, m: int):
    """(s, theta, alpha) of a leg from the equator (outward False) or its mirror back to it (True)."""
    l = np.linspace(0.0, leg.length, m)
    s, th, al = leg.state(l)
    if not outward:
        return s, theta_eq + th, al
    # The mirror image about the turnaround meridian, laid from the turnaround back to the equator.
    return s[::-1], theta_eq + (2.0 * th[-1] - th[::-1]), math.pi - al[::-1]


def _directions(surface, s: np.ndarray, th: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    ev = surface.evaluate(s, th, order=1)
    e_s = ev.ps / row_norms(ev.ps)[:, None]
    e_t = ev.pt / row_norms(ev.pt)[:, None]
    return np.cos(alpha)[:, None] * e_s + np.sin(alpha)[:, None] * e_t


def friction_vessel_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float, mu: float,
                          radii: tuple[float | None, float | None], slip: float, least_mu: bool = True) -> LayerPlan:
    """Each dome turns at its radius in radii (lambda solved for), or where lambda = +-slip leads where
    its radius is None (slip 0: a geodesic dome, docs/math/17 17.6). least_mu: where a dome needs more
    than the friction, find how much for the message (a full solve); else fail fast."""
    surf, w = ctx.surface, ctx.winding
    prof = surf.profile
    big_r, alpha = prof.radius, math.radians(cfg.angle_deg)
    e1, e2 = prof.equator_s
    openings = (prof.dome.end_radius, prof.end_dome.end_radius)
    # The first dome is reached going toward s = 0 (heading pi - alpha), the end dome toward s = L.
    domes = ((e1, math.pi - alpha), (e2, alpha))
    meridians = (dome_meridian(prof, False), dome_meridian(prof, True))
    legs, slips = [], []
    over = None  # the first dome needing more than the friction: the least mu follows the pattern's closing
    for d, (s_eq, heading) in enumerate(domes):
        where = f"{ctx.key(index)}: on the {'first' if d == 0 else 'end'} dome"
        if radii[d] is not None:
            try:
                lam, leg = solve_slip(meridians[d], s_eq, heading, radii[d], mu + 1e-12)
            except SolverError as exc:
                if not least_mu:
                    raise SolverError(f"{where}: {exc}") from exc
                try:  # beyond the friction: how far, for the message below
                    lam, leg = solve_slip(meridians[d], s_eq, heading, radii[d])
                except SolverError as exc2:
                    raise SolverError(f"{where}: {exc2}") from exc2
        else:
            lam = slip if d == 1 else -slip  # the sign follows the pass direction
            leg = trace_leg(meridians[d], s_eq, heading, lambda l, lam=lam: lam)
            if not leg.turned:
                raise SolverError(f"{where}: with slip {slip:g} the fiber at {cfg.angle_deg:g} deg does not turn "
                                  f"around before the polar opening ({openings[d]:.4g} mm); raise the slip or the angle")
        c_min = openings[d] + 0.5 * w.band_width
        if leg.radius < c_min - 1e-9:
            raise SolverError(f"{where}: the fiber turns around at r = {leg.radius:.3f} mm, inside the polar opening "
                              f"({openings[d]:.4g} mm) plus half a band ({c_min:.3f} mm)")
        if abs(lam) > mu + 1e-12 and over is None:
            t_turn = float(surf.t_of_s(np.array([leg.state(leg.length)[0]]))[0])
            over = (f"{where}: turning at r = {leg.radius:.3f} mm (t = {t_turn:.1f} mm) needs |k_g / k_n| = "
                    f"{abs(lam):.3g}, above the friction {mu:g} (winding.friction)")
        legs.append(leg)
        slips.append(lam)
    cyl = prof.cylinder_length * math.tan(alpha) / big_r
    advance = 2.0 * (legs[0].advance + cyl + legs[1].advance) / (2.0 * math.pi)
    n_c = cfg.circuits or circuits_for_coverage(2.0 * math.pi * big_r, alpha, w.band_width)
    k, delta = _pattern(advance, n_c, cfg.pattern)
    if abs(delta) > 1e-12:
        # Each dome is laid twice per circuit (in and out): a quarter of the change each.
        for d, (s_eq, heading) in enumerate(domes):
            leg = legs[d]
            try:
                lam0, lam1, legs[d] = close_leg(meridians[d], s_eq, heading, leg.radius, slips[d], leg.length,
                                                leg.advance + 0.25 * delta * 2.0 * math.pi, start=leg)
            except SolverError as exc:
                raise SolverError(f"{ctx.key(index)}: on the {'first' if d == 0 else 'end'} dome: {exc} (the leg "
                                  f"turns at r = {leg.radius:.3f} mm of {big_r:g}; a leg this short leaves the slip no "
                                  "hold on the advance: lower the angle, or give turnaround_radius)") from exc
            slips[d] = max(abs(lam0 - 0.5 * lam1), abs(lam0 + lam1 * (legs[d].length / leg.length - 0.5)))
    worst = max(abs(x) for x in slips)
    if over is not None:
        raise SolverError(f"{over}; the least mu is {_up(worst)} with the pattern closed")
    if worst > mu + 1e-12:
        raise SolverError(f"{ctx.key(index)}: closing the pattern needs |k_g / k_n| up to {worst:.3g} on the domes, "
                          f"above the friction {mu:g} (winding.friction); the least mu is {_up(worst)}")
    passes = _passes(ctx, index, legs, domes, theta0, n_c, cyl)
    c = 0.5 * (legs[0].radius + legs[1].radius)
    how = ["geodesic" if radii[d] is None and slip == 0.0 else "friction-held" for d in range(2)]
    notes = [f"turnarounds: r = {legs[0].radius:.3f} mm on the first dome ({how[0]}), {legs[1].radius:.3f} mm on "
             f"the end dome ({how[1]}) (Clairaut would turn at {big_r * math.sin(alpha):.3f} mm), |k_g / k_n| up to "
             f"{worst:.3f} (friction {mu:g}); pattern k = {k} of {n_c} closed on the domes, the angle kept"]
    t1, t2 = prof.equator_t
    stations = np.linspace(t1, t2, COVERAGE_STATIONS + 2)[1:-1]
    done = finish_layer(ctx, cfg, index, cfg.angle_deg, n_c, k, 0.0, 0.0, c, passes, stations, notes)
    return replace(done, turnaround_radii=(legs[0].radius, legs[1].radius))


def _passes(ctx: PlanContext, index: int, legs: list[Leg], domes, theta0: float, n_c: int,
            cyl: float) -> list[FiberPass]:
    surf = ctx.surface
    prof = surf.profile
    e1, e2 = prof.equator_s
    # The cylinder's samples are spaced no closer than the legs': a cylinder of no length (or of a
    # micrometre) joins the legs at the equator without repeating a point or crowding points closer
    # than any derivative of the pass can be read from (every spline of the pass is in t or s).
    spacing = min(leg.length for leg in legs) / (LEG_POINTS - 1)
    fiber = math.hypot(e2 - e1, prof.radius * cyl)  # the helix on the cylinder
    m_cyl = min(max(8, int(math.ceil((ctx.winding.points or 200) * 0.5))), 1 + int(math.ceil(fiber / spacing)))
    s_cyl = np.linspace(e1, e2, m_cyl)

    def one(forward: bool, th_start: float):
        first, last = (0, 1) if forward else (1, 0)
        s_a, th_a, al_a = _leg_points(surf, legs[first], domes[first][0], 0.0, True, LEG_POINTS)
        th_a = th_a - th_a[0] + th_start
        s_c = s_cyl if forward else s_cyl[::-1]
        th_c = th_a[-1] + cyl * np.linspace(0.0, 1.0, m_cyl)
        al_c = np.full(m_cyl, domes[1][1] if forward else domes[0][1])
        s_b, th_b, al_b = _leg_points(surf, legs[last], domes[last][0], th_c[-1], False, LEG_POINTS)
        s = np.concatenate([s_a, s_c[1:], s_b[1:]])
        th = np.concatenate([th_a, th_c[1:], th_b[1:]])
        al = np.concatenate([al_a, al_c[1:], al_b[1:]])
        return s, th, _directions(surf, s, th, al)

    fwd = one(True, theta0)
    ret = one(False, float(fwd[1][-1]))
    shift_circuit = float(ret[1][-1] - fwd[1][0])
    passes: list[FiberPass] = []
    number = 0
    for j in range(n_c):
        shift = j * shift_circuit
        for kind, (s, th, d) in ((PassKind.FORWARD, fwd), (PassKind.RETURN, ret)):
            number += 1
            c_, s_ = math.cos(shift), math.sin(shift)
            turned = np.column_stack([c_ * d[:, 0] - s_ * d[:, 1], s_ * d[:, 0] + c_ * d[:, 1], d[:, 2]])
            pts = surf.points(s, th + shift)
            length = float(np.sum(row_norms(np.diff(pts, axis=0))))
            passes.append(make_pass(surf, index + 1, j + 1, number, kind, s, th + shift, turned, length))
    return passes

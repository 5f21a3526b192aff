"""The slip check: friction holds a fiber where |k_g / k_n| <= mu and it presses, k_n > 0 (docs/math/07-friction.md).

check_slip: a hoop path, densely resampled. measure / check: every laid pass of a layer, whatever
planned it (geodesic, friction-held, hoop), from the pass's own points with the exact surface normal
(the discrete curvature of the polyline, winder.geometry.curvature); a layer that bridges or slips
is refused (SolverError, exit 1) naming the layer, the station and the least mu.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

import numpy as np

from winder.errors import SolverError
from winder.geometry.curvature import curve_curvatures, polyline_curvatures
from winder.geometry.sections import polar_arcs
from winder.geometry.surface import SweepSurface
from winder.winding.liftoff import pass_lift_off
from winder.winding.results import FiberPass, PassKind

if TYPE_CHECKING:  # passes.py checks every layer with this module: no import cycle at run time
    from winder.winding.passes import PlanContext

SLIP_SAMPLES_PER_TURN = 72
BRIDGE_TOL = 1e-6  # k_n below -this * the pass's largest k_n: the fiber bridges (flat faces have 0)
PRESS_FLOOR = 1e-3  # slip is measured where k_n >= this * the pass's largest k_n (not on flat faces)
SLIP_MARGIN = 1e-3  # measured slip may exceed mu by this (the polyline measurement's own error)
LINE_PRESS_FLOOR = 1e-2  # an unrolled line's slip is read where k_n is at least this share of its largest


def slip_ratio(surface: SweepSurface, s: np.ndarray, th: np.ndarray) -> np.ndarray:
    """|k_g / k_n| at the points (s, theta) (m,) of a densely sampled path: friction mu holds the fiber
    where this is <= mu (docs/math/07-friction.md). The samples' index is the parameter (np.gradient derivatives).
    Where the path runs on a flat face (k_n below PRESS_FLOOR of its largest) friction is not what
    holds it, and the ratio of two round-off values would say nothing: 0 there, as in `measure`."""
    ds, dth = np.gradient(s), np.gradient(th)
    k_n, k_g = curve_curvatures(surface, s, th, ds, dth, np.gradient(ds), np.gradient(dth))
    pressing = np.abs(k_n) >= PRESS_FLOOR * float(np.max(np.abs(k_n)))
    return np.where(pressing, np.abs(k_g) / np.where(pressing, np.abs(k_n), 1.0), 0.0)


def check_slip(ctx: PlanContext, index: int, p: FiberPass, turns: float) -> None:
    """Refuse a path of layer `index` (0-based) that friction cannot hold: |k_g / k_n| <= mu."""
    surf = ctx.surface
    if surf.is_axial_parameter and not surf.section.is_circle:
        # The hoop is the unrolled line (s and the perimeter fraction linear): its own curvature, not
        # that of theta interpolated linearly between its points, which bends at every corner of a
        # flattish section (a superellipse of exponent 4.5 read a slip of 1.32 on a geodesic)
        k_n, k_g = _line_curvatures(surf, [p])[0]
        s = p.s[1:-1]
        pressing = np.abs(k_n) >= PRESS_FLOOR * float(np.max(np.abs(k_n)))
        ratio = np.where(pressing, np.abs(k_g) / np.where(pressing, np.abs(k_n), 1.0), 0.0)
    else:
        m = max(50, int(turns * SLIP_SAMPLES_PER_TURN))
        i = np.linspace(0.0, p.s.size - 1.0, m)
        idx = np.arange(p.s.size, dtype=float)
        s, th = np.interp(i, idx, p.s), np.interp(i, idx, p.theta)
        ratio = slip_ratio(surf, s, th)
        from winder.geometry.joints import joint_stations  # noqa: PLC0415 - one-piece guides have none

        joints = joint_stations(surf)
        if joints.size:  # the differences straddling a joint of the guide read its metric's jump, not the fiber
            near = np.searchsorted(joints, s)
            gap = np.minimum(np.abs(s - joints[np.clip(near - 1, 0, joints.size - 1)]),
                             np.abs(s - joints[np.clip(near, 0, joints.size - 1)]))
            ratio = np.where(gap <= 2.0 * np.max(np.abs(np.diff(s))), 0.0, ratio)
    worst = int(np.argmax(ratio))
    if ratio[worst] > ctx.winding.friction + SLIP_MARGIN:  # a round-off slip is no slip, even at mu = 0
        t = float(surf.t_of_s(s[worst:worst + 1])[0])
        raise SolverError(f"{ctx.key(index)}: a hoop layer would slip here: |k_g / k_n| reaches "
                          f"{ratio[worst]:.3g} at t = {t:.3f} mm, above the friction coefficient "
                          f"{ctx.winding.friction:g} (winding.friction); hoop layers hold on cylindrical "
                          f"regions")


@dataclasses.dataclass(frozen=True)
class LayerSlip:
    """max_slip : largest |k_g / k_n| over the layer's passes; min_normal_curvature : least k_n (1/mm),
    max_normal_curvature : largest |k_n| (its scale). slip_t, bridge_t : stations (mm) of the largest
    slip and of the least k_n; pass numbers of both."""

    max_slip: float
    min_normal_curvature: float
    max_normal_curvature: float
    slip_t: float
    slip_pass: int
    bridge_t: float
    bridge_pass: int
    max_lift_off: float = 0.0  # mm: the largest lift-off over a concave stretch (docs/math 8.10)
    lift_t: float = 0.0  # station (mm) and pass of it
    lift_pass: int = 0


LIFT_FLOOR = 1e-6  # mm: a lift-off below this is round-off, no bridge (with a tolerance of 0)
WOUND_TOL = 1e-9  # mm: a station this close outside the wound region counts as in it


def _lift_off(laid: list[FiberPass], curves: list[tuple[np.ndarray, np.ndarray]],
              wound: tuple[float, float] | None = None) -> tuple[float, float, int]:
    """(lift-off mm, t, pass number) of the passes that bridge (k_n below -BRIDGE_TOL of their largest
    |k_n|), the largest within the stations `wound` (t_a, t_b; all where None); rotated copies (the
    same stations) are measured once."""
    best, seen = (0.0, 0.0, 0), {}
    for p, (k_n, _) in zip(laid, curves):
        top = float(np.max(np.abs(k_n))) if k_n.size else 0.0
        if not k_n.size or not float(np.min(k_n)) < -BRIDGE_TOL * top:
            continue
        key = (p.s.tobytes(), k_n.size)
        if key not in seen:
            t = p.t[1:-1]
            judged = None if wound is None else (t >= wound[0] - WOUND_TOL) & (t <= wound[1] + WOUND_TOL)
            seen[key] = pass_lift_off(p.points, k_n, judged)
        out = seen[key]
        if out.lift_mm > best[0]:
            best = (out.lift_mm, float(p.t[out.at + 1]), p.number)
    return best


def _curvatures(surface: SweepSurface, passes: list[FiberPass]) -> list[tuple[np.ndarray, np.ndarray]]:
    """polyline_curvatures of each pass (>= 3 points), from one call over the passes one after the
    other: its values at a vertex come from that vertex and its two neighbours, so those of each
    pass's interior are its own; the two at each junction between passes are dropped."""
    sizes = np.array([p.s.size for p in passes])
    with np.errstate(all="ignore"):  # a junction's segment may have no length (a pass starts where one ended)
        k_n, k_g = polyline_curvatures(surface, np.concatenate([p.s for p in passes]),
                                       np.concatenate([p.theta for p in passes]),
                                       np.concatenate([p.points for p in passes]))
    first = np.cumsum(sizes) - sizes  # in the interior vertices' numbering, pass i's start at first_i
    return [(k_n[a:a + n - 2], k_g[a:a + n - 2]) for a, n in zip(first.tolist(), sizes.tolist())]


def _geodesic_curvatures(surface: SweepSurface, passes: list[FiberPass]) -> list[tuple[np.ndarray, np.ndarray]]:
    """(k_n, k_g) at the interior vertices of passes known to be geodesics (their points and tangents
    exact): k_g = 0, k_n the surface's normal curvature along the tangent. Their polylines would read
    round-off and chord error instead (a 2 mm corner under 21 mm segments: a slip of 0.74)."""
    s = np.concatenate([p.s[1:-1] for p in passes])
    th = np.concatenate([p.theta[1:-1] for p in passes])
    d = np.concatenate([p.direction[1:-1] for p in passes])
    ev = surface.evaluate(s, th, order=1, with_point=False)
    # the tangent's parameter rates: d = a Phi_s + b Phi_theta (the normal equations of the 2 x 2 system)
    ee, ff, gg = (np.einsum("ij,ij->i", x, y) for x, y in ((ev.ps, ev.ps), (ev.ps, ev.pt), (ev.pt, ev.pt)))
    pd, td = np.einsum("ij,ij->i", ev.ps, d), np.einsum("ij,ij->i", ev.pt, d)
    det = ee * gg - ff * ff
    zero = np.zeros_like(s)
    k_n, _ = curve_curvatures(surface, s, th, (gg * pd - ff * td) / det, (ee * td - ff * pd) / det, zero, zero)
    cuts = np.cumsum([p.s.size - 2 for p in passes])[:-1]
    return [(k, np.zeros_like(k)) for k in np.split(k_n, cuts)]


def _line_curvatures(surface: SweepSurface, passes: list[FiberPass]) -> list[tuple[np.ndarray, np.ndarray]]:
    """(k_n, k_g) at the interior vertices of unrolled lines (advance.cylinder_pass: s and the perimeter
    fraction f linear in the point index), from their exact derivatives: s' and f' constant, theta' =
    f' theta_f, theta'' = f'^2 theta_ff, theta_f = L / w and theta_ff = -theta_f^2 w_theta / w (w = |d
    section point / d theta|, L the perimeter). On a cylinder k_g is round-off; on one grown by a laminate
    whose edge lies inside the region it is what friction must hold there."""
    arcs = polar_arcs(surface.section)
    out = []
    for p in passes:
        m = p.s.size
        f = arcs.fraction(p.theta[[0, -1]])
        ds, df = (p.s[-1] - p.s[0]) / (m - 1), (f[1] - f[0]) / (m - 1)
        s, th = p.s[1:-1], p.theta[1:-1]
        rho, r1, r2 = surface.section.polar_cs(np.cos(th), np.sin(th), order=2)
        w = np.hypot(rho, r1)
        th_f = arcs.length / w
        th_ff = -th_f * th_f * (rho * r1 + r1 * r2) / (w * w)
        k_n, k_g = curve_curvatures(surface, s, th, np.full_like(s, ds), df * th_f, np.zeros_like(s), df * df * th_ff)
        # On a flat face a laminate's overlaps curve the line by 1e-4 /mm both ways: k_g over k_n there
        # is the noise of the bands (a slip of 1.44 on a grown box), and the fiber hardly presses
        out.append((k_n, np.where(np.abs(k_n) >= LINE_PRESS_FLOOR * float(np.max(np.abs(k_n))), k_g, 0.0)))
    return out


def measure(surface: SweepSurface, passes: list[FiberPass] | tuple[FiberPass, ...],
            geodesic: frozenset[PassKind] = frozenset(), wound: tuple[float, float] | None = None,
            lines: bool = False) -> LayerSlip:
    """The layer's slip and bridging margin, from the points of every laid (non-dwell) pass; passes of
    the kinds `geodesic` are exact geodesics (_geodesic_curvatures), or unrolled lines where `lines`
    (_line_curvatures: geodesics on a cylinder, held by friction on one a laminate grew); the lift-off is
    judged within the
    stations `wound` (the winding region, t_a, t_b; everywhere where None)."""
    laid = [p for p in passes if p.kind is not PassKind.DWELL and p.s.size >= 3]
    if not laid:
        return LayerSlip(0.0, np.inf, 0.0, 0.0, 0, 0.0, 0)
    exact = [p.kind in geodesic for p in laid]
    curves = [None] * len(laid)
    for flag, fun in ((False, _curvatures), (True, _line_curvatures if lines else _geodesic_curvatures)):
        members = [i for i, e in enumerate(exact) if e is flag]
        for i, c in zip(members, fun(surface, [laid[i] for i in members]) if members else []):
            curves[i] = c
    k_n, k_g = (np.concatenate(c) for c in zip(*curves))
    if not (np.all(np.isfinite(k_n)) and np.all(np.isfinite(k_g))):
        return _measure_each(laid, curves, wound)
    # Over all the passes at once, what _measure_each finds pass by pass: the first pass (in laying
    # order) holding the layer's extreme, at that pass's first point of it.
    sizes = np.array([p.s.size - 2 for p in laid])
    first = np.cumsum(sizes) - sizes
    mag = np.abs(k_n)
    top = np.maximum.reduceat(mag, first)
    # The floor is the layer's: a pass lying on one flat face (a short pass at a low angle on a wide
    # box section) has only round-off k_n (4e-15 /mm), and a floor of its own read round-off k_g over
    # it as a slip of 1.8e3.
    pressing = k_n >= PRESS_FLOOR * float(np.max(top))
    ratio = np.where(pressing, np.abs(k_g) / np.where(pressing, k_n, 1.0), 0.0)
    owner = np.repeat(np.arange(len(laid)), sizes)
    i, j = int(np.argmin(k_n)), int(np.argmax(ratio))
    p_i, p_j = laid[owner[i]], laid[owner[j]]
    slip = (float(ratio[j]), float(p_j.t[j - first[owner[j]] + 1]), p_j.number) if ratio[j] > 0.0 else (0.0, 0.0, 0)
    return LayerSlip(slip[0], float(k_n[i]), float(np.max(top)), slip[1], slip[2],
                     float(p_i.t[i - first[owner[i]] + 1]), p_i.number, *_lift_off(laid, curves, wound))


def _measure_each(laid: list[FiberPass], curves: list[tuple[np.ndarray, np.ndarray]],
                  wound: tuple[float, float] | None = None) -> LayerSlip:
    """measure, pass by pass (curvatures that are not all finite: the comparisons decide as they fall)."""
    best = [0.0, 0.0, 0, np.inf, 0.0, 0]
    scale = max(float(np.max(np.abs(k_n))) for k_n, _ in curves)  # the layer's, as in measure
    for p, (k_n, k_g) in zip(laid, curves):
        i = int(np.argmin(k_n))
        if k_n[i] < best[3]:
            best[3:] = [float(k_n[i]), float(p.t[i + 1]), p.number]
        pressing = k_n >= PRESS_FLOOR * scale
        if np.any(pressing):
            ratio = np.where(pressing, np.abs(k_g) / np.where(pressing, k_n, 1.0), 0.0)
            j = int(np.argmax(ratio))
            if ratio[j] > best[0]:
                best[:3] = [float(ratio[j]), float(p.t[j + 1]), p.number]
    return LayerSlip(best[0], best[3], scale, best[1], best[2], best[4], best[5], *_lift_off(laid, curves, wound))


def check(surface: SweepSurface, passes, mu: float, key: str, angle_deg: float,
          tolerance: float = 0.0, geodesic: frozenset[PassKind] = frozenset(),
          wound: tuple[float, float] | None = None, lines: bool = False) -> LayerSlip:
    """measure, then refuse a layer whose fiber slips, or bridges a concave stretch standing off it by
    more than `tolerance` mm within the wound stations (winding.bridging_tolerance; SolverError naming
    key and station)."""
    out = measure(surface, passes, geodesic, wound, lines)
    if out.max_lift_off > tolerance + LIFT_FLOOR:
        raise SolverError(f"{key}: the fiber bridges at t = {out.lift_t:.1f} mm (pass {out.lift_pass}) at "
                          f"{angle_deg:g} deg: it stands {out.max_lift_off:.3g} mm off the mandrel there, above "
                          f"winding.bridging_tolerance ({tolerance:g} mm), whatever the friction (least k_n "
                          f"{out.min_normal_curvature:.3g} /mm)")
    if out.max_slip > mu + SLIP_MARGIN:
        raise SolverError(f"{key}: the fiber would slip at t = {out.slip_t:.1f} mm (pass {out.slip_pass}): it needs "
                          f"|k_g / k_n| = {out.max_slip:.3g} there, above the friction {mu:g} (winding.friction)")
    return out

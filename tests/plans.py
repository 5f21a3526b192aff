"""Plan builders shared by the machine and export tests: passes, layers and whole plans on a tube."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline

from winder.config.winding import LayerType
from winder.paths.geodesic import geodesic
from winder.winding.results import Coverage, FiberPass, LayerPlan, PassKind, WindingPlan, winding_angle_deg

R = 40.0  # mm, the tube of cylinder_plan


def make_pass(surface, s, theta, direction, *, layer, circuit, number, kind) -> FiberPass:
    s = np.asarray(s, float)
    theta = np.asarray(theta, float)
    pts = surface.points(s, theta)
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d, axis=1)[:, None]
    length = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    return FiberPass(layer, circuit, number, kind, surface.t_of_s(s), s, theta, pts, d,
                     winding_angle_deg(surface, s, theta, d), length)


def helix(surface, t0, t1, th0, th1, m, **kw) -> FiberPass:
    """A helix on a straight circular tube (a geodesic: it unrolls to a straight line); it also
    serves for a dwell (t0 == t1: the mandrel turns, the carriage waits)."""
    u = np.linspace(0.0, 1.0, m)
    s = t0 + u * (t1 - t0)
    th = th0 + u * (th1 - th0)
    ev = surface.evaluate(s, th, order=1)
    d = ev.ps * (t1 - t0) + ev.pt * (th1 - th0)
    out = make_pass(surface, s, th, d, **kw)
    radius = float(surface.radius(np.array([t0]), np.array([0.0]))[0])
    return FiberPass(*[getattr(out, f) for f in ("layer", "circuit", "number", "kind", "t", "s", "theta",
                                                  "points", "direction", "alpha_deg")],
                     length=float(np.hypot(t1 - t0, radius * (th1 - th0))) if surface.section.is_circle
                     else out.length)


def geodesic_pass(surface, start, end, n, *, rounds=0, **kw) -> FiberPass:
    """A solved geodesic; directions from the smooth path through its vertices."""
    res = geodesic(surface, start, end, rounds=rounds, n=n, estimate=False)
    i = np.arange(res.s.shape[0], dtype=float)
    cs, ct = CubicSpline(i, res.s), CubicSpline(i, res.theta)
    ev = surface.evaluate(res.s, res.theta, order=1)
    d = ev.ps * cs(i, 1)[:, None] + ev.pt * ct(i, 1)[:, None]
    out = make_pass(surface, res.s, res.theta, d, **kw)
    return FiberPass(*[getattr(out, f) for f in ("layer", "circuit", "number", "kind", "t", "s", "theta",
                                                  "points", "direction", "alpha_deg")], length=res.length)


def make_layer(index, passes, *, type_=LayerType.HELICAL, angle=55.0, circuits=2, pattern=1) -> LayerPlan:
    alphas = np.abs(np.concatenate([p.alpha_deg for p in passes]))
    return LayerPlan(index=index, type=type_, angle_deg=angle, requested_angle_deg=angle - 0.25,
                     circuits=circuits, pattern=pattern, dwell_start_deg=30.0, dwell_end_deg=45.0,
                     turnaround_radius=None, fiber_length_mm=float(sum(p.length for p in passes)),
                     alpha_min_deg=float(alphas.min()), alpha_max_deg=float(alphas.max()),
                     time_s=123.456789, passes=tuple(passes),
                     coverage=Coverage(np.linspace(20, 280, 5), 0.987654321, 1.23456789, 0.5, 1, 3),
                     notes=("a note",))


def cylinder_plan(surface, *, circuits=2, alpha=55.0, hoop=True, points=120) -> WindingPlan:
    """Helical circuits (forward, dwell, return, dwell) on a 40 mm tube, then a hoop layer whose
    angles restart near 0 (the program must carry A on)."""
    t0, t1 = 20.0, 280.0
    adv = (t1 - t0) * np.tan(np.radians(alpha)) / R
    passes = []
    th = 0.0
    number = 0
    for c in range(1, circuits + 1):
        for kind, (ta, tb, dth) in ((PassKind.FORWARD, (t0, t1, adv)), (PassKind.DWELL, (t1, t1, np.radians(45))),
                                    (PassKind.RETURN, (t1, t0, adv)), (PassKind.DWELL, (t0, t0, np.radians(30)))):
            number += 1
            m = points if kind in (PassKind.FORWARD, PassKind.RETURN) else 12
            passes.append(helix(surface, ta, tb, th, th + dth, m, layer=1, circuit=c, number=number, kind=kind))
            th += dth
    layers = [make_layer(1, passes, circuits=circuits, angle=alpha)]
    if hoop:
        turns = (t1 - t0) * np.tan(np.radians(86.0)) / R
        hp = helix(surface, t0, t1, 0.3, 0.3 + turns, 600, layer=2, circuit=1, number=1, kind=PassKind.HOOP)
        layers.append(make_layer(2, [hp], type_=LayerType.HOOP, angle=86.0, circuits=1, pattern=1))
    return WindingPlan("tube-test", "tests/tube.yaml", surface, tuple(layers))



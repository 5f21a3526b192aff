"""Guide curves and their rotation-minimizing frames (winder/curves.py, winder/frames.py).

Independent truths: the start conventions of docs/guide/conventions.md; closed-form arc geometry (centre of curvature,
end points, end frames); the RMF condition e2' . e3 = 0 by finite differences; the closed-form RMF
of a helix (Frenet frame turned by minus the integrated torsion) for double reflection on a
non-planar curve; a spline through samples of a circle against the circle itself.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from winder.config.axes import ArcAxis, PathAxis, SplineAxis
from winder.config.mandrel import LineAxis
from winder.geometry.build import make_curve
from winder.geometry.frames import double_reflection

EXACT_TOL = 1e-12  # closed-form geometry (mm, or dimensionless for unit vectors), scaled below
FRAME_TOL = 1e-12  # orthonormality / right-handedness of exact frames
FD_STEP = 1e-4  # mm, central differences along the curve
RMF_TOL = 1e-8  # |e2' . e3| by central differences (truncation ~ h^2 kappa^3 ~ 1e-14; round-off eps/h)
DR_TOL = 1e-10  # double reflection on a fine sampled arc vs the exact arc frame (global error O(h^4))
JOINT_TOL = 1e-10  # continuity of a path's point, tangent and frame across its joints
SPLINE_INTERP_TOL = 1e-8  # mm, the spline passes through its points
SPLINE_SPEED_TOL = 1e-8  # | |x'| - 1 | and |x' . x''| of the arc-length spline (measured ~1e-11, 2e-9)
SPLINE_FRAME_TOL = 1e-8  # spline frame: interpolated, re-orthonormalized
ARC_SPLINE_POS_TOL = 1e-3  # mm, cubic interpolation of 17 samples of a radius-100 quarter circle
ARC_SPLINE_KAPPA_RTOL = 2e-3  # curvature of that spline vs 1/radius, away from the ends (measured 1.2e-3)
ARC_SPLINE_FRAME_TOL = 5e-4  # its frame vs the exact arc frame (the not-a-knot end tangent is off by 1.7e-4 rad)

X, Y, Z = np.eye(3)


def stations(curve, m=97, margin=0.0):
    return np.linspace(margin, curve.length - margin, m)


def assert_orthonormal_right_handed(ev, tol=FRAME_TOL):
    t = ev.d1 / np.linalg.norm(ev.d1, axis=1)[:, None]
    frame = np.stack([t, ev.e2, ev.e3], axis=2)  # columns e1, e2, e3
    gram = np.einsum("mij,mik->mjk", frame, frame)
    np.testing.assert_allclose(gram, np.broadcast_to(np.eye(3), gram.shape), atol=tol)
    np.testing.assert_allclose(np.linalg.det(frame), 1.0, atol=tol)


def fd(curve, z, h=FD_STEP):
    """Central differences of point, tangent and e2 at stations z (kept inside [0, L])."""
    zp, zm = z + h, z - h
    ep, em = curve.evaluate(zp), curve.evaluate(zm)
    return ep, em, 2 * h


# Curves under test ------------------------------------------------------------------------------
ARC_CFG = ArcAxis(radius=150.0, angle_deg=90.0)
PATH_CFG = PathAxis((LineAxis(100.0), ArcAxis(150.0, 90.0), LineAxis(50.0)))
PATH3D_CFG = PathAxis((LineAxis(40.0), ArcAxis(100.0, 90.0, 0.0), LineAxis(30.0), ArcAxis(50.0, 90.0, 90.0),
                       ArcAxis(80.0, 60.0, -135.0), LineAxis(20.0)))
SPLINE_CFG = SplineAxis(((0.0, 0.0, 0.0), (5.0, 3.0, 40.0), (25.0, -4.0, 80.0), (40.0, 10.0, 110.0),
                         (45.0, 30.0, 140.0)))
WILD_SPLINE_CFG = SplineAxis(((0.0, 0.0, 0.0), (0.0, 10.0, 50.0), (20.0, 0.0, 100.0), (0.0, 0.0, 150.0)))

CURVES = {
    "line": LineAxis(120.0),
    "arc": ARC_CFG,
    "arc_toward30": ArcAxis(80.0, 135.0, 30.0),
    "arc_toward-120": ArcAxis(60.0, 200.0, -120.0),
    "path": PATH_CFG,
    "path3d": PATH3D_CFG,
    "spline": SPLINE_CFG,
}


def joints(cfg):
    if not isinstance(cfg, PathAxis):
        return np.array([])
    lens = [s.length if isinstance(s, LineAxis) else s.radius * np.radians(s.angle_deg) for s in cfg.segments]
    return np.cumsum(lens)[:-1]


def smooth_stations(cfg, curve, m=97):
    """Stations at least a few FD steps inside [0, L] and away from path joints."""
    z = stations(curve, m, margin=10 * FD_STEP)
    j = joints(cfg)
    if j.size:
        z = z[np.all(np.abs(z[:, None] - j[None, :]) > 10 * FD_STEP, axis=1)]
    return z


# -- SPEC start conventions -------------------------------------------------------------------------
@pytest.mark.parametrize("name", [n for n in CURVES if n != "spline"])
def test_start_conventions(name):
    curve = make_curve(CURVES[name], "t.yaml")
    ev = curve.evaluate(np.array([0.0]))
    np.testing.assert_allclose(ev.x[0], 0.0, atol=EXACT_TOL)
    np.testing.assert_allclose(ev.d1[0], Z, atol=EXACT_TOL)
    np.testing.assert_allclose(ev.e2[0], X, atol=EXACT_TOL)
    np.testing.assert_allclose(ev.e3[0], Y, atol=EXACT_TOL)


def test_spline_start_conventions():
    """x(0) = origin; e2(0) = +x made orthogonal to e1(0); e3 = e1 x e2 (SPEC mandrel.axis spline)."""
    curve = make_curve(SPLINE_CFG, "t.yaml")
    ev = curve.evaluate(np.array([0.0]))
    t0 = ev.d1[0] / np.linalg.norm(ev.d1[0])
    want = X - (X @ t0) * t0
    want /= np.linalg.norm(want)
    np.testing.assert_allclose(ev.x[0], 0.0, atol=EXACT_TOL)
    np.testing.assert_allclose(ev.e2[0], want, atol=SPLINE_FRAME_TOL)
    np.testing.assert_allclose(ev.e3[0], np.cross(t0, want), atol=SPLINE_FRAME_TOL)


def test_spline_start_tangent_along_x_takes_y_as_reference():
    curve = make_curve(SplineAxis(((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), (20.0, 0.0, 0.0), (30.0, 0.0, 0.0))), "t")
    ev = curve.evaluate(np.array([0.0, 15.0]))
    np.testing.assert_allclose(ev.d1, [X, X], atol=1e-9)
    np.testing.assert_allclose(ev.e2, [Y, Y], atol=1e-9)
    np.testing.assert_allclose(ev.e3, [Z, Z], atol=1e-9)


def test_line_is_the_z_axis():
    curve = make_curve(LineAxis(120.0), "t")
    z = stations(curve)
    ev = curve.evaluate(z)
    np.testing.assert_allclose(ev.x, np.c_[0 * z, 0 * z, z], atol=EXACT_TOL)
    assert curve.length == 120.0 and curve.is_straight and curve.max_curvature() == 0.0
    np.testing.assert_array_equal(ev.d2, 0.0)


@pytest.mark.parametrize("toward,centre_dir", [(0.0, X), (90.0, Y), (30.0, np.array([np.cos(np.pi / 6), 0.5, 0.0])),
                                                (180.0, -X), (-90.0, -Y)])
def test_arc_bends_toward_its_centre_of_curvature(toward, centre_dir):
    radius = 150.0
    curve = make_curve(ArcAxis(radius, 90.0, toward), "t")
    assert curve.length == pytest.approx(radius * np.pi / 2, rel=EXACT_TOL)
    centre = radius * centre_dir
    z = stations(curve)
    ev = curve.evaluate(z)
    # Every point at the bend radius from the centre, in the plane spanned by +z and centre_dir.
    np.testing.assert_allclose(np.linalg.norm(ev.x - centre, axis=1), radius, rtol=EXACT_TOL)
    normal = np.cross(Z, centre_dir)
    np.testing.assert_allclose(ev.x @ normal, 0.0, atol=EXACT_TOL * radius)
    # Curvature vector points at the centre, magnitude 1 / radius.
    np.testing.assert_allclose(ev.d2, (centre - ev.x) / radius**2, atol=EXACT_TOL)
    np.testing.assert_allclose(ev.d3, -ev.d1 / radius**2, atol=EXACT_TOL)
    # A quarter turn: ends at centre + radius * z, heading along centre_dir.
    end = curve.evaluate(np.array([curve.length]))
    np.testing.assert_allclose(end.x[0], centre + radius * Z, atol=1e-10 * radius)
    np.testing.assert_allclose(end.d1[0], centre_dir, atol=1e-12)
    assert curve.max_curvature() == pytest.approx(1.0 / radius)


def test_arc_end_frame_toward_zero():
    """Bending toward +x in the x-z plane: e2 turns from +x to -z, e3 stays +y (planar RMF)."""
    curve = make_curve(ArcAxis(150.0, 90.0, 0.0), "t")
    ev = curve.evaluate(stations(curve))
    np.testing.assert_allclose(ev.e3, np.broadcast_to(Y, ev.e3.shape), atol=EXACT_TOL)
    end = curve.evaluate(np.array([curve.length]))
    np.testing.assert_allclose(end.e2[0], -Z, atol=1e-12)


def test_arc_toward_90_keeps_e2():
    """Bending toward +y: e2 = +x is the binormal and never turns; e3 turns from +y to -z."""
    curve = make_curve(ArcAxis(150.0, 90.0, 90.0), "t")
    ev = curve.evaluate(stations(curve))
    np.testing.assert_allclose(ev.e2, np.broadcast_to(X, ev.e2.shape), atol=EXACT_TOL)
    end = curve.evaluate(np.array([curve.length]))
    np.testing.assert_allclose(end.e3[0], -Z, atol=1e-12)


# -- frames ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", list(CURVES))
def test_frames_orthonormal_and_right_handed(name):
    curve = make_curve(CURVES[name], "t")
    ev = curve.evaluate(stations(curve, 301))
    tol = SPLINE_FRAME_TOL if name == "spline" else FRAME_TOL
    assert_orthonormal_right_handed(ev, tol)
    if name != "spline":
        np.testing.assert_allclose(np.linalg.norm(ev.d1, axis=1), 1.0, atol=FRAME_TOL)


@pytest.mark.parametrize("name", list(CURVES))
def test_frame_is_rotation_minimizing(name):
    """RMF: e2' . e3 = 0 (no twist about e1), and e2' = -(T'. e2) T (docs/math/01-surface.md), by finite differences;
    also x' and T' = x'' against differences of x and x'."""
    cfg = CURVES[name]
    curve = make_curve(cfg, "t")
    z = smooth_stations(cfg, curve)
    ev = curve.evaluate(z)
    ep, em, dz = fd(curve, z)
    de2 = (ep.e2 - em.e2) / dz
    tol = RMF_TOL if name != "spline" else SPLINE_FRAME_TOL * 10
    np.testing.assert_allclose(np.einsum("ij,ij->i", de2, ev.e3), 0.0, atol=tol)
    want = -np.einsum("ij,ij->i", ev.d2, ev.e2)[:, None] * ev.d1
    np.testing.assert_allclose(de2, want, atol=tol)
    np.testing.assert_allclose((ep.x - em.x) / dz, ev.d1, atol=1e-8)
    np.testing.assert_allclose((ep.d1 - em.d1) / dz, ev.d2, atol=1e-8)
    # x''' of a spline is that of a cubic through the points, re-parametrized: it jumps at the data
    # points, and the quintic arc-length fit smooths the jump; compare loosely there.
    np.testing.assert_allclose((ep.d2 - em.d2) / dz, ev.d3, atol=1e-7 if name != "spline" else 1e-6)


def test_double_reflection_matches_exact_arc_frame():
    """Double reflection on a sampled arc (not in a coordinate plane) against the exact RMF."""
    arc = make_curve(ArcAxis(100.0, 120.0, 30.0), "t")
    z = np.linspace(0.0, arc.length, 4001)
    ev = arc.evaluate(z)
    e2 = double_reflection(ev.x, ev.d1, ev.e2[0])
    np.testing.assert_allclose(e2, ev.e2, atol=DR_TOL)
    # On a circle the two reflections are exact: even a coarse grid is right to round-off.
    zc = np.linspace(0.0, arc.length, 9)
    evc = arc.evaluate(zc)
    np.testing.assert_allclose(double_reflection(evc.x, evc.d1, evc.e2[0]), evc.e2, atol=DR_TOL)


def test_double_reflection_matches_helix_rmf():
    """Non-planar truth: on a helix of radius a, pitch 2 pi b (c = sqrt(a^2 + b^2), torsion tau = b / c^2),
    the RMF is the Frenet frame (N, B) turned by the angle -tau s about T."""
    a, b = 30.0, 8.0
    c = np.hypot(a, b)
    s = np.linspace(0.0, 4 * np.pi * c, 8001)
    u = s / c
    x = np.c_[a * np.cos(u), a * np.sin(u), b * u]
    t = np.c_[-a * np.sin(u), a * np.cos(u), b * np.ones_like(u)] / c
    nrm = np.c_[-np.cos(u), -np.sin(u), 0 * u]
    bin_ = np.cross(t, nrm)
    ang = -(b / c**2) * s
    rmf = np.cos(ang)[:, None] * nrm + np.sin(ang)[:, None] * bin_
    e2 = double_reflection(x, t, nrm[0])
    np.testing.assert_allclose(e2, rmf, atol=DR_TOL)
    # Coarse grids converge as O(h^4) (Wang et al. 2008): halving h divides the error by ~16.
    errs = []
    for m in (101, 201, 401):
        k = np.linspace(0, len(s) - 1, m).round().astype(int)
        errs.append(np.abs(double_reflection(x[k], t[k], nrm[0]) - rmf[k]).max())
    assert errs[0] / errs[1] > 12 and errs[1] / errs[2] > 12, errs


def test_path_geometry_line_arc_line():
    """Line 100, quarter bend of radius 150 toward +x, line 50: ends at (200, 0, 250) heading +x."""
    curve = make_curve(PATH_CFG, "t")
    assert curve.length == pytest.approx(150.0 + 75.0 * np.pi, rel=EXACT_TOL)
    ev = curve.evaluate(np.array([50.0, curve.length]))
    np.testing.assert_allclose(ev.x[0], [0, 0, 50], atol=EXACT_TOL)
    np.testing.assert_allclose(ev.x[1], [200, 0, 250], atol=1e-10)
    np.testing.assert_allclose(ev.d1[1], X, atol=1e-12)
    np.testing.assert_allclose(ev.e2[1], -Z, atol=1e-12)
    np.testing.assert_allclose(ev.e3[1], Y, atol=1e-12)
    np.testing.assert_array_equal(ev.d2[0], 0.0)


def test_path_arcs_in_two_planes():
    """Bend toward +x (radius 100), then, in the frame at that joint, toward e3 = +y (radius 50).
    After the first bend: point (100, 0, 100), T = +x, e2 = -z, e3 = +y. The second arc's centre is
    (100, 50, 100); it ends at (150, 50, 100) heading +y; e2 = -z is its binormal (unchanged) and
    e3 = T x e2 = -x."""
    cfg = PathAxis((ArcAxis(100.0, 90.0, 0.0), ArcAxis(50.0, 90.0, 90.0)))
    curve = make_curve(cfg, "t")
    j = 50 * np.pi
    ev = curve.evaluate(np.array([j, curve.length]))
    np.testing.assert_allclose(ev.x, [[100, 0, 100], [150, 50, 100]], atol=1e-10)
    np.testing.assert_allclose(ev.d1, [X, Y], atol=1e-12)
    np.testing.assert_allclose(ev.e2, [-Z, -Z], atol=1e-12)
    np.testing.assert_allclose(ev.e3, [Y, -X], atol=1e-12)
    mid = curve.evaluate(np.array([j + 25 * np.pi / 2]))  # 45 degrees into the second arc
    np.testing.assert_allclose(np.linalg.norm(mid.x[0] - [100, 50, 100]), 50.0, rtol=1e-12)


@pytest.mark.parametrize("name", ["path", "path3d"])
def test_path_frame_continuous_across_joints(name):
    cfg = CURVES[name]
    curve = make_curve(cfg, "t")
    for j in joints(cfg):
        eps = 1e-9 * max(1.0, j)
        ev = curve.evaluate(np.array([j - eps, j, j + eps]))
        for field in (ev.x, ev.d1, ev.e2, ev.e3):
            np.testing.assert_allclose(field[0], field[2], atol=JOINT_TOL * max(1.0, j))
            np.testing.assert_allclose(field[1], field[2], atol=JOINT_TOL * max(1.0, j))


# -- splines --------------------------------------------------------------------------------------
def nearest_station(curve, p):
    z = stations(curve, 2001)
    k = int(np.argmin(np.linalg.norm(curve.evaluate(z).x - p, axis=1)))
    lo, hi = z[max(k - 1, 0)], z[min(k + 1, len(z) - 1)]
    res = minimize_scalar(lambda s: float(np.sum((curve.evaluate(np.array([s])).x[0] - p) ** 2)),
                          bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
    # The bounded search never lands exactly on a bound: try the bounds (the curve's ends) too.
    cand = np.array([res.x, lo, hi])
    dist = np.linalg.norm(curve.evaluate(cand).x - p, axis=1)
    return cand[np.argmin(dist)], float(dist.min())


@pytest.mark.parametrize("cfg", [SPLINE_CFG, WILD_SPLINE_CFG], ids=["mild", "wild"])
def test_spline_interpolates_its_points(cfg):
    curve = make_curve(cfg, "t")
    for p in np.asarray(cfg.points, float):
        _, dist = nearest_station(curve, p)
        assert dist < SPLINE_INTERP_TOL
    np.testing.assert_allclose(curve.evaluate(np.array([curve.length])).x[0], cfg.points[-1], atol=SPLINE_INTERP_TOL)


@pytest.mark.parametrize("cfg", [SPLINE_CFG, WILD_SPLINE_CFG], ids=["mild", "wild"])
def test_spline_is_parametrized_by_arc_length(cfg):
    """t is arc length (SPEC): |x'| = 1, hence x' . x'' = 0 (the RMF formulas of docs/math/01-surface.md rely on it).
    Regression: a Newton polish of u(z) against a *linear* interpolant of ell(u) left | |x'| - 1 | ~ 2e-5
    and x' . x'' ~ 1.4e-3 near the ends of the 'wild' spline (fixed: Gauss-Legendre partial integrals)."""
    curve = make_curve(cfg, "t")
    ev = curve.evaluate(stations(curve, 4001))
    np.testing.assert_allclose(np.linalg.norm(ev.d1, axis=1), 1.0, atol=SPLINE_SPEED_TOL)
    np.testing.assert_allclose(np.einsum("ij,ij->i", ev.d1, ev.d2), 0.0, atol=SPLINE_SPEED_TOL * 10)


def arc_samples(radius, angle_deg, m):
    """Points of the arc of make_curve(ArcAxis(radius, angle_deg, 0)): in the x-z plane, centre (R, 0, 0)."""
    phi = np.linspace(0.0, np.radians(angle_deg), m)
    return np.c_[radius * (1 - np.cos(phi)), 0 * phi, radius * np.sin(phi)]


def test_spline_through_arc_samples_reproduces_the_arc():
    radius = 100.0
    pts = arc_samples(radius, 90.0, 17)
    curve = make_curve(SplineAxis(tuple(map(tuple, pts))), "t")
    exact = make_curve(ArcAxis(radius, 90.0, 0.0), "t")
    assert curve.length == pytest.approx(exact.length, abs=ARC_SPLINE_POS_TOL)
    z = stations(curve, 401)
    ev = curve.evaluate(z)
    np.testing.assert_allclose(np.linalg.norm(ev.x - [radius, 0, 0], axis=1), radius, atol=ARC_SPLINE_POS_TOL)
    np.testing.assert_allclose(ev.x[:, 1], 0.0, atol=EXACT_TOL)
    interior = (z > 0.1 * curve.length) & (z < 0.9 * curve.length)
    kappa = np.linalg.norm(ev.d2, axis=1)
    np.testing.assert_allclose(kappa[interior], 1.0 / radius, rtol=ARC_SPLINE_KAPPA_RTOL)
    # Same station, same point and frame as the exact arc (both by arc length from the origin).
    ex = exact.evaluate(np.minimum(z, exact.length))
    np.testing.assert_allclose(ev.x, ex.x, atol=10 * ARC_SPLINE_POS_TOL)
    np.testing.assert_allclose(ev.e2, ex.e2, atol=ARC_SPLINE_FRAME_TOL)
    np.testing.assert_allclose(ev.e3, ex.e3, atol=ARC_SPLINE_FRAME_TOL)
    assert_orthonormal_right_handed(ev, SPLINE_FRAME_TOL)


def test_spline_frame_matches_double_reflection_on_its_own_curve():
    """The stored (interpolated) frame equals a fresh, much finer double reflection along the spline."""
    curve = make_curve(SPLINE_CFG, "t")
    z = np.linspace(0.0, curve.length, 16001)
    ev = curve.evaluate(z)
    t = ev.d1 / np.linalg.norm(ev.d1, axis=1)[:, None]
    e2 = double_reflection(ev.x, t, ev.e2[0])
    np.testing.assert_allclose(ev.e2, e2, atol=SPLINE_FRAME_TOL)

"""The sweep surface (winder/surface.py): conventions, derivatives, normals, scaling, regularity.

Independent truths: docs/guide/conventions.md's straight-axis formula Phi = (r cos theta, r sin theta, t); the torus
equation for a circular tube on an arc; central finite differences of p for ps, pt and of ps, pt for
pss, pst, ptt; the section scaled by profile(t) / profile(0); the bend-radius rule for self-intersection.
"""

from __future__ import annotations

import functools
import itertools

import numpy as np
import pytest

from winder.config.axes import ArcAxis, PathAxis, SplineAxis
from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.config.profiles import ConeProfile, TableProfile
from winder.config.sections import EllipseSection, RoundedRectangleSection, SuperellipseSection
from winder.geometry.build import make_curve
from winder.errors import ConfigError
from winder.geometry.build import make_profile
from winder.geometry.build import make_section
from winder.geometry.outlines import RoundedRectangle
from winder.geometry.sections import Circle
from winder.geometry.build import build_surface
from winder.geometry.surface import SweepSurface
from roundoff import assert_roundoff

EXACT_TOL = 1e-10  # mm: closed-form positions (round-off on lengths ~ 100 mm)
H_S = 1e-4  # mm, finite-difference step along the axis
H_TH = 1e-5  # rad, finite-difference step around
DERIV_RTOL = 1e-7  # exact derivative formulas vs central differences, relative to the field's size
#                    (measured worst 1.5e-9 over lines, arcs and paths: FD truncation and round-off)
# Spline guides: x(z) is a quintic fit of the re-parametrized cubic and the frame is an interpolated
# double-reflection grid, so the closed-form frame derivatives (docs/math/01-surface.md, which assume |x'| = 1 and an
# exact RMF) are consistent with the evaluated points only to the fit accuracy (~1e-8 by design).
# Measured on SPLINE_POINTS: ps, pt to 2e-8; pss to 7e-7 (the third derivative of the quintic fit smooths the jump of
# the cubic's third derivative at the middle data point: d3 vs differences of d2 off by 1.6e-7 there).
SPLINE_DERIV_RTOL = 2e-6
NORMAL_TOL = 1e-12  # unit length and orthogonality of normals
JOINT_GAP = 1e-3  # rad (rounded rectangle) / mm (path joints): stay off the C1 joints by this much
N_SAMPLES = 40  # (s, theta) points per combination

# -- the matrix of mandrels -----------------------------------------------------------------------
SPLINE_POINTS = ((0.0, 0.0, 0.0), (5.0, 3.0, 40.0), (25.0, -4.0, 80.0), (40.0, 10.0, 110.0), (45.0, 30.0, 140.0))
AXES = {
    "line": LineAxis(200.0),
    "arc": ArcAxis(150.0, 90.0),
    "arc_toward30": ArcAxis(120.0, 120.0, 30.0),
    "path": PathAxis((LineAxis(60.0), ArcAxis(150.0, 90.0, 0.0), LineAxis(40.0))),
    "spline": SplineAxis(SPLINE_POINTS),
}
SECTIONS = {
    "circle": CircleSection(),
    "ellipse": EllipseSection(12.0, 8.0),
    "rounded_rectangle": RoundedRectangleSection(24.0, 16.0, 4.0),
    "superellipse4": SuperellipseSection(12.0, 8.0, 4.0),
}


def axis_len(cfg) -> float:
    if isinstance(cfg, LineAxis):
        return cfg.length
    if isinstance(cfg, ArcAxis):
        return cfg.radius * np.radians(cfg.angle_deg)
    if isinstance(cfg, PathAxis):
        return sum(axis_len(s) for s in cfg.segments)
    raise TypeError(cfg)


def profile(kind: str, length: float):
    if kind == "constant":
        return ConstantProfile(10.0)
    if kind == "cone":
        return ConeProfile(10.0, 14.0)
    if kind == "table":
        fr = (0.0, 0.3, 0.55, 0.8, 1.0)
        return TableProfile(tuple((f * length, r) for f, r in zip(fr, (10.0, 12.0, 11.0, 13.0, 12.5))))
    raise ValueError(kind)


def spline_length() -> float:
    return curve_of("spline").length


def mandrel(axis: str, section: str, prof: str) -> MandrelConfig:
    cfg = AXES[axis]
    length = spline_length() if axis == "spline" else axis_len(cfg)
    return MandrelConfig(cfg, profile(prof, length), SECTIONS[section])


@functools.lru_cache(maxsize=None)
def curve_of(axis: str):
    return make_curve(AXES[axis], "t.yaml")


@functools.lru_cache(maxsize=None)
def surface_of(axis: str, section: str, prof: str) -> SweepSurface:
    """The matrix's surfaces, assembled like build_surface does but sharing one guide curve per axis and
    skipping the regularity check (build_surface takes ~0.1 s each, mostly that check; the matrix has 60).
    test_matrix_assembly_matches_build_surface checks the assembly against build_surface itself."""
    cfg = mandrel(axis, section, prof)
    curve = curve_of(axis)
    prof_obj = make_profile(cfg.profile, curve.length, "t.yaml")
    sec = make_section(cfg.section)
    scale = 1.0 if isinstance(sec, Circle) else prof_obj.reference_radius
    return SweepSurface(curve, prof_obj, sec, scale, prof_obj.length, "")


@pytest.mark.parametrize("axis,section,prof", [("spline", "ellipse", "table"), ("path", "rounded_rectangle", "cone"),
                                               ("arc_toward30", "superellipse4", "constant")])
def test_matrix_assembly_matches_build_surface(axis, section, prof):
    built = build_surface(mandrel(axis, section, prof), "t.yaml")
    ours = surface_of(axis, section, prof)
    s = np.linspace(0.0, built.length, 17)
    th = np.linspace(-1.0, 7.0, 17)
    a, b = built.evaluate(s, th, 2), ours.evaluate(s, th, 2)
    for x, y in zip(a, b):
        assert_roundoff(x, y)


def path_joints(cfg) -> np.ndarray:
    if not isinstance(cfg, PathAxis):
        return np.array([])
    return np.cumsum([axis_len(s) for s in cfg.segments])[:-1]


def samples(surface, axis_cfg, section_cfg, table_knots=(), seed=0):
    """(s, theta) inside the surface, off path joints, table knots and rounded-rectangle joints."""
    rng = np.random.default_rng(seed)
    m = 4 * N_SAMPLES
    s = rng.uniform(0.02, 0.98, m) * surface.length
    th = rng.uniform(-np.pi, 3 * np.pi, m)
    keep = np.ones(m, bool)
    for j in list(path_joints(axis_cfg)) + list(table_knots):
        keep &= np.abs(s - j) > JOINT_GAP
    sec = make_section(section_cfg)
    if isinstance(sec, RoundedRectangle):
        hw, hh, rc = sec.width / 2, sec.height / 2, sec.corner_radius
        first = np.array([np.arctan2(hh - rc, hw), np.arctan2(hh, hw - rc)])
        joints = np.concatenate([first, np.pi - first, np.pi + first, 2 * np.pi - first])
        d = np.abs((th[:, None] - joints[None, :] + np.pi) % (2 * np.pi) - np.pi)
        keep &= np.all(d > JOINT_GAP, axis=1)
    s, th = s[keep][:N_SAMPLES], th[keep][:N_SAMPLES]
    # Exact axis-aligned directions too (theta = 0, pi/2: where sections have their extremes).
    return np.r_[s, s[:4]], np.r_[th, [0.0, np.pi / 2, np.pi, -np.pi / 2]]


def assert_close(fd, exact, rtol, what):
    scale = max(1.0, float(np.linalg.norm(exact, axis=1).max()))
    err = float(np.linalg.norm(fd - exact, axis=1).max())
    assert err <= rtol * scale, f"{what}: finite differences differ by {err:.3g} (scale {scale:.3g})"


MATRIX = list(itertools.product(AXES, SECTIONS, ("constant", "cone", "table")))


@pytest.mark.parametrize("axis,section,prof", MATRIX, ids=["-".join(c) for c in MATRIX])
def test_derivatives_match_finite_differences(axis, section, prof):
    cfg = mandrel(axis, section, prof)
    surf = surface_of(axis, section, prof)
    knots = [t for t, _ in cfg.profile.points] if prof == "table" else []
    s, th = samples(surf, cfg.axis, cfg.section, knots)
    ev = surf.evaluate(s, th, order=2)
    f = lambda ds, dt: surf.evaluate(s + ds, th + dt, order=1)  # noqa: E731
    sp, sm, tp, tm = f(H_S, 0.0), f(-H_S, 0.0), f(0.0, H_TH), f(0.0, -H_TH)
    rtol = SPLINE_DERIV_RTOL if axis == "spline" else DERIV_RTOL
    assert_close((sp.p - sm.p) / (2 * H_S), ev.ps, rtol, "ps")
    assert_close((tp.p - tm.p) / (2 * H_TH), ev.pt, rtol, "pt")
    assert_close((sp.ps - sm.ps) / (2 * H_S), ev.pss, rtol, "pss")
    assert_close((tp.ps - tm.ps) / (2 * H_TH), ev.pst, rtol, "pst from ps")
    assert_close((sp.pt - sm.pt) / (2 * H_S), ev.pst, rtol, "pst from pt")
    assert_close((tp.pt - tm.pt) / (2 * H_TH), ev.ptt, rtol, "ptt")
    # order 0 and 1 agree with order 2
    ev0 = surf.evaluate(s, th, order=0)
    assert_roundoff(ev0.p, ev.p)
    assert ev0.ps is None


@pytest.mark.parametrize("axis,section,prof", MATRIX, ids=["-".join(c) for c in MATRIX])
def test_normals_unit_orthogonal_outward(axis, section, prof):
    cfg = mandrel(axis, section, prof)
    surf = surface_of(axis, section, prof)
    s, th = samples(surf, cfg.axis, cfg.section, seed=1)
    nrm = surf.normals(s, th)
    ev = surf.evaluate(s, th, order=1)
    np.testing.assert_allclose(np.linalg.norm(nrm, axis=1), 1.0, atol=NORMAL_TOL)
    ps = ev.ps / np.linalg.norm(ev.ps, axis=1)[:, None]
    pt = ev.pt / np.linalg.norm(ev.pt, axis=1)[:, None]
    np.testing.assert_allclose(np.einsum("ij,ij->i", nrm, ps), 0.0, atol=NORMAL_TOL)
    np.testing.assert_allclose(np.einsum("ij,ij->i", nrm, pt), 0.0, atol=NORMAL_TOL)
    # Outward: away from the guide curve point of the same station.
    x = surf.curve.evaluate(surf.t_of_s(s)).x
    radial = ev.p - x
    cos = np.einsum("ij,ij->i", nrm, radial) / np.linalg.norm(radial, axis=1)
    assert np.all(cos > 0.5), cos.min()  # star-shaped convex sections: the normal is near-radial


# -- conventions ----------------------------------------------------------------------------------
@pytest.mark.parametrize("prof", ["constant", "cone", "table"])
def test_straight_axis_circle_is_phi_r_cos_r_sin_t(prof):
    cfg = MandrelConfig(LineAxis(200.0), profile(prof, 200.0), CircleSection())
    surf = build_surface(cfg, "t.yaml")
    t = np.linspace(0.0, 200.0, 21)
    th = np.linspace(-np.pi, 5 * np.pi, 21)
    p = surf.points(t, th)
    r = surf.radius(t, th)
    np.testing.assert_allclose(p, np.c_[r * np.cos(th), r * np.sin(th), t], atol=EXACT_TOL)
    if prof == "constant":
        np.testing.assert_allclose(r, 10.0, rtol=1e-14)
    if prof == "cone":
        np.testing.assert_allclose(r, 10.0 + 4.0 * t / 200.0, rtol=1e-13)
    if prof == "table":
        for tk, rk in cfg.profile.points:
            assert surf.radius(np.array([tk]), np.array([0.3]))[0] == pytest.approx(rk, rel=1e-12)
    # Surface of revolution: the outward normal is (cos, sin, -r'(t)) / sqrt(1 + r'^2).
    if prof == "constant":
        slope = np.zeros_like(t)
    elif prof == "cone":
        slope = np.full_like(t, 4.0 / 200.0)
    else:
        from scipy.interpolate import CubicSpline
        pts = np.asarray(cfg.profile.points)
        slope = CubicSpline(pts[:, 0], pts[:, 1])(t, 1)
    want = np.c_[np.cos(th), np.sin(th), -slope] / np.sqrt(1.0 + slope**2)[:, None]
    np.testing.assert_allclose(surf.normals(t, th), want, atol=1e-12)
    assert surf.is_revolution
    assert surf.axial_length == pytest.approx(200.0)


def test_theta_zero_is_plus_x_and_quarter_is_plus_y():
    surf = build_surface(MandrelConfig(LineAxis(100.0), ConstantProfile(10.0), EllipseSection(12.0, 8.0)), "t")
    p = surf.points(np.array([0.0, 0.0, 50.0]), np.array([0.0, np.pi / 2, np.pi]))
    np.testing.assert_allclose(p, [[12, 0, 0], [0, 8, 0], [-12, 0, 50]], atol=EXACT_TOL)


@pytest.mark.parametrize("toward", [0.0, 30.0, 90.0, 200.0])
def test_arc_inside_is_theta_equal_toward(toward):
    """theta = toward is nearest to the centre of curvature; its distance there is bend radius - r;
    theta = toward + 180 is farthest (bend radius + r)."""
    rb, r = 150.0, 40.0
    surf = build_surface(MandrelConfig(ArcAxis(rb, 90.0, toward), ConstantProfile(r), CircleSection()), "t")
    a = np.radians(toward)
    centre = rb * np.array([np.cos(a), np.sin(a), 0.0])
    th = np.linspace(0.0, 2 * np.pi, 7201)[:-1]
    for t in (0.0, 0.4 * surf.length, surf.length):
        d = np.linalg.norm(surf.points(np.full_like(th, t), th) - centre, axis=1)
        assert np.degrees(th[np.argmin(d)]) == pytest.approx(toward % 360, abs=0.05)
        assert d.min() == pytest.approx(rb - r, rel=1e-9)
        assert d.max() == pytest.approx(rb + r, rel=1e-9)


def test_arc_toward_zero_bends_toward_plus_x_and_is_a_torus():
    """Bend of radius Rb toward +x in the x-z plane: centre (Rb, 0, 0), torus axis along y:
    (sqrt((x - Rb)^2 + z^2) - Rb)^2 + y^2 = r^2 for every surface point."""
    rb, r = 150.0, 40.0
    surf = build_surface(MandrelConfig(ArcAxis(rb, 90.0), ConstantProfile(r), CircleSection()), "t")
    rng = np.random.default_rng(3)
    s = rng.uniform(0.0, surf.length, 200)
    th = rng.uniform(-np.pi, np.pi, 200)
    x, y, z = surf.points(s, th).T
    np.testing.assert_allclose((np.hypot(x - rb, z) - rb) ** 2 + y**2, r * r, rtol=1e-12)
    # The guide's end: (Rb, 0, Rb), and the surface around it lies in the plane x = Rb.
    end = surf.points(np.full(5, surf.length), np.linspace(0, 2 * np.pi, 5))
    np.testing.assert_allclose(end[:, 0], rb, atol=EXACT_TOL)


def test_arc_toward_ninety_bends_toward_plus_y():
    rb, r = 150.0, 40.0
    surf = build_surface(MandrelConfig(ArcAxis(rb, 90.0, 90.0), ConstantProfile(r), CircleSection()), "t")
    x, y, z = surf.points(np.full(9, surf.length), np.linspace(0, 2 * np.pi, 9)).T
    np.testing.assert_allclose(y, rb, atol=EXACT_TOL)
    np.testing.assert_allclose(np.hypot(x, z - rb), r, rtol=1e-12)


# -- sections with profiles -----------------------------------------------------------------------
@pytest.mark.parametrize("section", ["ellipse", "rounded_rectangle", "superellipse4"])
@pytest.mark.parametrize("prof", ["constant", "cone", "table"])
def test_section_is_scaled_by_profile_over_profile_at_zero(section, prof):
    """SPEC: with a profile, the section is scaled by profile(t) / profile(0)."""
    length = 200.0
    cfg = MandrelConfig(LineAxis(length), profile(prof, length), SECTIONS[section])
    surf = build_surface(cfg, "t.yaml")
    sec = make_section(SECTIONS[section])
    t = np.linspace(0.0, length, 11)
    th = np.linspace(0.1, 6.0, 11)
    # Reference profile values, independently of winder's profile code where possible.
    if prof == "constant":
        ratio = np.ones_like(t)
    elif prof == "cone":
        ratio = (10.0 + 4.0 * t / length) / 10.0
    else:
        from scipy.interpolate import CubicSpline
        pts = np.asarray(cfg.profile.points)
        ratio = CubicSpline(pts[:, 0], pts[:, 1])(t) / pts[0, 1]
    rho = sec.polar(th)[0]
    want = ratio * rho
    np.testing.assert_allclose(surf.radius(t, th), want, rtol=1e-12)
    np.testing.assert_allclose(surf.points(t, th), np.c_[want * np.cos(th), want * np.sin(th), t], atol=EXACT_TOL)
    # At t = 0 the section has its absolute size: the ellipse's semi-axes, the rectangle's half sides.
    p0 = surf.points(np.zeros(2), np.array([0.0, np.pi / 2]))
    half = {"ellipse": (12.0, 8.0), "rounded_rectangle": (12.0, 8.0), "superellipse4": (12.0, 8.0)}[section]
    np.testing.assert_allclose(p0[:, :2], [[half[0], 0.0], [0.0, half[1]]], atol=EXACT_TOL)
    assert surf.perimeter(length) == pytest.approx(ratio[-1] * sec.perimeter(), rel=1e-12)


@pytest.mark.parametrize("section", ["ellipse", "rounded_rectangle", "superellipse4"])
def test_section_is_absolute_without_profile(section):
    surf = build_surface(MandrelConfig(LineAxis(50.0), None, SECTIONS[section]), "t.yaml")
    sec = make_section(SECTIONS[section])
    th = np.linspace(-3.0, 9.0, 25)
    np.testing.assert_allclose(surf.radius(np.full_like(th, 20.0), th), sec.polar(th)[0], rtol=1e-14)
    assert not surf.is_revolution


def test_non_circular_section_on_arc_keeps_its_semi_axes_in_the_frame():
    """The ellipse's a axis stays along e2 along the bend (the RMF does not twist)."""
    surf = build_surface(MandrelConfig(ArcAxis(150.0, 90.0, 0.0), ConstantProfile(10.0), EllipseSection(12.0, 8.0)),
                         "t")
    cv = surf.curve.evaluate(np.array([surf.length]))
    p = surf.points(np.full(2, surf.length), np.array([0.0, np.pi / 2]))
    # At the end e2 = -z, e3 = +y (SPEC frame carried by the RMF through a bend toward +x).
    np.testing.assert_allclose(p[0], cv.x[0] + 12.0 * np.array([0, 0, -1.0]), atol=EXACT_TOL)
    np.testing.assert_allclose(p[1], cv.x[0] + 8.0 * np.array([0, 1.0, 0]), atol=EXACT_TOL)


# -- self-intersection ----------------------------------------------------------------------------
FOLD = "folds onto itself|bend radius"  # an arc names its key; a spline says where it folds

def test_bend_tighter_than_section_is_refused_with_bend_radius():
    with pytest.raises(ConfigError, match=FOLD) as exc:
        build_surface(MandrelConfig(ArcAxis(radius=30.0, angle_deg=90.0), ConstantProfile(40.0), CircleSection()),
                      "elbow.yaml")
    assert "30" in str(exc.value) and "elbow.yaml" in str(exc.value)


def test_bend_radius_just_below_section_radius_is_refused():
    with pytest.raises(ConfigError, match=FOLD):
        build_surface(MandrelConfig(ArcAxis(39.0, 90.0), ConstantProfile(40.0), CircleSection()), "t.yaml")


def test_bend_radius_just_above_section_radius_is_accepted():
    surf = build_surface(MandrelConfig(ArcAxis(41.0, 90.0), ConstantProfile(40.0), CircleSection()), "t.yaml")
    assert surf.length == pytest.approx(41.0 * np.pi / 2)


@pytest.mark.parametrize("toward", [30.0, 91.3, -60.0])
def test_bend_check_any_toward(toward):
    """The inside of the bend is theta = toward, whatever toward is (not only multiples of the check's
    sampling step)."""
    with pytest.raises(ConfigError, match=FOLD):
        build_surface(MandrelConfig(ArcAxis(39.0, 90.0, toward), ConstantProfile(40.0), CircleSection()), "t")
    build_surface(MandrelConfig(ArcAxis(41.0, 90.0, toward), ConstantProfile(40.0), CircleSection()), "t")


def test_bend_check_exact_in_theta():
    """BUG (surface._check_regular): theta is sampled every 2.5 deg, so a bend toward 1.25 deg with bend
    radius 39.995 < 40 is accepted (the sampled reach is 40/39.995 cos(1.25 deg) = 0.99988 < 1)."""
    with pytest.raises(ConfigError, match=FOLD):
        build_surface(MandrelConfig(ArcAxis(39.995, 90.0, 1.25), ConstantProfile(40.0), CircleSection()), "t")


def test_cone_growing_into_the_bend_is_refused():
    cfg = MandrelConfig(ArcAxis(40.0, 90.0), ConeProfile(20.0, 45.0), CircleSection())
    with pytest.raises(ConfigError, match=FOLD):
        build_surface(cfg, "t.yaml")
    build_surface(MandrelConfig(ArcAxis(40.0, 90.0), ConeProfile(20.0, 38.0), CircleSection()), "t.yaml")


def test_ellipse_refusal_depends_on_bend_direction():
    """a = 50 along e2, b = 20 along e3, bend radius 45: refused bending toward e2, fine toward e3."""
    sec = EllipseSection(50.0, 20.0)
    with pytest.raises(ConfigError, match=FOLD):
        build_surface(MandrelConfig(ArcAxis(45.0, 90.0, 0.0), None, sec), "t.yaml")
    build_surface(MandrelConfig(ArcAxis(45.0, 90.0, 90.0), None, sec), "t.yaml")


def test_short_tight_arc_inside_long_path_is_refused():
    """BUG (surface._check_regular): 801 stations over 2 m are 2.5 mm apart, and a 0.52 mm arc
    (radius 30, 1 deg) between them is never looked at: a 40 mm tube through it is accepted.
    """
    cfg = MandrelConfig(PathAxis((LineAxis(1001.2), ArcAxis(30.0, 1.0), LineAxis(1000.0))), ConstantProfile(40.0),
                        CircleSection())
    with pytest.raises(ConfigError, match=FOLD):
        build_surface(cfg, "t.yaml")


def test_straight_path_needs_no_bend_check():
    build_surface(MandrelConfig(PathAxis((LineAxis(10.0), LineAxis(20.0))), ConstantProfile(500.0), CircleSection()),
                  "t")


# -- the evaluation's special cases against the general one ---------------------------------------
FAST_PATH_REL = 1e-14  # the closed forms of a one-arc curve vs the general path gather, relative to the field: roundoff


@pytest.mark.parametrize("toward", [0.0, 30.0, 200.0])
@pytest.mark.parametrize("section", ["circle", "ellipse"])
def test_one_arc_closed_form_matches_the_general_path(toward, section):
    """A one-arc axis evaluates in closed form (half angle, no per-point frame); the same arc as two
    half arcs goes through the general multi-piece path evaluation."""
    one = make_curve(ArcAxis(150.0, 90.0, toward), "t.yaml")
    two = make_curve(PathAxis((ArcAxis(150.0, 45.0, toward), ArcAxis(150.0, 45.0, toward))), "t.yaml")
    sec = make_section(SECTIONS[section])
    scale = 1.0 if isinstance(sec, Circle) else 12.0
    prof = make_profile(ConstantProfile(10.0), one.length, "t.yaml")
    fast = SweepSurface(one, prof, sec, scale, one.length, "")
    general = SweepSurface(two, prof, sec, scale, two.length, "")
    assert fast._arc_frame is not None and general._arc_frame is None
    rng = np.random.default_rng(3)
    s, th = rng.uniform(0.0, one.length, 200), rng.uniform(-np.pi, 3 * np.pi, 200)
    for order in (0, 1, 2):
        a, b = fast.evaluate(s, th, order), general.evaluate(s, th, order)
        for x, y in zip(a, b):
            assert (x is None) == (y is None)
            if x is not None:
                scale_xy = max(1.0, float(np.abs(y).max()))
                assert float(np.abs(x - y).max()) <= FAST_PATH_REL * scale_xy


@pytest.mark.parametrize("axis", ["line", "arc", "path"])
@pytest.mark.parametrize("section", ["circle", "ellipse", "superellipse4"])
def test_evaluate_without_the_point_keeps_the_derivatives_bit_for_bit(axis, section):
    surf = surface_of(axis, section, "cone")
    s = np.linspace(0.0, surf.length, 33)
    th = np.linspace(-1.0, 7.0, 33)
    for order in (1, 2):
        full, bare = surf.evaluate(s, th, order), surf.evaluate(s, th, order, with_point=False)
        assert bare.p is None
        for x, y in zip(full[1:], bare[1:]):
            assert_roundoff(x, y)
    assert_roundoff(surf.evaluate(s, th, 0, with_point=False).p, surf.points(s, th))


def test_row_cross_product_is_numpys():
    from winder.geometry.measure import cross  # noqa: PLC0415

    rng = np.random.default_rng(5)
    storage = rng.standard_normal((2, 3, 257))
    a, b = storage[0].T, storage[1].T  # (m, 3) views of (3, m) storage, like an evaluation's fields
    assert_roundoff(cross(a, b), np.cross(a, b))
    assert_roundoff(cross(a[:-1], b[1:]), np.cross(a[:-1], b[1:]))


@pytest.mark.parametrize("axis,section,prof", MATRIX, ids=["-".join(c) for c in MATRIX])
def test_vanishing_terms_left_out_change_no_value(axis, section, prof, monkeypatch):
    # evaluate skips terms with an exact 0.0 coefficient and factors of 1.0: against every term
    # computed, the same values (only an exact zero's sign may differ)
    import winder.geometry.surface as surface_module  # noqa: PLC0415

    cfg = mandrel(axis, section, prof)
    surf = surface_of(axis, section, prof)
    s, th = samples(surf, cfg.axis, cfg.section, [])
    for m in (1, s.size):
        fast = [surf.evaluate(s[:m], th[:m], order=k) for k in (0, 1, 2)]
        with monkeypatch.context() as patch:
            patch.setattr(surface_module, "_zero", lambda v: False)
            patch.setattr(surface_module, "_times", lambda a, b: a * b)
            full = [surf.evaluate(s[:m], th[:m], order=k) for k in (0, 1, 2)]
        for a, b in zip(fast, full):
            for x, y in zip(a, b):
                assert (x is None) == (y is None)
                if x is not None:
                    assert_roundoff(x, y)


@pytest.mark.parametrize("axis, profile, section", [
    (LineAxis(300.0), ConstantProfile(40.0), CircleSection()),
    (LineAxis(100.0), ConstantProfile(10.0), EllipseSection(12.0, 8.0)),
    (LineAxis(100.0), ConstantProfile(10.0), RoundedRectangleSection(24.0, 16.0, 4.0)),
    (LineAxis(100.0), None, SuperellipseSection(12.0, 8.0, 4.0)),
    (LineAxis(100.0), ConeProfile(10.0, 14.0), CircleSection()),  # the meshgrid itself
    (ArcAxis(150.0, 90.0), ConstantProfile(40.0), CircleSection()),
])
def test_grid_points_are_points_on_the_meshgrid_bit_for_bit(axis, profile, section) -> None:
    surf = build_surface(MandrelConfig(axis, profile, section), "t")
    s = np.linspace(0.0, surf.length, 37)
    th = np.concatenate([np.linspace(0.0, 2.0 * np.pi, 64, endpoint=False), [-1.0, 7.5, np.pi]])
    ss, tt = np.meshgrid(s, th, indexing="ij")
    assert_roundoff(surf.grid_points(s, th), surf.points(ss.ravel(), tt.ravel()))


@pytest.mark.parametrize("prof", ["constant", "cone", "table"])
def test_turned_rows_are_the_surface_read_at_the_turned_angle(prof):
    """SweepSurface.turned against the surface evaluated at theta + dtheta itself: points about the
    axis line, directions (Phi_s, Phi_theta) about its tangent."""
    surface = surface_of("line", "circle", prof)
    rng = np.random.default_rng(5)
    s = rng.uniform(0.0, surface.length, 200)
    theta, turn = rng.uniform(-7.0, 7.0, 200), rng.uniform(-40.0, 40.0, 200)
    ev, want = surface.evaluate(s, theta, order=1), surface.evaluate(s, theta + turn, order=1)
    assert_roundoff(surface.turned(ev.p, turn), want.p, err_msg="turned points")
    for got, exact in ((ev.ps, want.ps), (ev.pt, want.pt)):
        assert_roundoff(surface.turned(got, turn, point=False), exact, err_msg="turned directions")

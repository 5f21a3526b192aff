"""Vessel domes and the vessel meridian (winder/domes.py) against independent truths.

Truths used: the sphere r^2 + h^2 = R^2 and its closed-form arc length R arccos(r0 / R); the ellipse
(r / R)^2 + (h / d)^2 = 1 and its arc length by the incomplete elliptic integral of the second kind
(scipy.special.ellipeinc); for the isotensoid the netting condition R2 / R1 = 2 - tan^2(alpha) with R1
from the curvature of the returned meridian, its integral sin(phi) = (r/R)^3 sqrt((R^2-c^2)/(r^2-c^2)),
the axial end r_* as a root (brentq) of Y^2 (1 + Y^2) = Y0^2 (1 + Y^2 + Y^4), and the depth and arc
length by adaptive quadrature (scipy quad, algebraic end weights) of dh/dY and dsigma/dY; five-point
finite differences for every derivative.
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import ellipeinc

from winder.config.vessel import Dome, DomeType, VesselProfile
from winder.geometry.build import make_dome, make_vessel
from winder.geometry.domes import (DomeMeridian, ELLIPSOID_MIN_DEPTH, ISOTENSOID_MAX_OPENING,
                                   ISOTENSOID_MIN_OPENING)
from winder.geometry.vessel import VesselMeridian
from winder.errors import ConfigError
from winder.geometry.build import make_profile

R = 100.0  # vessel radius used throughout, mm
EPS = np.finfo(float).eps

EXACT_TOL = 1e-12  # closed forms that hold to round-off, relative to R
UNIT_SPEED_TOL = 1e-9  # |h1^2 + r1^2 - 1| (measured <= 1e-11)
ELLIPSE_TOL = 1e-13  # residual of (r/R)^2 + (h/d)^2 - 1 (points are exact functions of the angle)
ARC_RTOL = 1e-12  # arc length and depth vs ellipeinc / quad (measured ~1e-14)
NETTING_TOL = 3e-7  # curvature vs netting theory, relative to |k| + 1/R (measured 7e-8 at c = 0.02 R,
#                     ~2e-9 from c = 0.1 R on: the quintic spline's curvature)
SIN_PHI_TOL = 1e-10  # h1 vs the integrated netting condition f(r) (measured ~1e-12)
END_RTOL = 1e-12  # isotensoid end radius vs brentq
FD_TOL = 1e-7  # five-point differences, relative to the derivative's scale, plus a round-off term
S_OF_T_TOL = 1e-12  # s_of_t / t_of_s round trips, relative to the vessel length

ISO_OPENINGS = (ISOTENSOID_MIN_OPENING, 0.1, 0.3, 0.5, ISOTENSOID_MAX_OPENING)  # c / R


def hemi(r0: float) -> Dome:
    return Dome(DomeType.HEMISPHERE, r0)


def ellip(r0: float, d: float) -> Dome:
    return Dome(DomeType.ELLIPSOID, r0, d)


def iso(r0: float) -> Dome:
    return Dome(DomeType.ISOTENSOID, r0)


def build(dome: Dome) -> DomeMeridian:
    return make_dome(dome, R, "test.yaml", "mandrel.profile.dome")


DOMES = {
    "hemisphere": hemi(20.0),
    "hemisphere_small_opening": hemi(2.0),
    "ellipsoid_2to1": ellip(25.0, 50.0),
    "ellipsoid_flat": ellip(10.0, ELLIPSOID_MIN_DEPTH * R),
    "ellipsoid_prolate": ellip(15.0, 300.0),
    **{f"isotensoid_{y:g}": iso(y * R) for y in ISO_OPENINGS},
}


@pytest.fixture(scope="module")
def domes() -> dict[str, DomeMeridian]:
    return {name: build(d) for name, d in DOMES.items()}


def curvature(e) -> np.ndarray:
    """Meridian curvature, positive where the dome is convex (turning toward the axis)."""
    return e.r1 * e.h2 - e.h1 * e.r2


def samples(dm: DomeMeridian, n: int = 2001) -> np.ndarray:
    """Arc lengths over the whole dome, refined geometrically toward both ends."""
    g = dm.length * np.logspace(-12, -0.5, 200)
    return np.unique(np.clip(np.concatenate([np.linspace(0.0, dm.length, n), g, dm.length - g]),
                             0.0, dm.length))


# ---------------------------------------------------------------------------------------------- all domes

@pytest.mark.parametrize("name", DOMES)
def test_unit_speed_and_monotone(domes, name):
    dm = domes[name]
    e = dm.evaluate(samples(dm))
    assert np.max(np.abs(e.h1**2 + e.r1**2 - 1.0)) < UNIT_SPEED_TOL
    assert np.all(e.h1 > 0.0)  # h strictly increasing: the inversion t -> s is well posed
    assert np.all(e.r1 <= EXACT_TOL)  # r never increases toward the pole
    assert np.all(e.r >= dm.end_radius - EXACT_TOL * R)


@pytest.mark.parametrize("name", DOMES)
def test_equator_and_end(domes, name):
    dm = domes[name]
    e0 = dm.evaluate(np.array([0.0]))
    # tangent-continuous junction with the cylinder: r = R, meridian parallel to the axis
    np.testing.assert_allclose([e0.h[0], e0.r[0], e0.h1[0], e0.r1[0]], [0.0, R, 1.0, 0.0],
                               atol=EXACT_TOL * R)
    e1 = dm.evaluate(np.array([dm.length]))
    assert abs(e1.h[0] - dm.depth) < EXACT_TOL * R
    assert abs(e1.r[0] - dm.end_radius) < EXACT_TOL * R
    eu = dm.evaluate_from_opening(np.array([0.0]))
    np.testing.assert_allclose([eu.h[0], eu.r[0]], [dm.depth, dm.end_radius], rtol=0, atol=EXACT_TOL * R)


def five_point(fun, x, step):
    return (-fun(x + 2 * step) + 8 * fun(x + step) - 8 * fun(x - step) + fun(x - 2 * step)) / (12 * step)


@pytest.mark.parametrize("name", DOMES)
def test_derivatives_match_finite_differences(domes, name):
    """h1, h2, r1, r2 are the derivatives of the h, r returned (the geodesic Newton relies on it).

    Checked in sigma on the equator half, and in u = length - sigma on the opening half, differencing
    the drop g = depth - h (drop_and_evaluate_from_opening) so that points microns from the opening
    (the isotensoid's end hook) are tested at full precision. The step is 1e-3 of the local scale
    (5-point error ~1e-13); the tolerance has a round-off term eps |value| / step.
    """
    dm = domes[name]
    half = 0.5 * dm.length

    def from_equator(x):
        e = dm.evaluate(x)
        return {"h": e.h, "dh": e.h1, "d2h": e.h2, "r": e.r, "dr": e.r1, "d2r": e.r2}

    def from_opening(x):  # derivatives in u: dg/du = h1, d2g/du2 = -h2, dr/du = -r1, d2r/du2 = r2
        g, e = dm.drop_and_evaluate_from_opening(x)
        return {"h": g, "dh": e.h1, "d2h": -e.h2, "r": e.r, "dr": -e.r1, "d2r": e.r2}

    for fun in (from_equator, from_opening):
        x = np.unique(np.concatenate([np.linspace(0.0, half, 301)[1:], half * np.logspace(-9, 0, 120)]))
        e = fun(x)
        rho = 1.0 / (np.abs(e["dr"] * e["d2h"] - e["dh"] * e["d2r"]) + 1.0 / R)
        # local scale: the radius of curvature, and the distance x to the end (the isotensoid's
        # curvature varies on that scale next to its end hook)
        step = 1e-3 * np.minimum(rho, x)
        for q in ("h", "r"):
            fd1 = five_point(lambda y, k=q: fun(y)[k], x, step)
            fd2 = five_point(lambda y, k="d" + q: fun(y)[k], x, step)
            big = np.abs(fun(x + 2 * step)[q]) + np.abs(fun(x - 2 * step)[q])
            tol1 = FD_TOL + 20.0 * EPS * big / step
            tol2 = FD_TOL * (np.abs(e["d2" + q]) + 1.0 / R) + 20.0 * EPS / step
            assert np.all(np.abs(fd1 - e["d" + q]) <= tol1), (q, fun.__name__)
            assert np.all(np.abs(fd2 - e["d2" + q]) <= tol2), (q, fun.__name__)


@pytest.mark.parametrize("name", DOMES)
def test_sigma_of_h_inverts(domes, name):
    dm = domes[name]
    s = samples(dm)
    e = dm.evaluate(s)
    # error of sigma = round-off of h / slope
    assert np.all(np.abs(dm.sigma_of_h(e.h) - s) <= S_OF_T_TOL * dm.length / e.h1)
    u = np.concatenate([[0.0], dm.length * np.logspace(-14, 0, 300)])
    g, eu = dm.drop_and_evaluate_from_opening(u)
    assert np.all(g >= 0.0) and np.all(np.diff(g) > 0.0)
    np.testing.assert_allclose(g, dm.depth - eu.h, rtol=0, atol=EXACT_TOL * R)
    # from the opening the inversion keeps relative precision: u ~ g near the (axial or not) end
    assert np.all(np.abs(dm.u_of_drop(g) - u) <= S_OF_T_TOL * u / eu.h1 + 4 * EPS * dm.length)


# ------------------------------------------------------------------------------------------- hemisphere

@pytest.mark.parametrize("r0", [1.0, 20.0, 60.0, 99.0])
def test_hemisphere_closed_form(r0):
    dm = build(hemi(r0))
    assert abs(dm.length - R * (np.pi / 2 - np.arcsin(r0 / R))) < EXACT_TOL * R
    assert abs(dm.depth - np.sqrt(R * R - r0 * r0)) < EXACT_TOL * R
    assert dm.end_radius == r0
    e = dm.evaluate(samples(dm))
    assert np.max(np.abs(np.hypot(e.r, e.h) - R)) < EXACT_TOL * R
    assert np.max(np.abs(curvature(e) - 1.0 / R)) < EXACT_TOL / R


# -------------------------------------------------------------------------------------------- ellipsoid

def ellipse_arc_length(a_r: float, d: float, tau: float) -> float:
    """Arc of r = a_r cos(t), h = d sin(t) for t in [0, tau], by ellipeinc with 0 <= m < 1."""
    if d >= a_r:
        return d * ellipeinc(tau, 1.0 - (a_r / d) ** 2)
    m = 1.0 - (d / a_r) ** 2
    return a_r * (ellipeinc(np.pi / 2, m) - ellipeinc(np.pi / 2 - tau, m))


@pytest.mark.parametrize(("r0", "d"), [(25.0, 50.0), (10.0, 5.0), (40.0, 20.0), (15.0, 300.0),
                                       (1.0, 1500.0), (90.0, 120.0)])
def test_ellipsoid_on_ellipse_and_arc_length(r0, d):
    dm = build(ellip(r0, d))
    e = dm.evaluate(samples(dm))
    assert np.max(np.abs((e.r / R) ** 2 + (e.h / d) ** 2 - 1.0)) < ELLIPSE_TOL
    tau_end = np.arccos(r0 / R)
    assert abs(dm.length - ellipse_arc_length(R, d, tau_end)) < ARC_RTOL * dm.length
    # config depth is the full semi-axis; the dome's depth stops at the opening plane
    assert abs(dm.depth - d * np.sqrt(1.0 - (r0 / R) ** 2)) < EXACT_TOL * d
    assert dm.end_radius == r0
    # arc length at intermediate points (the parametrization really is by arc length)
    s = np.linspace(0.0, dm.length, 23)
    tau = np.arctan2(dm.evaluate(s).h / d, dm.evaluate(s).r / R)
    truth = np.array([ellipse_arc_length(R, d, t) for t in tau])
    assert np.max(np.abs(truth - s)) < ARC_RTOL * dm.length


def test_ellipsoid_with_depth_r_is_the_hemisphere():
    el, he = build(ellip(20.0, R)), build(hemi(20.0))
    assert abs(el.length - he.length) < EXACT_TOL * R
    s = np.linspace(0.0, he.length, 501)
    for a, b in zip(el.evaluate(s), he.evaluate(s), strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-11 * R)


# ------------------------------------------------------------------------------------------- isotensoid

def isotensoid_truth(y0: float) -> tuple[float, float, float]:
    """(Y_*, depth / R, length / R) of the geodesic isotensoid, independently of winder.

    g(Y) = Y^2 (1 + Y^2) - Y0^2 (1 + Y^2 + Y^4) = (1 - Y0^2) (Y^2 - Y_*^2) (Y^2 - u_m), u_m = -1 - Y_*^2;
    dh/dY = Y^3 sqrt(1 - Y0^2) / sqrt((1 - Y^2) g(Y)) and dsigma/dY = sqrt(Y^2 - Y0^2) / sqrt((1 - Y^2) g)
    have 1/sqrt singularities at both ends, taken by quad's algebraic weight.
    """
    a = 1.0 - y0 * y0
    g = lambda y: a * y**4 + a * y**2 - y0 * y0  # noqa: E731
    ys = brentq(g, y0, 1.0, xtol=1e-300, rtol=4 * EPS, maxiter=500)
    um = -1.0 - ys * ys

    def smooth(y):  # (1 - Y^2) g(Y) / ((Y - Y_*) (1 - Y)) / (1 - Y0^2)
        return (1.0 + y) * (y + ys) * (y * y - um)

    opts = dict(weight="alg", wvar=(-0.5, -0.5), epsabs=0.0, epsrel=1e-13, limit=200)
    depth = quad(lambda y: y**3 / np.sqrt(smooth(y)), ys, 1.0, **opts)[0]
    length = quad(lambda y: np.sqrt((y * y - y0 * y0) / (a * smooth(y))), ys, 1.0, **opts)[0]
    return ys, depth, length


@pytest.mark.parametrize("y0", ISO_OPENINGS)
def test_isotensoid_end_depth_and_length(domes, y0):
    dm = domes[f"isotensoid_{y0:g}"]
    ys, depth, length = isotensoid_truth(y0)
    assert abs(dm.end_radius - ys * R) < END_RTOL * R
    assert dm.end_radius > dm.polar_opening  # r_* > c: the dome ends just outside the opening
    assert abs(dm.depth - depth * R) < ARC_RTOL * R
    assert abs(dm.length - length * R) < ARC_RTOL * R
    # the end is axial again: parallel to the axis, r at its minimum
    e = dm.evaluate(np.array([dm.length]))
    assert abs(e.h1[0] - 1.0) < EXACT_TOL and abs(e.r1[0]) < EXACT_TOL


@pytest.mark.parametrize("y0", ISO_OPENINGS)
def test_isotensoid_netting_condition(domes, y0):
    dm = domes[f"isotensoid_{y0:g}"]
    c = dm.polar_opening
    e = dm.evaluate(samples(dm, 4001))
    r = e.r
    # sin(phi) = h1 (phi: normal vs axis); R2 = r / sin(phi); R1 = 1 / curvature
    k = curvature(e)
    w = (r - c) * (r + c)  # r^2 - c^2; tan^2(alpha) = c^2 / (r^2 - c^2) with sin(alpha) = c / r
    # R2 / R1 = (r / h1) k = 2 - tan^2(alpha), times h1 w / r, as a curvature error relative to the
    # curvature scale |k| + 1/R (h1 can be ~1e-3 where the meridian is nearly radial: dividing by
    # it would only amplify the spline's absolute curvature error)
    resid = (k * w - e.h1 * (2.0 * r * r - 3.0 * c * c) / r) / ((np.abs(k) + 1.0 / R) * w)
    assert np.max(np.abs(resid)) < NETTING_TOL
    # the integrated condition: sin(phi) = (r/R)^3 sqrt((R^2 - c^2) / (r^2 - c^2))
    keep = w > 1e-6 * c * c  # (sqrt(w) has relative round-off eps c^2 / w)
    f = (r[keep] / R) ** 3 * np.sqrt((R - c) * (R + c) / w[keep])
    assert np.max(np.abs(e.h1[keep] - f)) < SIN_PHI_TOL
    # a convex dome near the equator, an inflection at r = c sqrt(3/2), concave toward the opening
    assert np.all(k[r > c * np.sqrt(1.5) * (1 + 1e-6)] > 0.0)
    assert np.all(k[r < c * np.sqrt(1.5) * (1 - 1e-6)] < 0.0)


# ---------------------------------------------------------------------------------------------- vessel

VESSELS = {
    "hemispheres": VesselProfile(R, 300.0, hemi(20.0), hemi(20.0)),
    "iso_and_ellipsoid": VesselProfile(R, 250.0, iso(30.0), ellip(15.0, 60.0)),
    "ellipsoid_and_iso_no_cylinder": VesselProfile(R, 0.0, ellip(40.0, 150.0), iso(10.0)),
}


@pytest.fixture(scope="module")
def vessels() -> dict[str, VesselMeridian]:
    return {name: make_vessel(cfg, "test.yaml") for name, cfg in VESSELS.items()}


@pytest.mark.parametrize("name", VESSELS)
def test_vessel_layout(vessels, name):
    v, cfg = vessels[name], VESSELS[name]
    d1, d2 = v.dome, v.end_dome
    assert v.radius == R
    assert v.reference_radius == d1.end_radius
    assert abs(v.axial_length - (d1.depth + cfg.cylinder_length + d2.depth)) < EXACT_TOL * R
    assert abs(v.length - (d1.length + cfg.cylinder_length + d2.length)) < EXACT_TOL * R
    assert v.equator_s == (d1.length, d1.length + cfg.cylinder_length)
    assert v.dome_ranges.dome == (0.0, d1.length)
    assert v.dome_ranges.cylinder == v.equator_s
    assert v.dome_ranges.end_dome == (v.equator_s[1], v.length)
    e = v.evaluate(np.array([0.0, v.length]))
    np.testing.assert_allclose(e.z, [0.0, v.axial_length], rtol=0, atol=EXACT_TOL * R)
    np.testing.assert_allclose(e.r, [d1.end_radius, d2.end_radius], rtol=0, atol=EXACT_TOL * R)


@pytest.mark.parametrize("name", VESSELS)
def test_vessel_meridian(vessels, name):
    v = vessels[name]
    s = np.linspace(0.0, v.length, 5001)
    e = v.evaluate(s)
    assert np.max(np.abs(e.z1**2 + e.r1**2 - 1.0)) < UNIT_SPEED_TOL
    assert np.all(e.z1 > 0.0) and np.all(np.diff(e.z) > 0.0)
    assert np.all(e.r > 0.0) and np.all(e.r <= R + EXACT_TOL * R)
    # pieces: the cylinder, and each dome as its own meridian (the first one reversed)
    a, b = v.equator_s
    cyl = (s >= a) & (s <= b)
    np.testing.assert_allclose(e.r[cyl], R, rtol=0, atol=EXACT_TOL * R)
    first = s < a
    ed = v.dome.evaluate(a - s[first])
    np.testing.assert_allclose(e.z[first], v.dome.depth - ed.h, rtol=0, atol=1e-11 * R)
    np.testing.assert_allclose(e.r[first], ed.r, rtol=0, atol=1e-11 * R)
    np.testing.assert_allclose(e.r1[first], -ed.r1, rtol=0, atol=1e-9)
    # C1 across both junctions: values and slopes agree from both sides
    for sj in (a, b):
        lo, hi = v.evaluate(np.array([sj - 1e-9 * R])), v.evaluate(np.array([sj + 1e-9 * R]))
        for k in ("z", "r"):
            assert abs(getattr(lo, k)[0] - getattr(hi, k)[0]) < 1e-8 * R
        for k in ("z1", "r1"):
            assert abs(getattr(lo, k)[0] - getattr(hi, k)[0]) < 1e-8
    # derivatives in s by five-point differences away from the junctions
    x = s[(np.abs(s - a) > 1.0) & (np.abs(s - b) > 1.0) & (s > 1.0) & (s < v.length - 1.0)]
    for val, der, der2 in (("z", "z1", "z2"), ("r", "r1", "r2")):
        ex = v.evaluate(x)
        rho = 1.0 / (np.abs(ex.r1 * ex.z2 - ex.z1 * ex.r2) + 1.0 / R)
        step = 1e-3 * np.minimum(rho, np.minimum(x, v.length - x))
        fd1 = five_point(lambda y, k=val: getattr(v.evaluate(y), k), x, step)
        fd2 = five_point(lambda y, k=der: getattr(v.evaluate(y), k), x, step)
        assert np.all(np.abs(fd1 - getattr(ex, der)) <= FD_TOL + 20 * EPS * v.axial_length / step)
        assert np.all(np.abs(fd2 - getattr(ex, der2)) <= FD_TOL / rho + 20 * EPS / step)


@pytest.mark.parametrize("name", VESSELS)
def test_vessel_s_of_t_round_trip(vessels, name):
    v = vessels[name]
    s = np.concatenate([np.linspace(0.0, v.length, 3001), list(v.equator_s),
                        v.length * np.logspace(-12, -1, 50), v.length * (1 - np.logspace(-12, -1, 50))])
    t = v.t_of_s(s)
    assert np.all(t >= 0.0) and np.all(t <= v.axial_length)
    z1 = v.evaluate(s).z1
    assert np.all(np.abs(v.s_of_t(t) - s) <= S_OF_T_TOL * v.length / np.minimum(z1, 1.0))
    tt = np.concatenate([np.linspace(0.0, v.axial_length, 3001), v.equator_t])
    assert np.max(np.abs(v.t_of_s(v.s_of_t(tt)) - tt)) <= S_OF_T_TOL * v.axial_length
    # shapes are preserved, scalars work, t outside [0, T] is clipped
    assert v.s_of_t(np.zeros((2, 3))).shape == (2, 3)
    assert v.evaluate(np.zeros((2, 3))).r.shape == (2, 3)
    assert float(v.s_of_t(0.0)) == 0.0
    assert abs(float(v.s_of_t(v.axial_length + 5.0)) - v.length) < S_OF_T_TOL * v.length


def test_make_profile_builds_the_vessel():
    cfg = VESSELS["iso_and_ellipsoid"]
    p = make_profile(cfg, None, "test.yaml")
    assert isinstance(p, VesselMeridian)
    assert p.reference_radius == p.evaluate(np.array([0.0])).r[0]


def test_build_is_fast():
    # the build's own CPU time: not scipy's import, nor the other processes of a busy machine
    make_vessel(next(iter(VESSELS.values())), "test.yaml")
    t0 = time.process_time()
    for cfg in VESSELS.values():
        make_vessel(cfg, "test.yaml")
    assert time.process_time() - t0 < 1.0


# ------------------------------------------------------------------------------------------- refusals

@pytest.mark.parametrize(("cfg", "key", "words"), [
    # Only what the geometry knows; signs, ranges and required keys are the config reader's (tests/config).
    (VesselProfile(R, 100.0, iso(80.0), hemi(20.0)), "mandrel.profile.dome.polar_opening",
     "sqrt(2/3)"),
    (VesselProfile(R, 100.0, hemi(20.0), iso(1.0)), "mandrel.profile.end_dome.polar_opening",
     "isotensoid"),
    (VesselProfile(R, 100.0, ellip(20.0, 2.0), hemi(20.0)), "mandrel.profile.dome.depth",
     "between"),
])
def test_refusals(cfg, key, words):
    with pytest.raises(ConfigError) as err:
        make_vessel(cfg, "vessel.yaml")
    msg = str(err.value)
    assert msg.startswith(f"vessel.yaml: {key}: "), msg
    assert words in msg, msg


def test_isotensoid_limits_are_inside_netting_theory():
    assert ISOTENSOID_MAX_OPENING < np.sqrt(2.0 / 3.0)
    build(iso(ISOTENSOID_MAX_OPENING * R))  # the limits themselves are accepted
    build(iso(ISOTENSOID_MIN_OPENING * R))



def test_one_table_of_values_and_derivatives_reads_as_the_pieces_do():
    """with_derivatives: each piece and its two derivatives, read in one call, against scipy's own
    derivative of each piece read alone (inside the knots and past both ends)."""
    from winder.geometry.domes import _quintic_hermite, with_derivatives  # noqa: PLC0415

    x = np.linspace(0.0, 3.0, 13)
    pieces = [_quintic_hermite(x, np.sin(x), np.cos(x), -np.sin(x)),
              _quintic_hermite(x, np.exp(-x), -np.exp(-x), np.exp(-x))]
    table = with_derivatives(pieces)
    q = np.linspace(-0.5, 3.5, 101)
    want = np.column_stack([p.derivative(j)(q) if j else p(q) for p in pieces for j in (0, 1, 2)])
    np.testing.assert_allclose(table(q), want, rtol=0.0, atol=1e-13 * np.abs(want).max())

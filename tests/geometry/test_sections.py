"""Cross-section shapes (winder/sections.py) against independent truths.

Truths used: central finite differences for rho' and rho''; the complete elliptic integral of the
second kind (scipy.special.ellipe) for the ellipse perimeter; adaptive quadrature of the arc-length
element |d/dtheta (rho (cos, sin))| = sqrt(rho^2 + rho'^2) for the rounded rectangle; the implicit
equation of each outline; the ellipse as the superellipse with p = 2.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import ellipe

from winder.config.mandrel import CircleSection
from winder.config.sections import EllipseSection, RoundedRectangleSection, SuperellipseSection
from winder.geometry.build import make_section
from winder.geometry.outlines import Ellipse, RoundedRectangle, Superellipse
from winder.geometry.sections import Circle
from roundoff import assert_roundoff

FD_STEP = 1e-5  # rad; central differences, truncation ~ h^2 rho''' / 6
FD_RTOL = 1e-7  # relative to the section's size: FD error (h^2 ~ 1e-10) plus round-off (eps/h ~ 1e-11)
EXACT_RTOL = 1e-12  # closed forms and identities that should hold to round-off
PERIMETER_RTOL = 1e-9  # perimeter(): spectral midpoint rule or closed form, vs quad / ellipe
IMPLICIT_TOL = 1e-12  # residual of the implicit outline equation at section points
JOINT_GAP = 1e-3  # rad kept away from the rounded rectangle's C1 side/corner joints (rho'' jumps)

# Theta samples in all four quadrants, unwrapped beyond [0, 2 pi) and negative (SPEC: theta unwrapped).
THETA = np.concatenate([np.linspace(-2.0 * np.pi, 4.0 * np.pi, 181) + 0.0123, [0.0, np.pi / 2, np.pi]])

SECTIONS = {
    "circle": Circle(7.5),
    "ellipse_wide": Ellipse(30.0, 20.0),
    "ellipse_tall": Ellipse(12.0, 25.0),
    "superellipse_p4": Superellipse(30.0, 20.0, 4.0),
    "superellipse_p3": Superellipse(15.0, 22.0, 3.0),
    "superellipse_p2.5": Superellipse(20.0, 20.0, 2.5),
    "rounded_rectangle": RoundedRectangle(60.0, 40.0, 8.0),
    "rounded_rectangle_tall": RoundedRectangle(30.0, 50.0, 12.0),
    "stadium": RoundedRectangle(60.0, 40.0, 20.0),  # corner radius = height / 2: vertical sides of length 0
}


def rr_joint_angles(rr: RoundedRectangle) -> np.ndarray:
    """Polar angles (rad, in [0, 2 pi)) where a straight side meets a corner arc."""
    hw, hh, rc = rr.width / 2, rr.height / 2, rr.corner_radius
    a1 = np.arctan2(hh - rc, hw)  # vertical side x = hw meets the corner at (hw, hh - rc)
    a2 = np.arctan2(hh, hw - rc)  # horizontal side y = hh meets the corner at (hw - rc, hh)
    first = np.array([a1, a2])
    return np.concatenate([first, np.pi - first, np.pi + first, 2 * np.pi - first]) % (2 * np.pi)


def away_from_joints(section, theta: np.ndarray, gap: float = JOINT_GAP) -> np.ndarray:
    """Theta where central differences of rho' converge as O(h^2): away from the rounded rectangle's
    joints, and for a superellipse with p not an even integer away from the semi-axes (there
    |sin|^(p-2) makes rho''' jump (p = 3) or blow up (2 < p < 3); rho'' itself is continuous)."""
    if isinstance(section, Superellipse) and section.p % 2 != 0:
        return theta[np.abs(np.sin(2 * theta)) > gap]
    if not isinstance(section, RoundedRectangle):
        return theta
    joints = rr_joint_angles(section)
    d = np.abs((theta[:, None] - joints[None, :] + np.pi) % (2 * np.pi) - np.pi)
    return theta[np.all(d > gap, axis=1)]


def size(section) -> float:
    rho, _, _ = section.polar(np.linspace(0, 2 * np.pi, 64))
    return float(rho.max())


# -- derivatives --------------------------------------------------------------------------------
@pytest.mark.parametrize("name", list(SECTIONS))
def test_polar_derivatives_match_finite_differences(name):
    sec = SECTIONS[name]
    th = away_from_joints(sec, THETA)
    h = FD_STEP
    rho, d1, d2 = sec.polar(th)
    rp, d1p, _ = sec.polar(th + h)
    rm, d1m, _ = sec.polar(th - h)
    scale = size(sec)
    np.testing.assert_allclose(d1, (rp - rm) / (2 * h), rtol=0, atol=FD_RTOL * scale)
    np.testing.assert_allclose(d2, (d1p - d1m) / (2 * h), rtol=0, atol=FD_RTOL * scale)
    # rho'' also against the second difference of rho itself (independent of rho').
    np.testing.assert_allclose(d2, (rp - 2 * rho + rm) / h**2, rtol=0, atol=1e-4 * scale)


@pytest.mark.parametrize("name", list(SECTIONS))
def test_polar_is_positive_finite_and_periodic(name):
    sec = SECTIONS[name]
    rho, d1, d2 = sec.polar(THETA)
    assert np.all(np.isfinite(rho)) and np.all(np.isfinite(d1)) and np.all(np.isfinite(d2))
    assert np.all(rho > 0)
    for shift in (2 * np.pi, -4 * np.pi):
        r2, e1, e2 = sec.polar(THETA + shift)
        scale = size(sec)
        np.testing.assert_allclose(r2, rho, rtol=0, atol=1e-9 * scale)
        np.testing.assert_allclose(e1, d1, rtol=0, atol=1e-9 * scale)


def test_rounded_rectangle_rho_second_derivative_jumps_only_at_joints():
    """rho is C1 at the side/corner joints (rho' continuous) but rho'' jumps there (curvature jump)."""
    rr = SECTIONS["rounded_rectangle"]
    eps = 1e-9
    for a in rr_joint_angles(rr):
        rho, d1, d2 = rr.polar(np.array([a - eps, a + eps]))
        assert abs(rho[1] - rho[0]) < 1e-6
        assert abs(d1[1] - d1[0]) < 1e-6
        assert abs(d2[1] - d2[0]) > 1.0  # side: curvature 0, corner: 1 / rc


# -- perimeters ---------------------------------------------------------------------------------
def ellipse_perimeter(a: float, b: float) -> float:
    big, small = max(a, b), min(a, b)
    return 4.0 * big * float(ellipe(1.0 - (small / big) ** 2))


@pytest.mark.parametrize("a,b", [(30.0, 20.0), (12.0, 25.0), (10.0, 10.0), (50.0, 5.0)])
def test_ellipse_perimeter_matches_complete_elliptic_integral(a, b):
    assert Ellipse(a, b).perimeter() == pytest.approx(ellipse_perimeter(a, b), rel=PERIMETER_RTOL)


def test_circle_radius_and_perimeter():
    c = Circle(7.5)
    rho, d1, d2 = c.polar(THETA)
    assert np.all(rho == 7.5) and np.all(d1 == 0) and np.all(d2 == 0)
    assert c.perimeter() == pytest.approx(2 * np.pi * 7.5, rel=EXACT_RTOL)


@pytest.mark.parametrize("w,h,rc", [(60.0, 40.0, 8.0), (30.0, 50.0, 12.0), (60.0, 40.0, 20.0),
                                    (20.0, 20.0, 10.0), (40.0, 40.0, 1.0)])
def test_rounded_rectangle_perimeter_closed_form_vs_quadrature(w, h, rc):
    rr = RoundedRectangle(w, h, rc)

    def element(t):
        rho, d1, _ = rr.polar(np.array([t]))
        return float(np.hypot(rho[0], d1[0]))

    # Integrate piecewise between the joints (the integrand is smooth on each piece).
    brk = np.unique(np.concatenate([[0.0, 2 * np.pi], rr_joint_angles(rr), np.arange(4) * np.pi / 2]))
    total = sum(quad(element, lo, hi, epsabs=1e-12, epsrel=1e-13, limit=200)[0]
                for lo, hi in zip(brk[:-1], brk[1:]) if hi > lo)
    assert rr.perimeter() == pytest.approx(total, rel=PERIMETER_RTOL)
    # And the closed form itself from the geometry: straight sides plus one full circle.
    assert rr.perimeter() == pytest.approx(2 * (w - 2 * rc) + 2 * (h - 2 * rc) + 2 * np.pi * rc,
                                           rel=EXACT_RTOL)


def test_rounded_rectangle_with_full_corners_is_a_circle():
    rr = RoundedRectangle(20.0, 20.0, 10.0)
    rho, d1, d2 = rr.polar(THETA)
    np.testing.assert_allclose(rho, 10.0, rtol=EXACT_RTOL)
    np.testing.assert_allclose(d1, 0.0, atol=1e-10)
    # BUG (sections.py): at theta = 0 and pi/2 the zero-length sides win the tie (phi <= side_x),
    # so rho'' = hw / cos^3 = 10 instead of the circle's 0.
    np.testing.assert_allclose(d2, 0.0, atol=1e-9)


def test_stadium_second_derivative_on_its_axis():
    """corner_radius = height / 2: the vertical sides have length 0, so around theta = 0 the outline
    is the corner circle on both sides, and rho'' there is the circle's, not a side's (hw / cos^3).
    Circle centred (cx, 0) = (hw - rc, 0), radius rc: rho = cx cos + sqrt(rc^2 - cx^2 sin^2),
    so rho''(0) = -cx - cx^2 / rc (both one-sided limits)."""
    rr = SECTIONS["stadium"]
    hw, rc = rr.width / 2, rr.corner_radius
    cx = hw - rc
    th = np.array([0.0, np.pi, 2 * np.pi, -np.pi])
    rho, d1, d2 = rr.polar(th)
    np.testing.assert_allclose(rho, hw, rtol=EXACT_RTOL)
    # The one-sided limits, from the formula just off the axis:
    near = rr.polar(np.array([1e-7, -1e-7]))[2]
    np.testing.assert_allclose(near, -cx - cx * cx / rc, rtol=1e-6)
    # BUG (sections.py): at theta = 0 exactly the zero-length side wins the tie: rho'' = hw.
    np.testing.assert_allclose(d2, -cx - cx * cx / rc, rtol=1e-9)


@pytest.mark.parametrize("name", ["superellipse_p4", "superellipse_p3", "superellipse_p2.5"])
def test_superellipse_perimeter_vs_quadrature(name):
    sec = SECTIONS[name]

    def element(t):
        rho, d1, _ = sec.polar(np.array([t]))
        return float(np.hypot(rho[0], d1[0]))

    total = 4 * quad(element, 0.0, np.pi / 2, epsabs=1e-12, epsrel=1e-13, limit=200)[0]
    assert sec.perimeter() == pytest.approx(total, rel=1e-8)


# -- superellipse p = 2 is the ellipse ----------------------------------------------------------
@pytest.mark.parametrize("a,b", [(30.0, 20.0), (12.0, 25.0)])
def test_superellipse_with_exponent_two_is_the_ellipse(a, b):
    se, el = Superellipse(a, b, 2.0), Ellipse(a, b)
    for x, y in zip(se.polar(THETA), el.polar(THETA)):
        np.testing.assert_allclose(x, y, rtol=0, atol=1e-11 * max(a, b))
    assert se.perimeter() == pytest.approx(el.perimeter(), rel=EXACT_RTOL * 100)


# -- the points lie on their outlines -----------------------------------------------------------
def xy(section, theta):
    rho = section.polar(theta)[0]
    return rho * np.cos(theta), rho * np.sin(theta)


@pytest.mark.parametrize("a,b", [(30.0, 20.0), (12.0, 25.0)])
def test_ellipse_points_satisfy_implicit_equation(a, b):
    x, y = xy(Ellipse(a, b), THETA)
    np.testing.assert_allclose((x / a) ** 2 + (y / b) ** 2, 1.0, rtol=0, atol=IMPLICIT_TOL)


@pytest.mark.parametrize("name", ["superellipse_p4", "superellipse_p3", "superellipse_p2.5"])
def test_superellipse_points_satisfy_implicit_equation(name):
    sec = SECTIONS[name]
    x, y = xy(sec, THETA)
    np.testing.assert_allclose(np.abs(x / sec.a) ** sec.p + np.abs(y / sec.b) ** sec.p, 1.0,
                               rtol=0, atol=IMPLICIT_TOL)


@pytest.mark.parametrize("name", ["rounded_rectangle", "rounded_rectangle_tall", "stadium"])
def test_rounded_rectangle_points_lie_on_a_side_or_a_corner_circle(name):
    rr = SECTIONS[name]
    hw, hh, rc = rr.width / 2, rr.height / 2, rr.corner_radius
    th = np.concatenate([THETA, rr_joint_angles(rr)])
    x, y = xy(rr, th)
    ax, ay = np.abs(x), np.abs(y)
    tol = IMPLICIT_TOL * max(hw, hh) * 10
    on_vertical = (np.abs(ax - hw) < tol) & (ay <= hh - rc + tol)
    on_horizontal = (np.abs(ay - hh) < tol) & (ax <= hw - rc + tol)
    on_corner = (np.abs(np.hypot(ax - (hw - rc), ay - (hh - rc)) - rc) < tol) & (ax >= hw - rc - tol) \
        & (ay >= hh - rc - tol)
    assert np.all(on_vertical | on_horizontal | on_corner)
    # Every piece is actually visited.
    assert on_vertical.any() and on_corner.any()


def test_rounded_rectangle_extremes_are_half_width_and_half_height():
    rr = SECTIONS["rounded_rectangle"]
    rho = rr.polar(np.array([0.0, np.pi / 2, np.pi, 3 * np.pi / 2]))[0]
    np.testing.assert_allclose(rho, [30.0, 20.0, 30.0, 20.0], rtol=EXACT_RTOL)


def test_make_section_maps_configs():
    assert isinstance(make_section(CircleSection()), Circle)
    assert make_section(EllipseSection(3.0, 2.0)) == Ellipse(3.0, 2.0)
    assert make_section(RoundedRectangleSection(6.0, 4.0, 1.0)) == RoundedRectangle(6.0, 4.0, 1.0)
    assert make_section(SuperellipseSection(3.0, 2.0, 4.0)) == Superellipse(3.0, 2.0, 4.0)


def _rounded_rectangle_reference(rr: RoundedRectangle, theta: np.ndarray) -> tuple[np.ndarray, ...]:
    """rho, rho', rho'' one point at a time: the side x = w/2, the corner circle or the side y = h/2."""
    hw, hh, rc = rr.width / 2.0, rr.height / 2.0, rr.corner_radius
    cx, cy = hw - rc, hh - rc
    out = []
    for th in theta:
        c, s = math.cos(th), math.sin(th)
        ac, as_ = abs(c), abs(s)
        phi = math.atan2(as_, ac)
        if phi < math.atan2(cy, hw):
            rho, d1, d2 = hw / ac, hw * as_ / ac**2, hw * (1.0 + as_**2) / ac**3
        elif phi > math.atan2(hh, cx):
            rho, d1, d2 = hh / as_, -hh * ac / as_**2, hh * (1.0 + ac**2) / as_**3
        else:
            aa, bb = cx * ac + cy * as_, -cx * as_ + cy * ac
            q = math.sqrt(rc * rc - bb * bb)
            rho, d1, d2 = aa + q, bb + aa * bb / q, -aa + (bb * bb - aa * aa) / q - aa * aa * bb * bb / q**3
        out.append((rho, math.copysign(1.0, c * s) * d1 if c * s != 0.0 else 0.0, d2))
    return tuple(np.array(v) for v in zip(*out))


@pytest.mark.parametrize("name", [k for k in SECTIONS if k.startswith("rounded") or k == "stadium"])
def test_rounded_rectangle_pieces_are_each_points_own(name):
    """Each point takes its own piece's formula (the pieces are gathered once in polar_cs)."""
    rr = SECTIONS[name]
    for got, want in zip(rr.polar(THETA), _rounded_rectangle_reference(rr, THETA)):
        np.testing.assert_allclose(got, want, rtol=EXACT_RTOL, atol=EXACT_RTOL * rr.width)
    # At the joints rho and rho' are continuous (rho'' jumps): either piece's value there will do.
    joints = rr_joint_angles(rr)
    for got, want in zip(rr.polar(joints)[:2], _rounded_rectangle_reference(rr, joints)[:2]):
        np.testing.assert_allclose(got, want, rtol=EXACT_RTOL, atol=EXACT_RTOL * rr.width)


@pytest.mark.parametrize("name", list(SECTIONS))
def test_polar_from_cos_sin_is_the_polar_radius_bit_for_bit(name):
    """The surface hands a section its angle's cosine and sine and asks only the derivatives it needs:
    the same numbers as polar(theta), to round-off, at every order (a NaN angle stays NaN)."""
    section = SECTIONS[name]
    th = np.concatenate([np.linspace(-7.0, 7.0, 101), [np.nan]])
    full = section.polar(th)
    for order in (0, 1, 2):
        part = section.polar_cs(np.cos(th), np.sin(th), order)
        for k in range(3):
            if k <= order:
                assert_roundoff(part[k], full[k])
            else:
                assert part[k] is None


ARC_MM = 1e-7  # the arc map's fraction against the closed-form arc length, mm (linear tables: 1.4e-4)
RATE_RTOL = 1e-9  # its d theta / d f against the closed form (a linear table: 1.5e-3 at a joint)
ROUND_TRIP_RAD = 1e-10  # theta(fraction(theta)): one Newton step after the linear table (3e-12 seen)


def test_rounded_rectangle_arc_map_against_its_closed_form_arc_length():
    """Arc length from theta = 0 on the first quadrant of a wide section with a small corner: the
    right face hw tan(theta), the corner rc times its turn, the top face from where it starts; the
    rate rho^2 / (p . n), n the outward normal. Every joint is a node of the table."""
    from winder.geometry.sections import arc_map  # noqa: PLC0415

    rr = RoundedRectangle(200.0, 100.0, 10.0)
    hw, hh, rc = 100.0, 50.0, 10.0
    cx, cy = hw - rc, hh - rc
    np.testing.assert_allclose(np.sort(rr.joints()), np.sort(rr_joint_angles(rr)), rtol=0, atol=EXACT_RTOL)
    arcs = arc_map(rr)
    assert np.all(np.min(np.abs(arcs.theta_grid[:, None] - rr.joints()[None, :]), axis=0) <= EXACT_RTOL)
    th = np.linspace(0.0, 0.5 * np.pi, 200_001)[1:-1]
    c, s = np.cos(th), np.sin(th)
    side, top = th < np.arctan2(cy, hw), th > np.arctan2(hh, cx)
    aa, bb = cx * c + cy * s, -cx * s + cy * c
    rho = np.where(side, hw / c, np.where(top, hh / s, aa + np.sqrt(np.maximum(rc * rc - bb * bb, 0.0))))
    p = rho[:, None] * np.column_stack([c, s])
    turn = np.arctan2(p[:, 1] - cy, p[:, 0] - cx)
    normal = np.where(side[:, None], [1.0, 0.0], np.where(top[:, None], [0.0, 1.0],
                                                          np.column_stack([np.cos(turn), np.sin(turn)])))
    sigma = np.where(side, p[:, 1], np.where(top, cy + 0.5 * np.pi * rc + cx - p[:, 0], cy + rc * turn))
    length = rr.perimeter()
    np.testing.assert_allclose(arcs.fraction(th) * length, sigma, rtol=0, atol=ARC_MM)
    rate = rho * rho / np.einsum("ij,ij->i", p, normal)
    np.testing.assert_allclose(arcs.dtheta_dfrac(th) * rate / length, 1.0, rtol=0, atol=RATE_RTOL)
    np.testing.assert_allclose(arcs.theta(arcs.fraction(th)), th, rtol=0, atol=ROUND_TRIP_RAD)

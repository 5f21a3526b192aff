"""Domes from drawings (winder.geometry.domes_torispherical, domes_contour; docs/math/17) against
independent truths: the torispherical head's closed forms (the meridian's radius of curvature r_k on the
knuckle and R_c on the crown, the head's height R_c - sqrt((R_c - r_k)^2 - (R - r_k)^2) to the pole, the
sphere through the crown), the ellipse a contour was sampled from, five-point finite differences of every
derivative, and DXF drawings written by ezdxf itself."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.config.job import load_config
from winder.errors import ConfigError
from winder.geometry.build import make_vessel
from winder.geometry.domes import Ellipsoid
from winder.geometry.domes_contour import ContourDome, ContourError
from winder.geometry.domes_torispherical import Torispherical

R = 150.0
CURVATURE_RTOL = 1e-12  # closed-form arcs: exact to round-off
EXACT_TOL = 1e-9  # mm, positions of closed forms
FD_TOL = 1e-6  # finite differences (step 1e-3 mm, five points) of the exact derivatives
SAMPLED_TOL = 1e-8  # mm: a contour of 200 exact ellipse points vs the ellipse
NOISE = 0.003  # mm: digitizing scatter added to a contour
DXF_TOL = 2e-3  # mm: a contour drawn as arcs and sampled vs the closed form


def _curvature(ev) -> np.ndarray:
    return ev.h1 * ev.r2 - ev.r1 * ev.h2


@pytest.mark.parametrize("crown, knuckle", [(300.0, 30.0), (150.0, 45.0), (270.0, 16.2), (500.0, 60.0)])
def test_torispherical_closed_form(crown: float, knuckle: float) -> None:
    """Radius of curvature r_k on the knuckle and R_c on the crown; the crown on the sphere about its
    centre on the axis; the full head's height."""
    r0 = 1e-6
    dome = Torispherical(R, crown, knuckle, r0)
    cos_j = (R - knuckle) / (crown - knuckle)
    sigma_j = knuckle * math.acos(cos_j)
    knuckle_s = np.linspace(0.0, sigma_j, 50)[1:-1]
    crown_s = np.linspace(sigma_j, dome.length, 50)[1:-1]
    ek, ec = dome.evaluate(knuckle_s), dome.evaluate(crown_s)
    np.testing.assert_allclose(-1.0 / _curvature(ek), knuckle, rtol=CURVATURE_RTOL)
    np.testing.assert_allclose(-1.0 / _curvature(ec), crown, rtol=CURVATURE_RTOL)
    centre = -math.sqrt((crown - knuckle) ** 2 - (R - knuckle) ** 2)
    np.testing.assert_allclose(np.hypot(ec.h - centre, ec.r), crown, atol=EXACT_TOL)
    np.testing.assert_allclose(np.hypot(ek.h, ek.r - (R - knuckle)), knuckle, atol=EXACT_TOL)
    height = crown - math.sqrt((crown - knuckle) ** 2 - (R - knuckle) ** 2)
    assert dome.depth == pytest.approx(height, abs=EXACT_TOL)
    np.testing.assert_allclose(ek.h1**2 + ek.r1**2, 1.0, atol=1e-14)


def test_torispherical_derivatives_and_depth_near_the_opening() -> None:
    dome = Torispherical(R, 280.0, 40.0, 22.0)
    s = np.linspace(0.01, dome.length - 0.01, 41)
    step = 1e-3
    f = [dome.evaluate(s + k * step) for k in (-2, -1, 1, 2)]
    e = dome.evaluate(s)
    for val, der in (("h", "h1"), ("r", "r1"), ("h1", "h2"), ("r1", "r2")):
        fd = (getattr(f[0], val) - 8 * getattr(f[1], val) + 8 * getattr(f[2], val) - getattr(f[3], val)) / (12 * step)
        np.testing.assert_allclose(fd, getattr(e, der), atol=FD_TOL)
    assert dome.evaluate(np.array([dome.length])).r[0] == pytest.approx(22.0, abs=EXACT_TOL)
    u = np.array([0.0, 1e-7, 1e-3, 5.0])
    g, ev = dome.drop_and_evaluate_from_opening(u)
    np.testing.assert_allclose(g, dome.depth - ev.h, atol=1e-12)
    assert g[1] > 0.0 and g[0] == 0.0


def _ellipse_points(d: float, r0: float, n: int) -> np.ndarray:
    tau = np.linspace(0.0, math.acos(r0 / R), n)
    return np.column_stack([d * np.sin(tau), R * np.cos(tau)])


@pytest.mark.parametrize("d", [60.0, 90.0, 150.0, 240.0])
def test_contour_of_ellipse_points_is_the_ellipse(d: float) -> None:
    ell = Ellipsoid(R, 22.0, d)
    dome = ContourDome(R, _ellipse_points(d, 22.0, 200), 0.01)
    assert dome.length == pytest.approx(ell.length, abs=SAMPLED_TOL * 10)
    s = np.linspace(0.0, ell.length, 301)
    a, b = dome.evaluate(s), ell.evaluate(s)
    for name in ("h", "r"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), atol=SAMPLED_TOL * 100)
    np.testing.assert_allclose(_curvature(a), _curvature(b), atol=1e-6 / R)


def test_noisy_contour_stays_within_its_tolerance_and_is_smooth() -> None:
    rng = np.random.default_rng(7)
    pts = _ellipse_points(90.0, 22.0, 400)
    noisy = pts.copy()
    noisy[1:-1] += rng.normal(0.0, NOISE, size=(398, 2))
    noisy[1:-1, 0] = np.maximum.accumulate(noisy[1:-1, 0])
    tol = 0.02
    dome = ContourDome(R, noisy, tol)
    assert dome.deviation <= tol
    ell = Ellipsoid(R, 22.0, 90.0)
    s = np.linspace(0.0, min(dome.length, ell.length), 201)
    # the smoothing removed most of the scatter's curvature (a spline through the points would carry
    # curvature errors ~ NOISE / h^2 = 0.02 / mm, the ellipse's own is 0.004 to 0.019): within a third
    # of the largest inside the ends (where the penalty's null space, the parabolas, leaves it freer)
    k_true = np.abs(_curvature(ell.evaluate(s)))
    k_err = np.abs(_curvature(dome.evaluate(s)) - _curvature(ell.evaluate(s)))[10:-10]
    assert np.median(k_err) < 0.1 * k_true.max()
    assert k_err.max() < 0.35 * k_true.max()


def test_contour_refused_where_it_cannot_follow_a_corner() -> None:
    pts = np.array([[0, R], [10, R - 0.05], [20, R - 0.2], [30, R - 0.45], [31, R - 20], [32, R - 40],
                    [40, 60.0], [50, 30.0]])
    with pytest.raises(ContourError) as info:
        ContourDome(R, pts, 0.001)
    assert 2 <= info.value.index <= 5  # next to the corner at points 3 to 5


def test_closed_end_contour_trimmed_at_the_shaft() -> None:
    pts = _ellipse_points(90.0, 0.0, 300)
    dome = ContourDome(R, pts, 0.01, 12.0)
    assert dome.end_radius == pytest.approx(12.0, abs=1e-9)
    ell = Ellipsoid(R, 12.0, 90.0)
    assert dome.depth == pytest.approx(ell.depth, abs=1e-7)


def _job(tmp_path, dome: str, extra: str = "") -> str:
    path = tmp_path / "v.yaml"
    path.write_text(f"name: v\nmandrel:\n  profile:\n    type: vessel\n    radius: {R:g}\n    cylinder_length: 300\n"
                    f"    dome: {dome}\n{extra}", encoding="utf-8")
    return str(path)


def _vessel(path: str):
    return make_vessel(load_config(path).mandrel.profile, path)


def test_dxf_spline_and_polyline_read_as_the_ellipse(tmp_path) -> None:
    ezdxf = pytest.importorskip("ezdxf")
    pts = _ellipse_points(90.0, 22.0, 200)
    ell = Ellipsoid(R, 22.0, 90.0)
    doc = ezdxf.new()
    msp = doc.modelspace()
    msp.add_lwpolyline([tuple(p) for p in pts[::-1]], dxfattribs={"layer": "LINER"})  # drawn pole first
    msp.add_line((0, 0), (400, 0), dxfattribs={"layer": "AXIS"})
    doc.saveas(tmp_path / "liner.dxf")
    dome = _vessel(_job(tmp_path, "{type: contour, file: liner.dxf, layer: LINER}")).dome
    s = np.linspace(0.0, ell.length, 101)
    np.testing.assert_allclose(dome.evaluate(s).r, ell.evaluate(s).r, atol=SAMPLED_TOL * 100)


def test_dxf_arcs_of_a_torisphere(tmp_path) -> None:
    """A torispherical head drawn as a LINE on the cylinder, the knuckle ARC and the crown ARC."""
    ezdxf = pytest.importorskip("ezdxf")
    crown, knuckle, r0 = 280.0, 40.0, 22.0
    tori = Torispherical(R, crown, knuckle, r0)
    psi_j = math.degrees(tori.psi_joint)
    doc = ezdxf.new()
    msp = doc.modelspace()
    # x = z from the junction, y = r; the cylinder's last 30 mm drawn too, then the junction moved to 0
    msp.add_arc((0, R - knuckle), knuckle, 90.0 - psi_j, 90.0)
    psi_end = math.degrees(math.acos(r0 / crown))
    msp.add_arc((tori.crown_centre, 0.0), crown, 90.0 - psi_end, 90.0 - psi_j)
    doc.saveas(tmp_path / "head.dxf")
    dome = _vessel(_job(tmp_path, "{type: contour, file: head.dxf, tolerance: 0.002}")).dome
    assert dome.depth == pytest.approx(tori.depth, abs=DXF_TOL)
    assert dome.length == pytest.approx(tori.length, abs=DXF_TOL)
    s = np.linspace(0.0, tori.length, 121)
    np.testing.assert_allclose(dome.evaluate(s).r, tori.evaluate(s).r, atol=DXF_TOL)


def test_dxf_gap_refused(tmp_path) -> None:
    ezdxf = pytest.importorskip("ezdxf")
    doc = ezdxf.new()
    msp = doc.modelspace()
    msp.add_line((0, R), (20, R - 2))
    msp.add_line((21, R - 3), (60, 40))
    doc.saveas(tmp_path / "gap.dxf")
    with pytest.raises(ConfigError, match=r"mandrel.profile.dome.file: gap.dxf: the entities are not one chain"):
        _vessel(_job(tmp_path, "{type: contour, file: gap.dxf}"))


def test_csv_line_named_where_not_monotone(tmp_path) -> None:
    (tmp_path / "liner.csv").write_text("z,r\n0,150\n10,149.6\n20,148.6\n15,146\n40,120\n", encoding="utf-8")
    with pytest.raises(ConfigError, match=r"mandrel.profile.dome.file: liner.csv line 5 \(z = 15, r = 146\): "
                                          r"not monotone in z"):
        load_config(_job(tmp_path, "{type: contour, file: liner.csv}"))

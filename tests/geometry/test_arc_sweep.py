"""The one-arc evaluation's stacked passes (winder/geometry/arc_sweep.py) against the field-by-field
formulas they replace, to round-off, and the jet the line and arc evaluations share their fields from."""

from __future__ import annotations

import numpy as np
import pytest

from winder.config.axes import ArcAxis, PathAxis
from winder.config.mandrel import CircleSection, ConstantProfile
from winder.config.profiles import ConeProfile
from winder.config.sections import EllipseSection
from winder.geometry.build import make_curve, make_profile, make_section
from winder.geometry.sections import Circle
from winder.geometry.surface import SweepSurface, jet_of
from roundoff import assert_roundoff


def _times(a, b):
    return b if isinstance(a, float) and a == 1.0 else a * b


def _zero(v) -> bool:
    return isinstance(v, float) and v == 0.0


def _fields(surface: SweepSurface, s: np.ndarray, th: np.ndarray, radius: tuple, section: tuple) -> list[np.ndarray]:
    """Phi, Phi_s, Phi_th, Phi_ss, Phi_st, Phi_thth on a one-arc sweep, one field at a time, each
    (3, m): the arithmetic the stacked passes must reproduce (docs/math/01-surface.md; K = kappa N, K'.n = 0).
    radius : p, p1, p2 (the profile's radius and s-derivatives); section : q, q1, q2, as evaluate
    takes them (exact floats where they are constants)."""
    arc = surface.curve.pieces[0]
    b, e2u, e2b, e3u, e3b = (float(v) if np.ndim(v) == 0 else v for v in arc.frame_components)
    origin, t0, u, b = arc.origin[:, None], arc.tangent[:, None], arc.toward_dir[:, None], b[:, None]
    kappa = 1.0 / arc.radius
    (p, p1, p2), (q, q1, q2) = radius, section
    c, sn = np.cos(th), np.sin(th)
    half = (0.5 * kappa) * s
    sh, ch = np.sin(half), np.cos(half)
    sh2 = sh * sh
    cp, sp = 1.0 - 2.0 * sh2, 2.0 * sh * ch
    tan = cp * t0 + sp * u
    nrm = cp * u - sp * t0
    n_nrm, n_b, m_nrm, m_b = c * e2u + sn * e3u, c * e2b + sn * e3b, c * e3u - sn * e2u, c * e3b - sn * e2b
    x = origin + (sp / kappa) * t0 + ((2.0 / kappa) * sh2) * u
    n = n_nrm * nrm + n_b * b
    m = m_nrm * nrm + m_b * b
    r = p * q
    kn, km = kappa * n_nrm, kappa * m_nrm
    r_s, r_t = p1 * q, p * q1
    stretch = 1.0 - r * kn
    ps = stretch * tan if _zero(r_s) else stretch * tan + r_s * n
    pt = r * m if _zero(r_t) else r_t * n + r * m
    kap = kappa * nrm
    bend = stretch * kap
    if not _zero(r_s):
        bend = (0.0 * (1.0 - r * kn) - 2.0 * r_s * 1.0 * kn - r * 1.0 * 1.0 * 0.0) * tan + bend
    pss = bend if _zero(p2 * q) else bend + (p2 * q) * n
    twist = (r * km if _zero(r_t) else r_t * kn + r * km) * tan
    if _zero(r_s):
        pst = -twist
    else:
        pst = r_s * m - twist if _zero(p1 * q1) else (p1 * q1) * n + r_s * m - twist
    ptt = (p * q2 - r) * n if _zero(r_t) else (p * q2 - r) * n + (2.0 * r_t) * m
    return [x + r * n, ps, pt, pss, pst, ptt]


@pytest.mark.parametrize("toward", [0.0, 30.0, 200.0])
@pytest.mark.parametrize("shape", ["constant circle", "cone circle", "constant ellipse"])
def test_stacked_passes_match_the_field_by_field_formulas(toward, shape):
    curve = make_curve(ArcAxis(150.0, 90.0, toward), "t.yaml")
    profile_cfg = ConeProfile(10.0, 14.0) if shape.startswith("cone") else ConstantProfile(10.0)
    sec = make_section(EllipseSection(12.0, 7.0) if shape.endswith("ellipse") else CircleSection())
    scale = 1.0 if isinstance(sec, Circle) else 12.0
    surface = SweepSurface(curve, make_profile(profile_cfg, curve.length, "t.yaml"), sec, scale, curve.length, "")
    assert surface._arc_frame is not None
    rng = np.random.default_rng(5)
    s, th = rng.uniform(0.0, curve.length, 64), rng.uniform(-np.pi, 3 * np.pi, 64)
    th[:2], s[2] = (0.0, -0.0), 0.0  # exact zeros keep their signs too
    radius = surface.profile.evaluate(s)[3:] if shape.startswith("cone") else (10.0, 0.0, 0.0)
    section = ((1.0, 0.0, 0.0) if isinstance(sec, Circle) else
               tuple(v / scale for v in sec.polar_cs(np.cos(th), np.sin(th), 2)))
    want = _fields(surface, s, th, radius, section)
    for order in (0, 1, 2):
        got = surface.evaluate(s, th, order)
        for k, field in enumerate(got):
            if k >= (1, 3, 6)[order]:
                assert field is None
                continue
            ref = want[k].T
            assert_roundoff(field, ref)
    assert surface.evaluate(s, th, 1, with_point=False).p is None


def test_jet_is_shared_on_lines_and_arcs_only(quarter_bend, elliptic_tube):
    s, th = np.linspace(10.0, 100.0, 9), np.linspace(0.0, 4.0, 9)
    for surface in (quarter_bend, elliptic_tube):
        ev = surface.evaluate(s, th, 2)
        jet = jet_of(ev, 6)
        assert jet is not None and jet.shape == (6, 3, 9)
        for k, field in enumerate(ev):
            np.testing.assert_array_equal(jet[k].T, field)
        assert jet_of(surface.evaluate(s, th, 1), 6) is None  # a first-order jet has no Phi_ss
        assert jet_of(surface.evaluate(s, th, 1), 3) is not None
    two_arcs = make_curve(PathAxis((ArcAxis(150.0, 45.0, 0.0), ArcAxis(150.0, 45.0, 0.0))), "t.yaml")
    general = SweepSurface(two_arcs, quarter_bend.profile, quarter_bend.section, quarter_bend.section_scale,
                           two_arcs.length, "")
    assert jet_of(general.evaluate(s, th, 2), 6) is None


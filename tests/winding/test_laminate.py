"""Laminate math against closed forms: band areas and masses by hand, the fiber-count law, the
turnaround zone's volume, the cylinder means."""

import math

import numpy as np
import pytest

from winder.winding.laminate import (
    Material,
    clairaut_density,
    clairaut_zone_volume,
    helical_mean_thickness,
    hoop_mean_thickness,
    smooth_density,
    turnaround_zone,
)

MASS_RTOL = 1e-9
LAW_RTOL = 1e-12
MIDPOINT_RTOL = 1e-5  # midpoint rule of the law on cells B / 64 wide

TOWS = Material(fiber_tex=800, tows=4, fiber_density=1.78, resin_density=1.15, fiber_volume_fraction=0.6)


def test_band_area_and_ply_by_hand():
    fiber = 4 * 800 / (1000 * 1.78)  # mm^2
    assert TOWS.fiber_area(10.0) == pytest.approx(fiber, rel=MASS_RTOL)
    assert TOWS.composite_area(10.0) == pytest.approx(fiber / 0.6, rel=MASS_RTOL)
    assert TOWS.ply(10.0) == pytest.approx(fiber / 0.6 / 10.0, rel=MASS_RTOL)


def test_masses_by_hand():
    length = 123456.7  # mm of band
    fiber_g = length * 4 * 800 * 1e-6  # tex: g per km = 1e-6 g per mm
    assert TOWS.fiber_mass_kg(length, 10.0) == pytest.approx(fiber_g / 1000, rel=MASS_RTOL)
    resin_g = fiber_g * 0.4 / 0.6 * 1.15 / 1.78
    assert TOWS.resin_mass_kg(length, 10.0) == pytest.approx(resin_g / 1000, rel=MASS_RTOL)
    # the same fiber volume from the area and density (g/cm^3 = 1e-3 g/mm^3)
    volume = length * TOWS.fiber_area(10.0)
    assert TOWS.fiber_mass_kg(length, 10.0) == pytest.approx(volume * 1.78e-3 / 1000, rel=MASS_RTOL)
    assert TOWS.material_length_mm(length) == pytest.approx(4 * length, rel=MASS_RTOL)


def test_ply_thickness_material():
    m = Material(ply_thickness=0.25, fiber_density=1.8, resin_density=1.2, fiber_volume_fraction=0.5)
    assert m.composite_area(8.0) == pytest.approx(2.0, rel=MASS_RTOL)
    assert m.ply(8.0) == pytest.approx(0.25, rel=MASS_RTOL)
    # fiber: half of 2 mm^2 at 1.8 g/cm^3 over 1 m: 1000 * 1 * 1.8e-3 g
    assert m.fiber_mass_kg(1000.0, 8.0) == pytest.approx(1.8e-3, rel=MASS_RTOL)
    assert m.resin_mass_kg(1000.0, 8.0) == pytest.approx(1.2e-3, rel=MASS_RTOL)
    bare = Material(ply_thickness=0.25)
    assert not bare.has_masses and math.isnan(bare.fiber_mass_kg(1000.0, 8.0))


def test_cylinder_means():
    # circuits that tile the perimeter exactly: N_c B = 2 pi R cos(alpha) -> two plies
    alpha, big_r, band = math.radians(40.0), 80.0, 10.0
    n_c = 2 * math.pi * big_r * math.cos(alpha) / band
    assert helical_mean_thickness(0.3, n_c, band, big_r, alpha) == pytest.approx(0.6, rel=LAW_RTOL)
    perimeter = 2 * math.pi * big_r
    pitch = perimeter * band / math.sqrt(perimeter**2 - band**2)
    assert hoop_mean_thickness(0.3, band, perimeter, pitch) == pytest.approx(0.3, rel=LAW_RTOL)


def test_clairaut_density_is_the_fiber_count_law():
    big_r, c, n, a = 100.0, 40.0, 60, 3.0
    r = np.linspace(45.0, 100.0, 50)
    t = clairaut_density(r, c, n, a) / (2 * np.pi * r)
    cos = np.sqrt(1 - (c / r) ** 2)
    t_big = t[-1]
    np.testing.assert_allclose(t, t_big * big_r * cos[-1] / (r * cos), rtol=LAW_RTOL)
    assert np.all(clairaut_density(np.array([30.0, 39.9]), c, n, a) == 0.0)


def _hemisphere_r(big_r: float, r0: float):
    # meridian from the opening: s = 0 at r0, r(s) = R cos(phi0 - s / R), phi0 = arccos(r0 / R)
    phi0 = math.acos(r0 / big_r)
    return lambda s: big_r * np.cos(phi0 - np.asarray(s) / big_r)


def test_turnaround_zone_finite_and_conserving():
    big_r, r0, band, n, a = 100.0, 30.0, 10.0, 40, 2.5
    r_of = _hemisphere_r(big_r, r0)
    c = 45.0
    s_c = big_r * (math.acos(r0 / big_r) - math.acos(c / big_r))
    ds = band / 64
    s = np.arange(0.5 * ds, 60.0, ds)
    dens = clairaut_density(r_of(s), c, n, a)
    zone = clairaut_zone_volume(r_of, s_c, s_c + 0.5 * band, c, n, a)
    out = turnaround_zone(s, dens, s_c, band, zone)
    assert np.all(np.isfinite(out)) and out.max() < 10 * zone / band
    # the volume beyond the zone is untouched; in all, the exact volume of the passes (the cells
    # beyond the zone are a midpoint rule of the smooth law)
    far = s - 0.5 * ds >= s_c + 0.5 * band
    np.testing.assert_array_equal(out[far], dens[far])
    exact = clairaut_zone_volume(r_of, s_c, s[-1] + 0.5 * ds, c, n, a, nodes=400)
    assert np.sum(out) * ds == pytest.approx(exact, rel=MIDPOINT_RTOL)
    # the spread meets the law at the zone's outer edge to leading order (1/sqrt singularity)
    k = int(np.argmax(far))
    assert out[k - 1] == pytest.approx(dens[k], rel=0.15)


def test_zone_volume_quadrature_against_closed_form_on_a_cylinder():
    # r constant is no turnaround, but checks the substitution: n a R / sqrt(R^2 - c^2) * length
    val = clairaut_zone_volume(lambda s: np.full_like(s, 50.0), 0.0, 7.0, 30.0, 3, 2.0)
    assert val == pytest.approx(3 * 2.0 * 50.0 / 40.0 * 7.0, rel=1e-13)


def test_smoothing_keeps_volume_and_constants():
    s = np.linspace(0.0, 100.0, 1001)
    v = np.where((s > 30) & (s < 60), 5.0, 0.0)
    sm = smooth_density(s, v, 4.0)
    assert sm.sum() == pytest.approx(v.sum(), rel=1e-12)
    const = smooth_density(s, np.full_like(s, 2.0), 4.0, (True, True))
    np.testing.assert_allclose(const, 2.0, rtol=1e-14)


# -- the band-spread cubic (docs/math/08-laminate-edges.md 8.6) --------------------------------------
def test_spread_coefficients_meet_their_four_conditions():
    from winder.winding.laminate import spread_coefficients

    d1, e, m = 1.297, -0.401, 1.697  # the worked example of docs/math 8.6
    a = np.array(spread_coefficients(d1, e, m))
    # solved independently: value and slope at 1, the mean over [0, 1]
    want = np.linalg.solve(np.array([[1.0, 1.0, 1.0], [1.0, 2.0, 3.0], [0.5, 1.0 / 3.0, 0.25]]), [d1, e, m])
    np.testing.assert_allclose(a, want, rtol=1e-12)
    np.testing.assert_allclose(a, [12.18, -20.07, 9.19], atol=0.01)
    x = np.linspace(0.0, 1.0, 10001)
    p = ((a[2] * x + a[1]) * x + a[0]) * x
    assert p.min() >= 0.0 and p.max() == pytest.approx(2.25, abs=0.01)


def test_band_spread_keeps_the_volume_and_the_law_beyond_two_bands():
    from winder.winding.laminate import band_spread

    # a flat pole (r = c + u): the law n a r / sqrt(r^2 - c^2) from a turnaround at s_c = 20
    c, band, n, a = 35.0, 10.0, 100, 2.5
    edges = np.linspace(0.0, 120.0, 961)
    s, w = 0.5 * (edges[1:] + edges[:-1]), np.diff(edges)
    r_of = lambda x: c + (np.asarray(x) - 20.0)  # noqa: E731
    law = clairaut_density(r_of(s), c, n, a)
    # the cells' volumes of the law, exact: n a sqrt(r^2 - c^2) between the edges
    prim = n * a * np.sqrt(np.clip(r_of(edges) ** 2 - c * c, 0.0, None))
    dens = np.diff(prim) / w
    out = band_spread(s, w, dens, 20.0, band, 1.0, r_of)
    assert np.sum(out * w) == pytest.approx(np.sum(dens * w), rel=1e-12)
    beyond = s > 20.0 + 2.0 * band + w[0]
    np.testing.assert_allclose(out[beyond], dens[beyond], rtol=1e-12)
    assert np.all(out[s < 20.0 - 0.5 * band - w[0]] == 0.0)  # nothing inside the band's inner edge
    assert np.all(np.isfinite(out)) and out.max() < 2.0 * law[beyond][0]

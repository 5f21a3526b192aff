"""The variational geodesic solver against closed forms, finite differences and its own theory."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from conftest import ellipse_arc
from winder.errors import ConfigError, SolverError
from winder.paths.energy import energy_terms
from winder.paths.geodesic import Method, geodesic, solve_path, straight_path
from winder.paths.resolution import DEFAULT_PER_ROUND

SMOOTH_REL = 1e-9  # smooth-path length, n = 200, on developable tubes
FD_REL = 1e-5  # finite-difference checks of gradient and Hessian
RATIO_TOL = 0.02  # (L* - L_n) / (L* - L_2n) against 4
CLAIRAUT_REL = 1e-6
BOUND_SLACK = 2.5  # the smooth error estimate bounds the error, and by no more than this factor


def helix_length(dt: float, radius: float, dtheta: float) -> float:
    """A straight circular tube unrolls to a plane: the geodesic is a straight line."""
    return float(np.hypot(dt, radius * dtheta))


@pytest.mark.parametrize("rounds", [0, 1, 5])
def test_straight_tube_helix_closed_form(straight_tube, rounds):
    res = geodesic(straight_tube, (20.0, 0.0), (280.0, np.radians(100.0)), rounds=rounds, n=200)
    truth = helix_length(260.0, 40.0, np.radians(100.0) + 2 * np.pi * rounds)
    assert res.converged
    assert abs(res.length - truth) / truth < SMOOTH_REL
    # The unrolled helix is a straight line in (t, theta): the vertices sit on it.
    f = (res.t - 20.0) / 260.0
    assert np.allclose(res.theta, f * (np.radians(100.0) + 2 * np.pi * rounds), atol=1e-9)
    assert res.theta[-1] == pytest.approx(np.radians(100.0) + 2 * np.pi * rounds)


@pytest.mark.parametrize("rounds", [0, 2])
def test_elliptic_tube_unrolled(elliptic_tube, rounds):
    th0, th1 = np.radians(-20.0), np.radians(70.0)
    res = geodesic(elliptic_tube, (0.0, th0), (400.0, th1), rounds=rounds, n=400)
    truth = np.hypot(400.0, ellipse_arc(60.0, 35.0, th0, th1 + 2 * np.pi * rounds))
    assert res.converged
    assert abs(res.length - truth) / truth < 1e-8


def test_cone_unrolled_sector(cone):
    sin_b = 0.1 / np.sqrt(1.01)  # half angle b: tan b = 30 / 300
    t0, t1, dth = 10.0, 290.0, np.radians(250.0) + 2 * np.pi
    rho0, rho1 = (60.0 - 0.1 * t0) / sin_b, (60.0 - 0.1 * t1) / sin_b  # slant distances from the apex
    truth = np.sqrt(rho0**2 + rho1**2 - 2 * rho0 * rho1 * np.cos(dth * sin_b))
    res = geodesic(cone, (t0, 0.0), (t1, np.radians(250.0)), rounds=1, n=200)
    assert abs(res.length - truth) / truth < 1e-8


def clairaut(surface, s, theta):
    """r sin(alpha) along the smooth path through the vertices (r^2 theta' / |v| on revolutions)."""
    i = np.arange(s.shape[0], dtype=float)
    cs, ct = CubicSpline(i, s), CubicSpline(i, theta)
    ev = surface.evaluate(s, theta, order=1)
    v = ev.ps * cs(i, 1)[:, None] + ev.pt * ct(i, 1)[:, None]
    r = surface.radius(s, theta)
    return r**2 * ct(i, 1) / np.linalg.norm(v, axis=1)


def test_cone_clairaut(cone):
    res = geodesic(cone, (10.0, 0.0), (290.0, np.radians(250.0)), rounds=1, n=400)
    plain = clairaut(cone, res.s, res.theta)
    refined = clairaut(cone, res.refined_s, res.refined_theta)
    # The plain vertices are O(h^2) off the geodesic, the extrapolated ones O(h^4).
    assert np.ptp(plain) / np.mean(plain) < 4e-4
    assert np.ptp(refined) / np.mean(refined) < CLAIRAUT_REL
    assert np.ptp(refined) < np.ptp(plain) / 100


def _fd_check(surface, s, th):
    e, grad, hd, ho, _ = energy_terms(surface, s, th)
    n = s.shape[0] - 2
    eps_s, eps_t = 1e-5, 1e-7
    fd_g = np.zeros((n, 2))
    fd_h = np.zeros((2 * n, 2 * n))
    for i in range(n):
        for c, eps in ((0, eps_s), (1, eps_t)):
            plus, minus = [s.copy(), th.copy()], [s.copy(), th.copy()]
            plus[c][i + 1] += eps
            minus[c][i + 1] -= eps
            ep, gp, *_ = energy_terms(surface, *plus)
            em, gm, *_ = energy_terms(surface, *minus)
            fd_g[i, c] = (ep - em) / (2 * eps)
            fd_h[:, 2 * i + c] = ((gp - gm) / (2 * eps)).ravel()
    dense = np.zeros((2 * n, 2 * n))
    for i in range(n):
        dense[2 * i:2 * i + 2, 2 * i:2 * i + 2] = hd[i]
        if i < n - 1:
            dense[2 * i:2 * i + 2, 2 * i + 2:2 * i + 4] = ho[i]
            dense[2 * i + 2:2 * i + 4, 2 * i:2 * i + 2] = ho[i].T
    assert np.abs(fd_g - grad).max() <= FD_REL * np.abs(grad).max()
    assert np.abs(fd_h - dense).max() <= FD_REL * np.abs(dense).max()


@pytest.mark.parametrize("name", ["quarter_bend", "elliptic_tube", "cone"])
def test_gradient_and_hessian_finite_differences(name, request):
    surface = request.getfixturevalue(name)
    k = 10
    rng = np.random.default_rng(3)
    s = np.linspace(5.0, surface.length - 5.0, k) + np.r_[0, rng.uniform(-3, 3, k - 2), 0]
    th = np.linspace(0.0, 8.0, k) + np.r_[0, rng.uniform(-0.2, 0.2, k - 2), 0]
    _fd_check(surface, s, th)


@pytest.fixture(scope="module")
def bend_truth(quarter_bend):
    """Quarter bend, 1 extra round, by two-point shooting (independent of the variational solver)."""
    from winder.paths.shooting import shoot  # noqa: PLC0415

    res = shoot(quarter_bend, (0.0, 0.0), (quarter_bend.length, np.pi / 2), rounds=1)
    assert res.converged
    return res.length


def test_quarter_bend_accuracy(quarter_bend, bend_truth):
    t_end = quarter_bend.axial_length
    r200 = geodesic(quarter_bend, (0.0, 0.0), (t_end, np.pi / 2), rounds=1, n=200)
    assert abs(r200.length - bend_truth) / bend_truth < 1e-9
    r1000 = geodesic(quarter_bend, (0.0, 0.0), (t_end, np.pi / 2), rounds=1, n=1000)
    assert abs(r1000.polyline_length - bend_truth) / bend_truth < 3e-6
    assert abs(r1000.length_extrapolated - bend_truth) / bend_truth < 1e-7
    # The estimate is an honest bound for the polyline at 2n + 1 and the extrapolation.
    assert abs(r1000.length_extrapolated - bend_truth) < r1000.error_estimate


def test_elliptic_tube_accuracy(elliptic_tube):
    th1 = np.pi / 2 + 4 * np.pi
    truth = np.hypot(400.0, ellipse_arc(60.0, 35.0, 0.0, th1))
    r200 = geodesic(elliptic_tube, (0.0, 0.0), (400.0, np.pi / 2), rounds=2, n=200)
    assert abs(r200.length - truth) / truth < 1e-7
    r1000 = geodesic(elliptic_tube, (0.0, 0.0), (400.0, np.pi / 2), rounds=2, n=1000)
    assert abs(r1000.polyline_length - truth) / truth < 2e-5
    assert abs(r1000.length_extrapolated - truth) / truth < 1e-7


def test_quadratic_convergence_ratio(quarter_bend, bend_truth):
    t_end = quarter_bend.axial_length
    ln = geodesic(quarter_bend, (0.0, 0.0), (t_end, np.pi / 2), rounds=1, n=100, estimate=False)
    l2n = geodesic(quarter_bend, (0.0, 0.0), (t_end, np.pi / 2), rounds=1, n=201, estimate=False)
    ratio = (bend_truth - ln.polyline_length) / (bend_truth - l2n.polyline_length)
    assert abs(ratio - 4.0) < 4.0 * RATIO_TOL


def test_tolerance_stops_on_the_reported_lengths_bound(quarter_bend, bend_truth):
    tol = 1e-8
    a, b = (0.0, 0.0), (quarter_bend.axial_length, np.pi / 2)
    res = geodesic(quarter_bend, a, b, rounds=1, tolerance=tol)
    assert res.converged
    assert res.smooth_error_estimate < tol
    assert abs(res.length - bend_truth) < tol
    # n within 2x of the least n that meets the tolerance: half of it does not.
    half = geodesic(quarter_bend, a, b, rounds=1, n=res.n // 2, estimate=False)
    assert abs(half.length - bend_truth) > tol


def test_tight_tolerance_on_the_elliptic_tube_in_one_refinement(elliptic_tube):
    """1e-12 of the length needs ~94x the coarsest pair's segments: the h^4 prediction gets there in
    one refinement, and the bound still holds against the unrolled closed form."""
    truth = np.hypot(400.0, ellipse_arc(60.0, 35.0, 0.0, np.pi / 2 + 4 * np.pi))
    tol = 1e-12 * truth
    res = geodesic(elliptic_tube, (0.0, 0.0), (400.0, np.pi / 2), rounds=2, tolerance=tol)
    err = abs(res.length - truth)
    assert res.converged and res.smooth_error_estimate < tol
    assert err <= res.smooth_error_estimate <= BOUND_SLACK * err
    assert [lv.n for lv in res.levels][2:] == [res.n, 2 * res.n + 1]  # the coarsest pair, then this one


@pytest.mark.parametrize("name, n", [("elliptic", 50), ("elliptic", 200), ("elliptic", 1000), ("cone", 25),
                                     ("cone", 400), ("bend", 25), ("bend", 200), ("straight", 200)])
def test_smooth_error_estimate_bounds_the_true_error(name, n, elliptic_tube, cone, quarter_bend,
                                                     straight_tube, bend_truth):
    sin_b = 0.1 / np.sqrt(1.01)
    rho = (60.0 - 0.1 * np.array([10.0, 290.0])) / sin_b
    dth = np.radians(250.0) + 2 * np.pi
    case = {
        "elliptic": (elliptic_tube, (0.0, 0.0), (400.0, np.pi / 2), 2,
                     np.hypot(400.0, ellipse_arc(60.0, 35.0, 0.0, np.pi / 2 + 4 * np.pi))),
        "cone": (cone, (10.0, 0.0), (290.0, np.radians(250.0)), 1,
                 np.sqrt(rho[0]**2 + rho[1]**2 - 2 * rho[0] * rho[1] * np.cos(dth * sin_b))),
        "bend": (quarter_bend, (0.0, 0.0), (quarter_bend.axial_length, np.pi / 2), 1, bend_truth),
        "straight": (straight_tube, (20.0, 0.0), (280.0, np.radians(100.0)), 5,
                     helix_length(260.0, 40.0, np.radians(100.0) + 10 * np.pi)),
    }[name]
    surface, a, b, rounds, truth = case
    res = geodesic(surface, a, b, rounds=rounds, n=n)
    err = abs(res.length - truth)
    assert err <= res.smooth_error_estimate
    if name != "straight":  # developable tubes are exact but for roundoff
        assert res.smooth_error_estimate <= BOUND_SLACK * err


def test_many_round_helix_default_converges(quarter_bend):
    a, b = (0.0, 0.0), (quarter_bend.axial_length, np.pi / 2)
    res = geodesic(quarter_bend, a, b, rounds=50)
    assert res.converged and res.n >= 50 * DEFAULT_PER_ROUND
    assert res.smooth_error_estimate < 1e-5
    # Too few points for the rounds: the message says why and what to do.
    few = geodesic(quarter_bend, a, b, rounds=50, n=200, estimate=False)
    assert few.converged or "per round" in few.message
    # Every solve is reported with its iteration cap, the estimate's 2n + 1 solve last.
    assert res.levels[-1].n == 2 * res.n + 1 and all(lv.iterations <= lv.max_iter for lv in res.levels)


def test_fewer_than_three_segments_a_round_refused(quarter_bend):
    """A chord of over a third of a turn cuts across the tube: 200 points for 100 rounds of the elbow
    sample "converged" to 72.9 m where the fiber is 25.1 m. Refused before the solve; from 3 segments a
    round on, a solve converges near the length or says it did not."""
    a, b = (0.0, 0.0), (quarter_bend.axial_length, np.pi / 2)  # 100.25 rounds: at least 300 points
    with pytest.raises(ConfigError, match=r"^points: must be at least 300 for a path of 100\.[23] rounds.*got 299$"):
        geodesic(quarter_bend, a, b, rounds=100, n=299)
    with pytest.raises(ConfigError, match="^points: must be at least 300"):
        geodesic(quarter_bend, a, b, rounds=100, n=200, tolerance=1e-3)
    truth = geodesic(quarter_bend, a, b, rounds=100, tolerance=1e-6).length
    res = geodesic(quarter_bend, a, b, rounds=100, n=300, estimate=False)
    assert "per round" in res.message if not res.converged else abs(res.length - truth) < 1e-3 * truth
    assert abs(res.length - truth) < 1e-3 * truth  # close even unconverged, not a chain across the tube


def test_tolerance_below_roundoff_and_too_many_points_refused(quarter_bend):
    a, b = (0.0, 0.0), (quarter_bend.axial_length, np.pi / 2)
    with pytest.raises(SolverError, match="below what double precision resolves"):
        geodesic(quarter_bend, a, b, rounds=1, tolerance=1e-14)
    with pytest.raises(SolverError, match="would need about"):
        geodesic(quarter_bend, a, b, rounds=1, tolerance=1e-11, max_points=1000)
    with pytest.raises(ConfigError, match="^points: at most 1000000"):
        geodesic(quarter_bend, a, b, n=1_000_001)


def test_equal_spacing_and_zero_geodesic_curvature(quarter_bend):
    for n in (100, 400):
        res = geodesic(quarter_bend, (10.0, 0.3), (200.0, 2.0), rounds=2, n=n, estimate=False)
        # Stationarity makes consecutive segments equal up to O(h^2) terms.
        assert res.spacing_deviation < 50.0 / n**2
        assert res.max_geodesic_curvature < 0.5 / n**2


def test_warm_start_converges_in_two_iterations(quarter_bend):
    a, b = (0.0, 0.0), (quarter_bend.axial_length, np.pi / 2)
    cold = geodesic(quarter_bend, a, b, rounds=1, n=300, estimate=False)
    warm = geodesic(quarter_bend, a, b, rounds=1, n=300, estimate=False, init=(cold.s, cold.theta))
    assert warm.converged and warm.iterations <= 2
    assert warm.length == pytest.approx(cold.length, rel=1e-12)
    # A refined n from a coarser converged path (paper 6.2): also one or two steps.
    finer = geodesic(quarter_bend, a, b, rounds=1, n=601, estimate=False, init=(cold.s, cold.theta))
    assert finer.converged and finer.iterations <= 2


def test_newton_from_straight_path_is_quadratic(quarter_bend):
    s, th = straight_path(0.0, 0.0, quarter_bend.length, np.pi / 2 + 2 * np.pi, 1)
    sol = solve_path(quarter_bend, s, th, 1000)
    assert sol.converged
    assert sol.iterations <= 12


def test_lbfgs_matches_newton(quarter_bend):
    a, b = (0.0, 0.0), (quarter_bend.axial_length, np.pi / 2)
    newton = geodesic(quarter_bend, a, b, rounds=0, n=10, estimate=False)
    lbfgs = geodesic(quarter_bend, a, b, rounds=0, n=10, estimate=False, method=Method.LBFGS)
    assert lbfgs.method is Method.LBFGS and lbfgs.converged
    assert lbfgs.polyline_length == pytest.approx(newton.polyline_length, rel=1e-8)
    assert lbfgs.iterations > 10 * newton.iterations  # the chain's condition number grows like n^2


def test_station_outside_mandrel_refused(straight_tube):
    with pytest.raises(ConfigError, match=r"^end: t must lie on the mandrel, in \[0, 300\]"):
        geodesic(straight_tube, (0.0, 0.0), (301.0, 0.0))


def test_path_over_the_polar_opening_refused():
    from winder.config.job import parse_config  # noqa: PLC0415
    from winder.geometry.build import build_surface  # noqa: PLC0415

    job = parse_config({"name": "v", "mandrel": {"profile": {
        "type": "vessel", "radius": 100, "cylinder_length": 300,
        "dome": {"type": "hemisphere", "polar_opening": 30}}}}, "v.yaml")
    vessel = build_surface(job.mandrel, job.source)
    with pytest.raises(SolverError, match=r"runs off the mandrel past t = 0 \(the first polar opening\)"):
        geodesic(vessel, (5.0, 0.0), (5.0, np.pi))
    # A quarter turn stays on the dome.
    assert geodesic(vessel, (5.0, 0.0), (5.0, np.pi / 2)).converged


def test_hemisphere_great_circle():
    """On a hemispherical dome geodesics are great circles: length = R * central angle."""
    from winder.config.job import parse_config  # noqa: PLC0415
    from winder.geometry.build import build_surface  # noqa: PLC0415

    job = parse_config({"name": "v", "mandrel": {"profile": {
        "type": "vessel", "radius": 100, "cylinder_length": 300,
        "dome": {"type": "hemisphere", "polar_opening": 20}}}}, "v.yaml")
    vessel = build_surface(job.mandrel, job.source)
    centre = np.array([0.0, 0.0, np.sqrt(100.0**2 - 20.0**2)])  # the first dome's centre, on the axis
    a, b = (10.0, 0.3), (60.0, 1.9)
    res = geodesic(vessel, a, b, n=200)
    pa, pb = res.points[0] - centre, res.points[-1] - centre
    truth = 100.0 * np.arccos(pa @ pb / (np.linalg.norm(pa) * np.linalg.norm(pb)))
    assert abs(res.length - truth) / truth < 1e-9
    # Every vertex lies in the plane of the great circle through the end points and the centre.
    normal = np.cross(pa, pb)
    assert np.max(np.abs((res.points - centre) @ normal)) / np.linalg.norm(normal) < 1e-3


TINY_REL = 1e-6  # a path of 1e-7 mm far from the origin: its ends carry the stations' roundoff


@pytest.mark.parametrize("dt", [1e-7, 1e-9])
def test_a_path_shorter_than_the_coordinates_resolve_converges(straight_tube, dt):
    """Ends 1e-7 mm apart at t = 10 on a 40 mm tube: the energy is all roundoff, so the line search
    cannot judge a step; a step below the points' own roundoff is converged, the length the chord."""
    res = geodesic(straight_tube, (10.0, 0.0), (10.0 + dt, 0.0))
    assert res.converged
    assert res.length == pytest.approx(dt, rel=TINY_REL)


def test_geodesic_curvature_on_first_use_is_the_solvers(quarter_bend):
    """max_geodesic_curvature, computed when asked, takes the same surface derivatives as the solve's
    last evaluation: the evaluation is per point and order 1 gives order 2's first derivatives."""
    from winder.geometry.measure import geodesic_curvature  # noqa: PLC0415
    from winder.paths.geodesic import solve_path, straight_path  # noqa: PLC0415

    res = geodesic(quarter_bend, (10.0, 0.3), (200.0, 2.0), rounds=1, n=64, estimate=False)
    s0, s1 = (float(v) for v in quarter_bend.s_of_t(np.array([10.0, 200.0])))
    sol = solve_path(quarter_bend, *straight_path(s0, 0.3, s1, 2.0 + 2.0 * np.pi, 64), 64)
    assert np.array_equal(sol.s, res.s) and np.array_equal(sol.theta, res.theta)
    kg = geodesic_curvature(quarter_bend, sol.s, sol.theta, sol.points(), (sol.ev.ps, sol.ev.pt))
    assert "max_geodesic_curvature" not in vars(res)  # not computed by the solve
    assert res.max_geodesic_curvature == float(np.max(np.abs(kg)))

"""Geodesic fiber paths by the variational method (paper Eq. 14; MATH.md 2-3).

A path is a polyline of n interior points u_i = (s_i, theta_i) on the surface between two fixed
end points; it minimizes E = sum |y_{i+1} - y_i|^2 with y_i = Phi(u_i). Minimizers are equally
spaced and converge to the geodesic with an O(1/n^2) length error.

Solvers:
- newton (default): Newton on the block-tridiagonal Hessian (2x2 blocks, banded Cholesky, O(n) per
  step), including the second-derivative term that carries the surface curvature; Armijo line
  search; where the Hessian is indefinite or its direction is not downhill, the positive-definite
  Gauss-Newton matrix. Coarse-to-fine: solve at ~31 points, resample, re-solve, up to n.
- lbfgs: the paper's method, scipy's L-BFGS-B with the same analytic gradient, from the straight path.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from enum import Enum

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.linalg import LinAlgError, solveh_banded
from scipy.optimize import minimize

from winder.config.winding import DEFAULT_POINTS
from winder.errors import ConfigError, SolverError
from winder.geometry.measure import (geodesic_curvature, polyline_length, richardson, smooth_length,
                                     spacing_deviation)
from winder.geometry.surface import SweepSurface
from winder.paths.energy import energy, energy_terms


class Method(Enum):
    NEWTON = "newton"
    LBFGS = "lbfgs"


class StopReason(Enum):
    STEP = "the Newton step fell below the step tolerance"
    ROUNDOFF = "no further decrease of the energy at machine precision"
    LBFGS = "L-BFGS-B stopped on its tolerances"
    MAX_ITER = "the iteration limit was reached"


COARSEST = 31  # interior points of the coarsest level
LEVEL_FACTOR = 4  # segments multiply by this from one level to the next
POINTS_PER_ROUND = 24  # the coarsest level keeps this many points per round of a helix
STEP_TOL = 1e-9  # converged when no vertex moves more than this fraction of the mean segment
POLISH_STEP = 1e-4  # a full Newton step this small (of the mean segment) is taken even on flat energy
ENERGY_ROUNDOFF = 1e-12  # relative energy rise that is round-off, not a worse path
LEVEL_STEP_TOL = 1e-5  # looser on the coarse levels: the next level corrects them in a step or two
MAX_NEWTON = 100
LBFGS_MAX_ITER = 200_000
LBFGS_FTOL = 1e-15  # relative energy decrease per iteration at which L-BFGS-B stops
LBFGS_GTOL = 1e-9  # largest gradient component (mm) at which L-BFGS-B stops
ARMIJO = 1e-4
BOUNDARY_TOL = 1e-9  # a vertex this close (mm) to an end of the mandrel is on it


@dataclass(frozen=True)
class PathSolve:
    """A solved polyline in the parameter domain.

    s, theta : (n + 2,) float, end points included, theta unwrapped (radians).
    history : (k, 2) float, energy and gradient norm per iteration (finest level).
    """

    s: np.ndarray
    theta: np.ndarray
    iterations: int
    converged: bool
    reason: StopReason
    history: np.ndarray
    nfev: int = 0  # energy evaluations (with or without derivatives)


@dataclass(frozen=True)
class GeodesicResult:
    """A geodesic between two surface points.

    t, s, theta : (n + 2,) float: axial station (mm), internal station, unwrapped angle (rad).
    points : (n + 2, 3) float, xyz on the surface (mm).
    length : smooth-path length through the points (mm), the reported length.
    polyline_length, length_extrapolated (Richardson), error_estimate (|L_2n - L_n| / 3): mm.
    smooth_error_estimate : |length at n - length at 2n+1| (mm), a bound on the reported length's error.
    spacing_deviation : max |segment / mean - 1|.  max_geodesic_curvature : 1/mm.
    refined_s, refined_theta : (n + 2,) float, Richardson-extrapolated vertices (O(h^4) from the
        geodesic instead of O(h^2)); None without the 2n + 1 solve.
    """

    t: np.ndarray
    s: np.ndarray
    theta: np.ndarray
    points: np.ndarray
    length: float
    polyline_length: float
    length_extrapolated: float
    error_estimate: float
    smooth_error_estimate: float
    n: int
    iterations: int
    converged: bool
    reason: StopReason
    method: Method
    spacing_deviation: float
    max_geodesic_curvature: float
    seconds: float
    history: np.ndarray
    refined_s: np.ndarray | None = None
    refined_theta: np.ndarray | None = None
    nfev: int = 0

    # scipy's result vocabulary (scipy.optimize.OptimizeResult)
    @property
    def success(self) -> bool:
        return self.converged

    @property
    def status(self) -> int:
        """0 converged, 1 the iteration limit was reached (scipy's codes)."""
        return 1 if self.reason is StopReason.MAX_ITER else 0

    @property
    def message(self) -> str:
        return self.reason.value

    @property
    def nit(self) -> int:
        return self.iterations


# -- the Newton step ----------------------------------------------------------------------------------
def _banded(hd: np.ndarray, ho: np.ndarray) -> np.ndarray:
    """Upper banded storage (4, 2n) of the interleaved (s_1, th_1, s_2, ...) block-tridiagonal H."""
    n = hd.shape[0]
    ab = np.zeros((4, 2 * n))
    ab[3, 0::2], ab[3, 1::2] = hd[:, 0, 0], hd[:, 1, 1]
    ab[2, 1::2] = hd[:, 0, 1]
    ab[2, 2::2] = ho[:, 1, 0]
    ab[1, 2::2] = ho[:, 0, 0]
    ab[1, 3::2] = ho[:, 1, 1]
    ab[0, 3::2] = ho[:, 0, 1]
    return ab


def _direction(hd: np.ndarray, ho: np.ndarray, grad: np.ndarray) -> np.ndarray | None:
    try:
        step = solveh_banded(_banded(hd, ho), -grad.ravel(), check_finite=False)
    except (LinAlgError, ValueError):
        return None
    return step.reshape(-1, 2)


def _max_step(s: np.ndarray, ds: np.ndarray, s_max: float) -> float:
    """Largest alpha <= 1 keeping every interior station inside [0, s_max]."""
    with np.errstate(divide="ignore", invalid="ignore"):
        lim = np.where(ds < 0, -s / ds, np.where(ds > 0, (s_max - s) / ds, np.inf))
    return float(min(1.0, np.min(lim))) if lim.size else 1.0


def _newton(surface: SweepSurface, s: np.ndarray, th: np.ndarray, step_tol: float,
            max_iter: int = MAX_NEWTON) -> PathSolve:
    s, th = s.copy(), th.copy()
    s_max = surface.length
    history = []
    reason = StopReason.MAX_ITER
    converged = False
    it = nfev = 0
    prev_disp = np.inf
    for it in range(1, max_iter + 1):
        e, grad, hd, ho, jac = energy_terms(surface, s, th)
        nfev += 1
        history.append((e, float(np.linalg.norm(grad))))
        step = _direction(hd, ho, grad)
        newton = step is not None and np.sum(step * grad) < 0.0
        if not newton:
            hd_gn = 4.0 * np.einsum("nki,nkj->nij", jac, jac)
            step = _direction(hd_gn, ho, grad)
            if step is None:
                raise SolverError("the Gauss-Newton matrix is singular: the surface parametrization is "
                                  "degenerate on the path")
        slope = float(np.sum(step * grad))
        disp = np.linalg.norm(jac[:, :, 0] * step[:, :1] + jac[:, :, 1] * step[:, 1:], axis=1).max()
        h = np.sqrt(e / (s.shape[0] - 1))
        if newton and disp <= step_tol * h:
            # Already converged: this step is below the tolerance (and usually at roundoff).
            converged, reason = True, StopReason.STEP
            break
        alpha = _max_step(s[1:-1], step[:, 0], s_max)
        bounded = alpha < 1.0
        if bounded:
            alpha *= 0.999
        while True:
            s_try = s.copy()
            th_try = th.copy()
            s_try[1:-1] += alpha * step[:, 0]
            th_try[1:-1] += alpha * step[:, 1]
            e_try = energy(surface, s_try, th_try)
            nfev += 1
            if e_try <= e + ARMIJO * alpha * slope or alpha < 1e-12:
                break
            alpha *= 0.5
        # The energy is flat to round-off this close to its minimum (it pins the vertices only to
        # sqrt(eps) of a segment), but a small full Newton step is trusted: taking it makes the result
        # independent of the BLAS and numpy build.
        polish = newton and alpha == 1.0 and disp <= POLISH_STEP * h and e_try - e <= ENERGY_ROUNDOFF * e
        if e_try >= e and not polish:
            if -slope <= 1e-13 * e or disp * alpha <= step_tol * h:
                converged, reason = True, StopReason.ROUNDOFF
            elif bounded and alpha < 1e-9:
                _raise_left(surface, s)
            break
        s, th = s_try, th_try
        # Quadratic convergence predicts the next step as disp^3 / prev_disp^2: stop when that (or
        # this step) is below the tolerance, which saves the last, roundoff-only iteration.
        if alpha == 1.0 and (disp <= step_tol * h or (newton and disp < prev_disp < np.inf
                                                       and disp**3 <= step_tol * h * prev_disp**2)):
            converged, reason = True, StopReason.STEP
            break
        prev_disp = disp if alpha == 1.0 else np.inf
    interior = s[1:-1]
    if interior.size and (interior.min() <= BOUNDARY_TOL or interior.max() >= s_max - BOUNDARY_TOL):
        _raise_left(surface, s)
    return PathSolve(s, th, it, converged, reason, np.array(history), nfev)


def _raise_left(surface: SweepSurface, s: np.ndarray) -> None:
    low = s[1:-1].min() <= surface.length / 2
    edge = "polar opening" if not surface.is_axial_parameter else "end"
    where = f"t = 0 (the first {edge})" if low else f"t = {surface.axial_length:.6g} (the far {edge})"
    raise SolverError(f"the shortest path between these points runs off the mandrel past {where}: no "
                      f"geodesic on the surface joins them with this number of rounds; move the end "
                      f"points away from the edge or change the number of rounds")


def _lbfgs(surface: SweepSurface, s: np.ndarray, th: np.ndarray, max_iter: int = LBFGS_MAX_ITER,
           callback=None) -> PathSolve:
    n = s.shape[0] - 2
    history: list[tuple[float, float]] = []

    last: dict[str, np.ndarray] = {}

    def fun(x: np.ndarray) -> tuple[float, np.ndarray]:
        ss, tt = s.copy(), th.copy()
        ss[1:-1], tt[1:-1] = x[0::2], x[1::2]
        e, grad, *_ = energy_terms(surface, ss, tt, full_hessian=False)
        last["x"], last["g"] = x.copy(), grad.ravel()
        return e, last["g"]

    def record(intermediate_result) -> None:
        # The accepted iterate is the last one evaluated (L-BFGS-B's line search ends on it).
        g = last["g"] if np.array_equal(last["x"], intermediate_result.x) else fun(intermediate_result.x)[1]
        history.append((float(intermediate_result.fun), float(np.linalg.norm(g))))
        if callback is not None:
            callback(intermediate_result)

    x0 = np.stack([s[1:-1], th[1:-1]], axis=1).ravel()
    bounds = [(0.0, surface.length), (None, None)] * n
    res = minimize(fun, x0, jac=True, method="L-BFGS-B", bounds=bounds, callback=record,
                   options={"maxiter": max_iter, "maxfun": 2 * max_iter, "ftol": LBFGS_FTOL, "gtol": LBFGS_GTOL,
                            "maxcor": 10})
    s_out, th_out = s.copy(), th.copy()
    s_out[1:-1], th_out[1:-1] = res.x[0::2], res.x[1::2]
    converged = bool(res.success)
    reason = StopReason.LBFGS if converged else StopReason.MAX_ITER
    return PathSolve(s_out, th_out, int(res.nit), converged, reason, np.array(history), int(res.nfev))


# -- paths --------------------------------------------------------------------------------------------
def straight_path(s0: float, th0: float, s1: float, th1: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The straight segment in the (s, theta) domain with n interior points."""
    f = np.linspace(0.0, 1.0, n + 2)
    return s0 + (s1 - s0) * f, th0 + (th1 - th0) * f


def resample(s: np.ndarray, th: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A path resampled to n interior points by cubic splines against the normalized index.

    Converged vertices are equally spaced in 3D, so the index is a good arc-length proxy; halving
    (n -> 2n + 1) keeps the old vertices and inserts spline midpoints.
    """
    f_old = np.linspace(0.0, 1.0, s.shape[0])
    f_new = np.linspace(0.0, 1.0, n + 2)
    s_new, th_new = CubicSpline(f_old, s)(f_new), CubicSpline(f_old, th)(f_new)
    s_new[[0, -1]], th_new[[0, -1]] = s[[0, -1]], th[[0, -1]]
    return s_new, th_new


def _levels(n: int, coarsest: int) -> list[int]:
    levels = [n]
    while levels[-1] > LEVEL_FACTOR * coarsest:
        levels.append((levels[-1] + 1) // LEVEL_FACTOR - 1)
    return levels[::-1]


def solve_path(surface: SweepSurface, s: np.ndarray, th: np.ndarray, n: int,
               method: Method = Method.NEWTON, warm: bool = False) -> PathSolve:
    """Minimize E from the path (s, th) (any number of points; end points fixed) at n interior points.

    warm : the given path is already near the solution; solve at n directly (no coarse levels).
    """
    if method is Method.LBFGS:
        return _lbfgs(surface, *resample(s, th, n))
    rounds = abs(th[-1] - th[0]) / (2.0 * np.pi)
    coarsest = max(COARSEST, int(POINTS_PER_ROUND * rounds))
    levels = [n] if warm or s.shape[0] - 2 >= n else [k for k in _levels(n, coarsest) if k >= s.shape[0] - 2]
    total = nfev = 0
    sol = None
    for k, level in enumerate(levels):
        cur_s, cur_t = resample(s, th, level)
        last = k == len(levels) - 1
        sol = _newton(surface, cur_s, cur_t, STEP_TOL if last else LEVEL_STEP_TOL)
        total += sol.iterations
        nfev += sol.nfev
        s, th = sol.s, sol.theta
    return PathSolve(sol.s, sol.theta, total, sol.converged, sol.reason, sol.history, nfev)


def extrapolate_vertices(coarse: PathSolve, fine: PathSolve) -> tuple[np.ndarray, np.ndarray]:
    """Richardson on vertex positions: (4 u_2n - u_n) / 3 at the n + 2 shared index fractions.

    The vertices of the solutions at n and 2n + 1 interior points share the fractions i / (n + 1);
    their O(h^2) deviation from the geodesic has a smooth expansion in h^2, so the combination
    cancels it. Returns (s, theta), each (n + 2,) float.
    """
    return (4.0 * fine.s[::2] - coarse.s) / 3.0, (4.0 * fine.theta[::2] - coarse.theta) / 3.0


# -- the user-facing geodesic ---------------------------------------------------------------------------
def _check_station(surface: SweepSurface, t: float, what: str) -> None:
    if not (np.isfinite(t) and -1e-9 <= t <= surface.axial_length + 1e-9):
        raise ConfigError(f"t must lie on the mandrel, in [0, {surface.axial_length:.6g}] mm, got {t:g}",
                          key_path=what)


def geodesic(surface: SweepSurface, start: tuple[float, float], end: tuple[float, float], *,
             rounds: int = 0, n: int = DEFAULT_POINTS, tolerance: float | None = None,
             method: Method = Method.NEWTON, init: tuple[np.ndarray, np.ndarray] | None = None,
             estimate: bool = True, max_points: int = 2_000_000) -> GeodesicResult:
    """The geodesic from start to end, each (t mm, theta rad), end angle + 2 pi rounds.

    n : interior points; tolerance : refine (n -> 2n + 1, warm-started) until error_estimate < it.
    init : a previous path (s, theta) to warm-start from (any number of points).
    estimate : also solve at 2n + 1 for Richardson's estimate (doubles the work).
    """
    _check_station(surface, start[0], "start")
    _check_station(surface, end[0], "end")
    if n < 1:
        raise ConfigError(f"must be >= 1, got {n}", key_path="points")
    t0 = time.perf_counter()
    s0, s1 = (float(v) for v in surface.s_of_t(np.array([start[0], end[0]])))
    th0, th1 = float(start[1]), float(end[1]) + 2.0 * np.pi * rounds
    if init is not None:
        s_init, th_init = (np.asarray(a, dtype=float) for a in init)
        s_init, th_init = s_init.copy(), th_init.copy()
        s_init[[0, -1]], th_init[[0, -1]] = (s0, s1), (th0, th1)
    else:
        s_init, th_init = straight_path(s0, th0, s1, th1, 1)
    sol = solve_path(surface, s_init, th_init, n, method, warm=init is not None)
    iterations, nfev = sol.iterations, sol.nfev
    fine = None
    while estimate or tolerance is not None:
        fine = solve_path(surface, sol.s, sol.theta, 2 * n + 1, method, warm=True)
        iterations += fine.iterations
        nfev += fine.nfev
        pts_n = surface.points(sol.s, sol.theta)
        pts_2n = surface.points(fine.s, fine.theta)
        _, err = richardson(polyline_length(pts_n), polyline_length(pts_2n))
        if tolerance is None or err < tolerance:
            break
        if 2 * n + 1 > max_points:
            raise SolverError(f"{tolerance:g} mm not reached with {max_points} points "
                              f"(estimated error {err:.3g} mm)", key_path="tolerance")
        sol, n = fine, 2 * n + 1
    pts = surface.points(sol.s, sol.theta)
    length = smooth_length(surface, sol.s, sol.theta)
    poly = polyline_length(pts)
    refined = (None, None)
    if fine is not None:
        refined = extrapolate_vertices(sol, fine)
        pts_2n = surface.points(fine.s, fine.theta)
        extrapolated, err = richardson(poly, polyline_length(pts_2n))
        smooth_err = abs(length - smooth_length(surface, fine.s, fine.theta))
    else:
        extrapolated, err, smooth_err = float("nan"), float("nan"), float("nan")
    kg = geodesic_curvature(surface, sol.s, sol.theta, pts)
    converged = sol.converged and (fine is None or fine.converged)
    return GeodesicResult(
        t=surface.t_of_s(sol.s), s=sol.s, theta=sol.theta, points=pts, length=length,
        polyline_length=poly, length_extrapolated=extrapolated, error_estimate=err,
        smooth_error_estimate=smooth_err, n=n, iterations=iterations, converged=converged,
        reason=sol.reason, method=method, spacing_deviation=spacing_deviation(pts),
        max_geodesic_curvature=float(np.max(np.abs(kg))) if kg.size else 0.0,
        seconds=time.perf_counter() - t0, history=sol.history, refined_s=refined[0], refined_theta=refined[1],
        nfev=nfev)

"""Geodesic fiber paths by the variational method (paper Eq. 14; docs/math/02-energy.md, docs/math/03-newton.md).

A path is a polyline of n interior points u_i = (s_i, theta_i) on the surface between two fixed
end points; it minimizes E = sum |y_{i+1} - y_i|^2 with y_i = Phi(u_i). Minimizers are equally
spaced and converge to the geodesic with an O(1/n^2) length error.

Solvers:
- newton (default): Newton on the block-tridiagonal Hessian (winder.paths.newton), coarse-to-fine:
  solve at ~31 points (24 per round of a helix), resample, re-solve, up to n, each level 8x finer.
- lbfgs: the paper's method, scipy's L-BFGS-B with the same analytic gradient, from the straight path.

The reported length is the smooth length through the vertices (O(h^4)); with the 2n + 1 solve its
error bound, and --tolerance chooses n by that bound (the h^4 rate predicts the n that meets it).
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from winder.config.winding import DEFAULT_POINTS
from winder.errors import ConfigError, SolverError
from winder.geometry.index_spline import resample_index
from winder.geometry.measure import GAUSS_SEGMENTS, polyline_length, richardson, segment_measures, smooth_lengths
from winder.geometry.surface import SurfaceEval, SweepSurface
from winder.paths.energy import energy_terms
from winder.paths.geodesic_result import GeodesicResult, Method
from winder.paths.lbfgs import _lbfgs
from winder.paths.newton import (LENGTH_SHARE, LEVEL_PREDICTED, LEVEL_STEP_TOL, MAX_NEWTON, STEP_TOL, Level,
                                 PathSolve, StopReason, _newton, chain_bend, evaluate_with_ends)
from winder.paths.resolution import MAX_POINTS, check_points, coarsest_points, default_points, too_few_hint

__all__ = ["DEFAULT_POINTS", "STEP_TOL", "GeodesicResult", "Level", "Method", "PathSolve", "StopReason",
           "energy_terms", "geodesic", "solve_path", "straight_path", "_lbfgs", "_newton"]


LEVEL_FACTOR = 8  # segments multiply by this from one level to the next (measured: 4 needs more levels, 16 is no faster)
# The smooth length's error at n is at most twice |L_n - L_2n+1| whenever halving the segments at
# least halves the error (convergence rate >= 1; the theory and the measurements give 4, for which
# the factor would be 16/15): so the reported estimate bounds the error, by about 1.9x asymptotically.
SMOOTH_SAFETY = 2.0
TOLERANCE_AIM = 0.5  # a refinement aims at this fraction of the tolerance
# Segment-count factor per refinement; up to 128 so that the h^4 prediction from the coarsest pair
# reaches the n of a tight tolerance in one step (measured: 1e-12 of the length needs 33x from
# n = 31 on the quarter bend and 94x from n = 54 on the elliptic tube; 32 stopped at 1023 and 1759,
# and the tube then needed another pair).
MIN_GROWTH, MAX_GROWTH = 1.5, 128.0
MAX_REFINE = 12
# Tolerance mode predicts the n that meets the tolerance from the coarsest solve alone: the smooth
# length's relative error is about PREDICT_ERROR (h k)^4, h k the chain's largest turn per segment
# (max |y_{i-1} - 2 y_i + y_{i+1}| / h). Measured at n = 31 to 439: 6.0e-5 to 6.5e-5 on the quarter
# bend, 2.2e-4 to 3.0e-4 on the elliptic tube; the larger is taken, so the prediction errs toward a
# larger n (the bend's comes out 1.25x the n of its measured rate). It only picks the first pair; the
# bound still comes from that pair (n, 2n + 1), and a pair that misses predicts the next from its
# measured rate. Where the prediction is at most 2n + 1 the coarsest pair is solved first, and so it is
# beyond PREDICT_MAX_POINTS, where the cheap pair's rate costs less than the prediction's overshoot.
PREDICT_ERROR = 3e-4
PREDICT_MAX_POINTS = 1000
ROUNDOFF_FLOOR = 1e-15  # relative: about 4 ulp, the roundoff of a length in double precision
STALL_FLOOR = 1e3  # an error bound that stops falling this close to the roundoff floor is roundoff


# -- paths --------------------------------------------------------------------------------------------
def straight_path(s0: float, th0: float, s1: float, th1: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The straight segment in the (s, theta) domain with n interior points."""
    # linspace's arithmetic (i * step, the last fraction exactly 1) without its wrapper
    f = np.arange(n + 2, dtype=float)
    f *= 1.0 / (n + 1)
    f[-1] = 1.0
    return s0 + (s1 - s0) * f, th0 + (th1 - th0) * f


def resample(s: np.ndarray, th: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A path resampled to n interior points by cubic splines against the normalized index.

    Converged vertices are equally spaced in 3D, so the index is a good arc-length proxy; halving
    (n -> 2n + 1) keeps the old vertices and inserts spline midpoints.
    """
    if s.shape[0] == n + 2:
        return s.copy(), th.copy()
    out = resample_index(np.stack([s, th], axis=1), n + 2)
    return out[:, 0], out[:, 1]


def first_level(n: int, rounds: float) -> int:
    """Interior points of the first level solve_path solves from a straight path to reach n."""
    coarsest = coarsest_points(rounds)
    return coarsest if n < coarsest else _levels(n, coarsest)[0]


def _levels(n: int, coarsest: int) -> list[int]:
    levels = [n]
    while levels[-1] > LEVEL_FACTOR * coarsest:
        levels.append((levels[-1] + 1) // LEVEL_FACTOR - 1)
    return levels[::-1]


def solve_path(surface: SweepSurface, s: np.ndarray, th: np.ndarray, n: int,
               method: Method = Method.NEWTON, warm: bool = False, ends: SurfaceEval | None = None,
               length_tol: float | None = None, loose: bool = False) -> PathSolve:
    """Minimize E from the path (s, th) (any number of points; end points fixed) at n interior points.

    warm : the given path is already near the solution; solve at n directly (no coarse levels).
    ends : the surface at the two end points (order >= 1), when the caller has it (a refinement).
    length_tol : the smooth length's tolerance (mm), when only the length needs the solve (tolerance
    mode): the last level may stop once its remaining step cannot move the length at it.
    loose : the last level too stops on the coarse levels' tolerances (a solve to predict from).
    Fewer than the coarsest level's points (a many-round path at a small n) are solved at the
    coarsest level first and resampled down: from a straight start they would not converge.
    """
    if method is Method.LBFGS:
        return _lbfgs(surface, *resample(s, th, n))
    coarsest, given = coarsest_points(abs(th[-1] - th[0]) / (2.0 * np.pi)), s.shape[0] - 2
    if warm:
        levels = [n]
    elif n < coarsest:  # the coarsest level first, from a coarser path or the straight one at its size
        levels = [coarsest, n] if given < n or given == coarsest else [n]
    elif given >= n:
        levels = [n]
    else:
        levels = [k for k in _levels(n, coarsest) if k >= given]
    total = nfev = 0
    sol = None
    report = []
    ev = None  # the first level's start, where it comes with the ends (fixed: shared by every level)
    if ends is None and s.shape[0] == levels[0] + 2:
        ends, ev = evaluate_with_ends(surface, s, th)
        nfev = 1  # the first level's starting evaluation, made here
    elif ends is None:
        ends = surface.evaluate(s[[0, -1]], th[[0, -1]], order=1)
    for k, level in enumerate(levels):
        cur_s, cur_t = (s, th) if s.shape[0] == level + 2 else resample(s, th, level)  # _newton copies it
        last = k == len(levels) - 1
        sol = (_newton(surface, cur_s, cur_t, STEP_TOL, ends=ends, length_tol=length_tol, ev=ev) if last and not loose
               else _newton(surface, cur_s, cur_t, LEVEL_STEP_TOL, ends=ends, predicted_tol=LEVEL_PREDICTED, ev=ev))
        ev = None
        total += sol.iterations
        nfev += sol.nfev
        report.append(Level(level, sol.iterations, MAX_NEWTON, sol.converged))
        s, th = sol.s, sol.theta
    return sol.with_totals(total, nfev, tuple(report))


def _with_eval(surface: SweepSurface, sol: PathSolve) -> PathSolve:
    """The solve with its surface evaluation at the vertices (L-BFGS's solves come without)."""
    if sol.ev is not None:
        return sol
    ends = surface.evaluate(sol.s[[0, -1]], sol.theta[[0, -1]], order=1)
    return replace(sol, ev=surface.evaluate(sol.s[1:-1], sol.theta[1:-1], order=1), ends=ends)


def extrapolate_vertices(coarse: PathSolve, fine: PathSolve) -> tuple[np.ndarray, np.ndarray]:
    """Richardson on vertex positions: (4 u_2n - u_n) / 3 at the n + 2 shared index fractions.

    The vertices of the solutions at n and 2n + 1 interior points share the fractions i / (n + 1);
    their O(h^2) deviation from the geodesic has a smooth expansion in h^2, so the combination
    cancels it. Returns (s, theta), each (n + 2,) float.
    """
    return (4.0 * fine.s[::2] - coarse.s) / 3.0, (4.0 * fine.theta[::2] - coarse.theta) / 3.0


# -- the user-facing geodesic ---------------------------------------------------------------------------
def _check_station(surface: SweepSurface, t: float, what: str) -> None:
    if not (np.isfinite(t) and surface.t_start - 1e-9 <= t <= surface.axial_length + 1e-9):
        raise ConfigError(f"t must lie on the mandrel, in [{surface.t_start:.6g}, {surface.axial_length:.6g}] mm, "
                          f"got {t:g}",
                          key_path=what)


def _lengths(surface: SweepSurface, sol: PathSolve, lobatto: bool = False) -> float:
    """The smooth length; lobatto: by 4-point Gauss-Lobatto at every n (tolerance mode).

    Lobatto's nodes include the knots, where the solver has the surface already: two new evaluations
    per segment instead of five. Its O(h^6) quadrature error falls 4x faster than the length's O(h^4)
    error, so the pair (n, 2n + 1) still bounds the sum: measured against 5-point Gauss on the
    reference mandrels, at most 6.5e-3 of the length's error (elliptic tube, n = 54; quarter bend,
    n = 31: 3e-4), about 0.025 (h k)^2 of it with h k the chain's turn per segment.
    """
    return _lengths_of(surface, (sol,), lobatto)[0]


def _lengths_of(surface: SweepSurface, sols: tuple[PathSolve, ...], lobatto: bool = False) -> list[float]:
    """_lengths of several solves, their nodes in one surface evaluation (the same lengths)."""
    return smooth_lengths(surface, [(sol.s, sol.theta, sol.jacobian_rows()) for sol in sols],
                          gauss_segments=0 if lobatto else GAUSS_SEGMENTS)


def _refine(surface: SweepSurface, sol: PathSolve, n: int, tolerance: float | None, method: Method,
            max_points: int) -> tuple[PathSolve, PathSolve, float, float, tuple[int, int], tuple[Level, ...]]:
    """Solve at 2n + 1 beside n; with a tolerance, move n until the length's error bound is below it.

    The smooth length converges like h^4, so from one pair (n, 2n + 1) the n that meets the tolerance
    follows; a pair that misses it predicts the next n (aiming at half the tolerance), warm-started
    from the finer solution. Returns (solve at n, solve at 2n + 1, length at n, error bound, (Newton
    iterations, energy evaluations) of all solves, all levels solved).
    """
    tried: list[tuple[int, float]] = []
    iterations, nfev, levels = sol.iterations, sol.nfev, list(sol.levels)
    if tolerance is not None and method is Method.NEWTON:
        # The first solve stopped on the coarse levels' tolerances: a jump to the predicted n needs no
        # more of it; staying at n, its Newton goes on to the length's tolerance.
        n_next = _predicted_points(sol, tolerance)
        if 2 * n + 1 < n_next <= min(PREDICT_MAX_POINTS, max_points):
            sol, n = solve_path(surface, sol.s, sol.theta, n_next, method, warm=True, ends=sol.ends,
                                length_tol=tolerance), n_next
            levels += sol.levels
        else:  # one solve at n, in two legs: the second from the first's end, a chord step first
            sol = _newton(surface, sol.s, sol.theta, STEP_TOL, ends=sol.ends, length_tol=tolerance, ev=sol.ev,
                          factor=sol.factor)
            levels[-1] = Level(levels[-1].n, levels[-1].iterations + sol.iterations, levels[-1].max_iter, sol.converged)
        iterations += sol.iterations
        nfev += sol.nfev
    while True:
        sol = _with_eval(surface, sol)
        fine = _with_eval(surface, solve_path(surface, sol.s, sol.theta, 2 * n + 1, method, warm=True, ends=sol.ends,
                                              length_tol=tolerance))
        iterations += fine.iterations
        nfev += fine.nfev
        levels += fine.levels
        quick = tolerance is not None
        length, fine_length = _lengths_of(surface, (sol, fine), quick)
        # The floor: a length in double precision carries its last bits of roundoff whatever n.
        bound = SMOOTH_SAFETY * abs(length - fine_length) + ROUNDOFF_FLOOR * length
        if StopReason.LENGTH in (sol.reason, fine.reason):
            # Each length may carry up to LENGTH_SHARE of the tolerance from its unfinished Newton: the
            # difference up to twice that, doubled by SMOOTH_SAFETY, and the reported length's own once.
            bound += (2 * SMOOTH_SAFETY + 1) * LENGTH_SHARE * tolerance
        if tolerance is None or bound < tolerance:
            return sol, fine, length, bound, (iterations, nfev), tuple(levels)
        tried.append((n, bound))
        floor = ROUNDOFF_FLOOR * length
        stalled = len(tried) >= 2 and bound > tried[-2][1] * (tried[-2][0] + 1) / (n + 1)
        if tolerance <= floor or (stalled and bound < STALL_FLOOR * floor):
            raise SolverError(f"{tolerance:g} mm is below what double precision resolves on this path "
                              f"({floor:.2g} mm for {length:.6g} mm): the length's error bound is {bound:.3g} mm "
                              f"at n = {n}", key_path="tolerance")
        if len(tried) > MAX_REFINE:
            raise SolverError(f"{tolerance:g} mm not reached in {MAX_REFINE} refinements (error bound "
                              f"{bound:.3g} mm at n = {n}): " + ", ".join(f"n = {k}: {b:.3g} mm" for k, b in tried),
                              key_path="tolerance")
        grow = min(MAX_GROWTH, max(MIN_GROWTH, (bound / (TOLERANCE_AIM * tolerance)) ** 0.25))
        n_next = int(np.ceil((n + 1) * grow)) - 1
        if n_next > max_points:
            raise SolverError(f"{tolerance:g} mm would need about {n_next} points, more than the "
                              f"{max_points} allowed (error bound {bound:.3g} mm at n = {n})", key_path="tolerance")
        sol, n = solve_path(surface, fine.s, fine.theta, n_next, method, warm=True, ends=fine.ends,
                            length_tol=tolerance), n_next
        iterations += sol.iterations
        nfev += sol.nfev
        levels += sol.levels


def _predicted_points(sol: PathSolve, tolerance: float) -> int:
    """The n at which the smooth length's error is predicted (PREDICT_ERROR) to be TOLERANCE_AIM of
    the tolerance (mm), from the solve sol (with its evaluation). Not TOLERANCE_AIM / SMOOTH_SAFETY, as
    a pair's measured rate aims: the constant is the larger measured, so where it is right (the tube)
    the bound comes out at about 0.7 of the tolerance, and where it is 5x too large (the bend) n stays
    within 2x of the least n whose error meets the tolerance."""
    y = sol.points()
    segments = y.shape[0] - 1
    length = polyline_length(y)
    turn = chain_bend(y) * segments / length
    error = PREDICT_ERROR * turn**4 * length
    grow = min(MAX_GROWTH, (error / (TOLERANCE_AIM * tolerance)) ** 0.25)
    return int(np.ceil(segments * grow)) - 1


def _message(sol: PathSolve, levels: tuple[Level, ...], rounds: float, n: int) -> str:
    """Why the solve did (not) converge, with the coarse levels that stopped at their caps."""
    capped = [lv for lv in levels if not lv.converged and lv.n != n]
    text = sol.reason.value
    if capped:
        text += "; coarse levels stopped at their iteration caps: " + ", ".join(
            f"n = {lv.n} after {lv.iterations} of {lv.max_iter}" for lv in capped)
    if not sol.converged:
        text += too_few_hint(n, rounds)
    return text


def _load_solver(method: Method) -> None:
    """Import the library routines a solve by `method` calls, so that the solve's `seconds` time the
    solve alone: the banded LAPACK solvers (Newton's steps, the index splines' slopes), and scipy's
    L-BFGS-B for the paper's method. Loaded on the first solve only (later imports are lookups)."""
    import scipy.linalg.lapack  # noqa: F401, PLC0415 - winder.paths.energy, winder.geometry.index_spline

    if method is Method.LBFGS:
        import scipy.optimize  # noqa: F401, PLC0415 - winder.paths.lbfgs


def geodesic(surface: SweepSurface, start: tuple[float, float], end: tuple[float, float], *,
             rounds: int = 0, n: int | None = None, tolerance: float | None = None,
             method: Method = Method.NEWTON, init: tuple[np.ndarray, np.ndarray] | None = None,
             estimate: bool = True, max_points: int = MAX_POINTS) -> GeodesicResult:
    """The geodesic from start to end on a surface (docs/math/02-energy.md, 03-newton.md).

    Parameters
    ----------
    surface : SweepSurface
        The mandrel (winder.geometry.build.build_surface).
    start, end : tuple of float
        (t mm, theta rad) of the two end points.
    rounds : int
        Extra full turns: the end angle is end[1] + 2 pi rounds (an N-round helix).
    n : int, optional
        Interior points (default: default_points(rounds), 200 and at least 48 a round).
    tolerance : float, optional
        Choose n so that the reported length's error bound (smooth_error_estimate) is below it (mm),
        starting from min(n, the coarsest level).
    method : Method
        NEWTON (the block-tridiagonal Newton, default) or LBFGS (the paper's method, for comparison).
    init : tuple of ndarray, optional
        A previous path (s, theta), any number of points, to warm-start from.
    estimate : bool
        Also solve at 2n + 1 for the error estimates (about doubles the work).
    max_points : int
        The largest n solved (memory and time grow linearly in n); beyond it, an error.

    Returns
    -------
    GeodesicResult
        The vertices (t, s, theta: (n + 2,); points: (n + 2, 3)), the smooth `length` (mm) with its
        bound `smooth_error_estimate`, the polyline length and Richardson's estimate, convergence.

    Raises
    ------
    ConfigError
        An end point off the mandrel, too few points for the rounds.
    SolverError
        No convergence, a path that would leave the mandrel, a tolerance past double precision.

    Examples
    --------
    A quarter turn over 100 mm of a tube of radius 50: the tube unrolls flat, so the geodesic is a
    straight line there, sqrt(100^2 + (50 pi / 2)^2) long.

    >>> import math
    >>> from winder.config.job import parse_config
    >>> from winder.geometry.build import build_surface
    >>> job = parse_config({"name": "tube", "mandrel": {"axis": {"type": "line", "length": 500},
    ...                                                 "profile": {"type": "constant", "radius": 50}}}, "tube.yaml")
    >>> result = geodesic(build_surface(job.mandrel), (0.0, 0.0), (100.0, math.pi / 2))
    >>> result.converged, result.points.shape
    (True, (202, 3))
    >>> abs(result.length - math.hypot(100.0, 25.0 * math.pi)) < 1e-9
    True
    """
    _check_station(surface, start[0], "start")
    _check_station(surface, end[0], "end")
    th0, th1 = float(start[1]), float(end[1]) + 2.0 * np.pi * rounds
    swept = abs(th1 - th0) / (2.0 * np.pi)
    n = default_points(swept) if n is None else n
    check_points(n, swept, max_points)
    _load_solver(method)
    t0 = time.perf_counter()  # the solve alone: what the solver imports is loaded above
    s0, s1 = (float(v) for v in surface.s_of_t(np.array([start[0], end[0]])))
    if init is not None:
        s_init, th_init = (np.asarray(a, dtype=float) for a in init)
        s_init, th_init = s_init.copy(), th_init.copy()
        s_init[[0, -1]], th_init[[0, -1]] = (s0, s1), (th0, th1)
    else:
        if tolerance is not None:
            n = min(n, coarsest_points(swept))
        # The straight path at the first level's size: solve_path then starts on it without a resample.
        s_init, th_init = straight_path(s0, th0, s1, th1, first_level(n, swept))
    sol = solve_path(surface, s_init, th_init, n, method, warm=init is not None, length_tol=tolerance,
                     loose=tolerance is not None and method is Method.NEWTON)
    if estimate or tolerance is not None:
        sol, fine, length, smooth_err, (iterations, nfev), levels = _refine(surface, sol, n, tolerance, method,
                                                                            max_points)
        n = sol.s.shape[0] - 2
    else:
        sol, fine = _with_eval(surface, sol), None
        length, smooth_err, levels = _lengths(surface, sol), float("nan"), sol.levels
        iterations, nfev = sol.iterations, sol.nfev
    pts = sol.points()
    poly, spacing = segment_measures(pts)
    refined = (None, None)
    if fine is not None:
        refined = extrapolate_vertices(sol, fine)
        extrapolated, err = richardson(poly, polyline_length(fine.points()))
    else:
        extrapolated, err = float("nan"), float("nan")
    converged = sol.converged and (fine is None or fine.converged)
    return GeodesicResult(
        t=surface.t_of_s(sol.s), s=sol.s, theta=sol.theta, points=pts, length=length,
        polyline_length=poly, length_extrapolated=extrapolated, error_estimate=err,
        smooth_error_estimate=smooth_err, n=n, iterations=iterations, converged=converged,
        reason=sol.reason, method=method, spacing_deviation=spacing,
        seconds=time.perf_counter() - t0, history=sol.history, refined_s=refined[0], refined_theta=refined[1],
        nfev=nfev, levels=levels, message=_message(sol, levels, swept, n), surface=surface)

"""Two-point geodesic shooting (docs/math/04-checks.md): the paper's Runge-Kutta baseline and the independent
check of the variational solver in winder.paths.geodesic.

shoot: the two-point geodesic with N extra rounds by root finding on (heading, length). The Jacobian
    column in the length is the end velocity (exact); the column in the heading is a central
    difference of two neighbouring rays integrated together with the nominal ray in one system, so
    that all three share one step sequence and the difference carries no step-size noise (internal
    numerical differentiation). The ODE and the ray tracing are winder.paths.ode.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import field
from typing import Callable

import numpy as np

from winder.errors import ConfigError, SolverError
from winder.geometry.surface import SweepSurface
from winder.paths.headings import heading_of_velocity, tangent_basis, velocity_of_heading
from winder.paths.ode import check_start, fan_rhs

HEADING_STEP = 1e-6  # rad: half-width of the central difference in the heading (IND fan)
CONVERGED_RESIDUAL = 1e-9  # a shot converges when its end misses by <= this times max(length, 1 mm)
ON_MANDREL_SAMPLES = 2001  # dense samples checking that a shot path stays on the mandrel
SHOT_SAMPLES = 201  # equally spaced arc-length samples returned by shoot
GUESS_NODES, GUESS_PIECES = 8, 16  # Gauss-Legendre along the straight segment of the initial guess
MAX_SHOOT_EVALS = 200  # hybr fallback: fan integrations
MAX_NEWTON = 60  # Newton iterations (each one or more fan integrations)
MAX_HEADING_STEP = 0.5  # rad: a Newton step changes the heading by at most this much
RTOL_LEVELS = (1e-8,)  # coarser integrator tolerances used first, while the miss is large
LEVEL_GOAL = 10.0  # a coarse level ends when the miss is below this times its rtol times the length
RESIDUAL_GOAL = 10.0  # the final level ends when the miss is below this times tol times the length
STALL_RATIO = 0.5  # a Newton step reducing the miss by less than this factor ends a level ...
FLOOR_FACTOR = 1e4  # ... once the miss is below this times its rtol times the length (its floor)
LEAVE_TOL = 1e-6  # mm: a shot path this far past an end of the mandrel has left it


# -- two-point shooting ---------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True, eq=False)
class ShootResult:
    """A two-point geodesic found by shooting.

    heading_deg : winding angle at the start; length : arc length (mm).
    arc, s, theta : (m,) float, SHOT_SAMPLES samples equally spaced in arc length.
    sol : dense output of the final trace (arc length -> (s, theta)); state : -> (s, theta, s', theta').
    residual : distance (mm, in the metric at the end) between the traced end and the target.
    converged : the residual is <= CONVERGED_RESIDUAL * max(length, 1) and the path stays on the
        mandrel. left_mandrel : the path leaves s in [0, surface.length] by more than LEAVE_TOL (the
        surface formulas were continued past the ends while shooting).
    nfev : three-ray fan integrations (Newton and line search, or hybrj); seconds : wall time.
    success, status, message : scipy's result vocabulary.
    speed_error : max | |J u'| - 1 | at the final trace's steps.
    """

    heading_deg: float
    length: float
    arc: np.ndarray
    s: np.ndarray
    theta: np.ndarray
    sol: Callable[[np.ndarray], np.ndarray] = field(repr=False)
    state: Callable[[np.ndarray], np.ndarray] = field(repr=False)
    converged: bool
    residual: float
    left_mandrel: bool
    nfev: int
    message: str
    seconds: float
    speed_error: float

    @property
    def success(self) -> bool:
        return self.converged

    @property
    def status(self) -> int:
        """0 converged, 1 not converged, 2 the path leaves the mandrel."""
        return 2 if self.left_mandrel else (0 if self.converged else 1)


def initial_guess(surface: SweepSurface, start: tuple[float, float],
                  end: tuple[float, float]) -> tuple[float, float]:
    """(heading_deg, length) of the straight segment start -> end in the (s, theta) domain.

    The segment's velocity J du is split, along the segment, into its parts along the meridian (e1)
    and across it (e2); their integrals are the two legs of the "unrolled" segment. The heading is
    the angle of that unrolled segment (exact on any straight tube, and the metric at the start for a
    short segment) and its length the length guess (exact there too; the surface length of the
    segment itself would overestimate). Gauss-Legendre along the segment.
    end : (s, theta) with the extra rounds already added to theta.
    """
    s0, th0 = start
    du = np.array([end[0] - s0, end[1] - th0])
    x, w = np.polynomial.legendre.leggauss(GUESS_NODES)
    f = ((np.arange(GUESS_PIECES)[:, None] + 0.5 + 0.5 * x[None, :]) / GUESS_PIECES).ravel()
    weights = np.tile(w, GUESS_PIECES) * 0.5 / GUESS_PIECES
    ev = surface.evaluate(s0 + f * du[0], th0 + f * du[1], order=1)
    ns, along, width = tangent_basis(ev.ps, ev.pt)
    c1 = ns * du[0] + along * du[1]
    c2 = width * du[1]
    heading = np.arctan2(weights @ c2, weights @ c1)
    return float(np.degrees(heading)), float(np.hypot(weights @ c1, weights @ c2))


def _metric_factor(surface: SweepSurface, s: float, theta: float) -> np.ndarray:
    """Upper Cholesky factor R of the metric (R^T R = g): |R du| is the length of J du (mm)."""
    ev = surface.evaluate(np.array([s]), np.array([theta]), order=1)
    jac = np.stack([ev.ps[0], ev.pt[0]], axis=1)
    return np.linalg.cholesky(jac.T @ jac).T


def shoot(surface: SweepSurface, start: tuple[float, float], end: tuple[float, float], rounds: int = 0,
          guess: tuple[float, float] | None = None, tol: float = 1e-12) -> ShootResult:
    """The geodesic from start to end, each (s, theta_rad), end angle + 2 pi rounds, by shooting.

    Newton's method on (heading, length) so that the traced end hits the target, with a backtracking
    line search on the miss; if it stalls, MINPACK's hybrj (scipy.optimize.root 'hybr') from the
    best point. The miss is measured in mm (the metric at the target).
    guess : (heading_deg, length mm); default: initial_guess (the straight parameter-domain segment).
    tol : the integrator's rtol and atol on the final iterations (the first ones run at RTOL_LEVELS
        until the miss is near their accuracy floor).
    """
    t_start = time.perf_counter()
    s0, th0 = float(start[0]), float(start[1])
    s1, th1 = float(end[0]), float(end[1]) + 2.0 * np.pi * rounds
    check_start(surface, s0, "shoot start")
    check_start(surface, s1, "shoot end")
    if guess is None:
        guess = initial_guess(surface, (s0, th0), (s1, th1))
    if not (np.isfinite(guess[0]) and np.isfinite(guess[1]) and guess[1] > 0.0):
        raise ConfigError(f"shoot guess: (heading_deg, length > 0) expected, got {guess}")
    factor = _metric_factor(surface, s1, th1)
    target = np.array([s1, th1])
    scale = max(float(guess[1]), 1.0)  # mm: the length unknown is scaled to O(1)
    fun3 = fan_rhs(surface, 3)
    count = 0

    def evaluate(x: np.ndarray, rtol: float, dense: bool = False):
        """Miss (2,) mm, Jacobian (2, 2) in (heading rad, length / scale), dense output or None."""
        nonlocal count
        count += 1
        a, length = float(x[0]), float(x[1]) * scale
        heads = np.array([a, a - HEADING_STEP, a + HEADING_STEP])
        ds, dth = velocity_of_heading(surface, np.full(3, s0), np.full(3, th0), heads)
        y0 = np.concatenate([np.full(3, s0), np.full(3, th0), ds, dth])
        with np.errstate(all="ignore"):
            from scipy.integrate import solve_ivp  # noqa: PLC0415 - slow to import: only when shooting
            res = solve_ivp(fun3, (0.0, length), y0, method="DOP853", rtol=rtol, atol=rtol,
                            dense_output=dense, vectorized=True)
        yend = res.y[:, -1].reshape(4, 3)
        if res.status == -1 or not np.all(np.isfinite(yend)):
            return None, None, None
        miss = factor @ (yend[:2, 0] - target)
        d_heading = factor @ (yend[:2, 2] - yend[:2, 1]) / (2.0 * HEADING_STEP)
        d_length = factor @ yend[2:, 0] * scale
        return miss, np.column_stack([d_heading, d_length]), res

    x = np.array([np.radians(guess[0]), guess[1] / scale])
    levels = [r for r in RTOL_LEVELS if r > tol] + [tol]
    method = "newton"
    accepted = False
    miss = jac = res = None
    for rtol in levels:
        final = rtol == levels[-1]
        miss, jac, res = evaluate(x, rtol, dense=final)
        if miss is None:
            break
        for _ in range(MAX_NEWTON):
            norm = float(np.linalg.norm(miss))
            goal = (RESIDUAL_GOAL if final else LEVEL_GOAL) * rtol * max(float(x[1]) * scale, 1.0)
            if norm <= goal:
                accepted = final
                break
            try:
                step = np.linalg.solve(jac, -miss)
            except np.linalg.LinAlgError:
                break
            # Bound the step: at most MAX_HEADING_STEP rad in heading and half the length.
            lim = min(1.0, MAX_HEADING_STEP / max(abs(step[0]), 1e-300),
                      0.5 * x[1] / max(abs(step[1]), 1e-300))
            lam = lim
            found = False
            while lam > 1e-6 * lim:
                x_try = x + lam * step
                miss_t, jac_t, res_t = evaluate(x_try, rtol, dense=final)
                if miss_t is not None and np.linalg.norm(miss_t) < (1.0 - 1e-4 * lam) * norm:
                    found = True
                    break
                lam *= 0.5
            if not found:
                break
            x, miss, jac, res = x_try, miss_t, jac_t, res_t
            new = float(np.linalg.norm(miss))
            if new > STALL_RATIO * norm and new < FLOOR_FACTOR * rtol * max(float(x[1]) * scale, 1.0):
                break  # slow progress near this level's accuracy floor: go on to the next level
        if miss is None:
            break
    if miss is not None and not accepted:
        # At the accuracy floor a little above the goal: accept if within the converged bound.
        accepted = float(np.linalg.norm(miss)) <= CONVERGED_RESIDUAL * max(float(x[1]) * scale, 1.0)
    if not accepted:
        # Fall back to MINPACK from the best point, at full accuracy.
        method = "hybr"
        last = {}

        def fun(xx: np.ndarray):
            m, j, r = evaluate(xx, tol, dense=True)
            if m is None:
                m, j = np.full(2, 1e10), np.eye(2)
            last["x"], last["res"], last["miss"] = xx.copy(), r, m
            return m, j

        from scipy.optimize import root  # noqa: PLC0415 - slow to import: only when shooting
        sol = root(fun, x, jac=True, method="hybr", options={"xtol": 1e-15, "maxfev": MAX_SHOOT_EVALS})
        x = sol.x
        if not np.array_equal(last.get("x"), x):
            fun(x)
        miss, res = last["miss"], last["res"]
    if res is None or res.sol is None:
        raise SolverError("geodesic shooting failed: no trace reached the end point")
    heading, length = float(np.degrees(x[0])), float(x[1]) * scale
    residual = float(np.linalg.norm(miss))
    if not (np.isfinite(length) and length > 0.0):
        raise SolverError(f"geodesic shooting did not find a path (length {length:g} mm)")
    dense = res.sol

    def path(l):
        return dense(l)[[0, 3]]

    def path_state(l):
        return dense(l)[[0, 3, 6, 9]]

    check = np.linspace(0.0, length, ON_MANDREL_SAMPLES)
    s_check = np.concatenate([dense(check)[0], res.y[0]])
    left = bool(s_check.min() < -LEAVE_TOL or s_check.max() > surface.length + LEAVE_TOL)
    converged = residual <= CONVERGED_RESIDUAL * max(length, 1.0) and not left
    if left:
        message = "the geodesic through these points leaves the mandrel"
    elif converged:
        message = f"converged ({method}): the end is missed by {residual:.3g} mm"
    else:
        message = f"not converged ({method}): the end is missed by {residual:.3g} mm"
    arc = np.linspace(0.0, length, SHOT_SAMPLES)
    s_arc, th_arc = path(arc)
    st = dense(res.t)
    _, speed = heading_of_velocity(surface, st[0], st[3], st[6], st[9])
    return ShootResult(heading_deg=heading, length=length, arc=arc, s=s_arc, theta=th_arc, sol=path,
                       state=path_state,
                       converged=converged, residual=residual, left_mandrel=left, nfev=count, message=message,
                       seconds=time.perf_counter() - t_start, speed_error=float(np.max(np.abs(speed - 1.0))))

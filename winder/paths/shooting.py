"""Geodesic shooting: the geodesic ODE in the parameter domain (MATH.md 4).

This is the paper's Runge-Kutta baseline ("one point, one direction") and an independent check of
the variational solver in winder.paths.geodesic. A curve u(l) = (s(l), theta(l)) on the surface,
parametrized by arc length l, is a geodesic when its acceleration is normal to the surface:

    g u'' = -J^T (Phi_ss s'^2 + 2 Phi_st s' theta' + Phi_tt theta'^2),

J = [Phi_s, Phi_theta] (3 x 2), g = J^T J (the metric). The state is y = (s, theta, s', theta'); the
right-hand side (geodesic_rhs) works on a (4, k) array of k independent states at once, so that a fan
of rays is integrated in one solve_ivp call (with one step sequence).

Directions are given as the winding angle alpha (heading): the angle in the tangent plane from the
direction of increasing s (the meridian, Phi_s) toward increasing theta. The orthonormal tangent
basis is e1 = Phi_s / |Phi_s| and e2 = the unit part of Phi_theta orthogonal to e1.

Stations are the surface's internal station s in [0, surface.length] (the axial station t for every
mandrel except vessels; convert with surface.s_of_t / t_of_s).

trace: integrate from one point in one direction (DOP853, dense output), stopping where s leaves
    [0, surface.length].
shoot: the two-point geodesic with N extra rounds by root finding on (heading, length). The Jacobian
    column in the length is the end velocity (exact); the column in the heading is a central
    difference of two neighbouring rays integrated together with the nominal ray in one system, so
    that all three share one step sequence and the difference carries no step-size noise (internal
    numerical differentiation).
clairaut_constant: r sin(alpha) on a surface of revolution, conserved along every geodesic.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import root

from winder.errors import ConfigError, SolverError
from winder.geometry.surface import SweepSurface

HEADING_STEP = 1e-6  # rad: half-width of the central difference in the heading (IND fan)
STATION_TOL = 1e-9  # mm: a start station this far outside [0, length] is still on the mandrel
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


# -- the ODE ---------------------------------------------------------------------------------------------
def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("ij,ij->i", a, b)


def geodesic_rhs(surface: SweepSurface, y: np.ndarray) -> np.ndarray:
    """d/dl of the state y = (s, theta, s', theta'): (4,) or (4, k) float -> same shape.

    Each column is an independent state; the 2x2 metric systems are solved in closed form.
    """
    y = np.asarray(y, dtype=float)
    flat = y.ndim == 1
    y2 = y[:, None] if flat else y
    s, th, ds, dth = y2
    ev = surface.evaluate(s, th, order=2)
    acc = (ev.pss * (ds * ds)[:, None] + 2.0 * ev.pst * (ds * dth)[:, None]
           + ev.ptt * (dth * dth)[:, None])
    b0, b1 = -_dot(ev.ps, acc), -_dot(ev.pt, acc)
    g00, g01, g11 = _dot(ev.ps, ev.ps), _dot(ev.ps, ev.pt), _dot(ev.pt, ev.pt)
    det = g00 * g11 - g01 * g01
    out = np.empty_like(y2)
    out[0], out[1] = ds, dth
    out[2] = (g11 * b0 - g01 * b1) / det
    out[3] = (g00 * b1 - g01 * b0) / det
    return out[:, 0] if flat else out


def _tangent_basis(ps: np.ndarray, pt: np.ndarray):
    """|Phi_s|, e1.Phi_theta and |w|, w = the part of Phi_theta orthogonal to e1; each (m,)."""
    ns = np.linalg.norm(ps, axis=1)
    e1 = ps / ns[:, None]
    along = _dot(e1, pt)
    w = np.linalg.norm(pt - along[:, None] * e1, axis=1)
    return ns, along, w


def velocity_of_heading(surface: SweepSurface, s: np.ndarray, theta: np.ndarray,
                        heading_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameter velocity (s', theta') of the unit tangent vector at winding angle heading_rad.

    The unit vector d = cos(a) e1 + sin(a) e2 written as d = s' Phi_s + theta' Phi_theta.
    All arguments (m,) float (broadcast); returns two (m,) arrays.
    """
    s, theta, a = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, dtype=float))
                                        for v in (s, theta, heading_rad)))
    ev = surface.evaluate(s, theta, order=1)
    ns, along, w = _tangent_basis(ev.ps, ev.pt)
    dth = np.sin(a) / w
    ds = (np.cos(a) - dth * along) / ns
    return ds, dth


def heading_of_velocity(surface: SweepSurface, s: np.ndarray, theta: np.ndarray, ds: np.ndarray,
                        dtheta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Winding angle (rad, from the meridian toward increasing theta) and speed |J u'| (mm per unit).

    All arguments (m,) float (broadcast); returns two (m,) arrays.
    """
    s, theta, ds, dtheta = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, dtype=float))
                                                 for v in (s, theta, ds, dtheta)))
    ev = surface.evaluate(s, theta, order=1)
    ns, along, w = _tangent_basis(ev.ps, ev.pt)
    c1 = ns * ds + along * dtheta  # component along e1
    c2 = w * dtheta  # component along e2
    return np.arctan2(c2, c1), np.hypot(c1, c2)


def clairaut_constant(surface: SweepSurface, s: np.ndarray, theta: np.ndarray, ds: np.ndarray,
                      dtheta: np.ndarray) -> np.ndarray:
    """r sin(alpha) at points (s, theta) moving with parameter velocity (ds, dtheta): (m,) float, mm.

    r is the distance from the axis, alpha the angle from the meridian (signed: positive toward
    increasing theta). Constant along every geodesic of a surface of revolution (Clairaut).
    Raises SolverError if the surface is not one of revolution.
    """
    if not surface.is_revolution:
        raise SolverError(f"Clairaut's relation needs a surface of revolution (a straight axis and a "
                          f"circular section); the mandrel {surface.name!r} is not one")
    alpha, _ = heading_of_velocity(surface, s, theta, ds, dtheta)
    s_b = np.broadcast_arrays(np.atleast_1d(np.asarray(s, dtype=float)), alpha)[0]
    th_b = np.broadcast_arrays(np.atleast_1d(np.asarray(theta, dtype=float)), alpha)[0]
    return surface.radius(s_b, th_b) * np.sin(alpha)


# -- integration ------------------------------------------------------------------------------------------
def _fan_fun(surface: SweepSurface, k: int) -> Callable[[float, np.ndarray], np.ndarray]:
    """solve_ivp right-hand side of k rays stacked as y = (s_1..s_k, theta_1.., s'_1.., theta'_1..).

    vectorized=True: y may also be (4k, j), j states of the whole fan (each column a fan).
    """

    def fun(_l: float, y: np.ndarray) -> np.ndarray:
        if y.ndim == 1:
            return geodesic_rhs(surface, y.reshape(4, k)).reshape(-1)
        j = y.shape[1]
        z = y.reshape(4, k * j)  # row-major: column c of fan state is spread over k*j entries
        return geodesic_rhs(surface, z).reshape(4 * k, j)

    return fun


def _leave_events(surface: SweepSurface):
    def below(_l, y):
        return y[0]

    def above(_l, y):
        return y[0] - surface.length

    for ev, direction in ((below, -1.0), (above, 1.0)):
        ev.terminal = True
        ev.direction = direction
    return below, above


@dataclass(frozen=True)
class Trace:
    """A geodesic traced from one point in one direction.

    s, theta : (m,) float at the integrator's steps (theta unwrapped, radians); arc : (m,) their
    arc lengths (mm) from the start. length : the arc length reached (mm; shorter than asked if the
    path left the mandrel). sol : dense output, arc length (scalar or (k,)) -> array (2,) or (2, k)
    of (s, theta); state(l) gives the whole (4,) / (4, k) state (s, theta, s', theta').
    left_mandrel : the path reached s = 0 or s = surface.length before the asked length.
    speed_error : max | |J u'| - 1 | over the steps (the arc-length parametrization's drift).
    """

    s: np.ndarray
    theta: np.ndarray
    arc: np.ndarray
    length: float
    sol: Callable[[np.ndarray], np.ndarray]
    state: Callable[[np.ndarray], np.ndarray] = field(repr=False)
    left_mandrel: bool
    status: str
    heading_deg: float
    speed_error: float
    nfev: int


def _check_start(surface: SweepSurface, s: float, what: str) -> None:
    if not (np.isfinite(s) and -STATION_TOL <= s <= surface.length + STATION_TOL):
        raise ConfigError(f"{what}: the station s must lie on the mandrel, in [0, {surface.length:.6g}], "
                          f"got {s:g}")


def trace(surface: SweepSurface, start: tuple[float, float], heading_deg: float, length: float,
          rtol: float = 1e-12, atol: float = 1e-12, *, stop_at_ends: bool = True) -> Trace:
    """Trace the geodesic from start = (s, theta_rad) at winding angle heading_deg for length mm.

    heading_deg : from the direction of increasing s (the meridian) toward increasing theta.
    stop_at_ends : stop where s leaves [0, surface.length] (terminal events); otherwise the surface
        formulas are continued past the ends.
    """
    s0, th0 = float(start[0]), float(start[1])
    _check_start(surface, s0, "trace start")
    if not (np.isfinite(length) and length > 0.0):
        raise ConfigError(f"trace length: must be a number > 0 mm, got {length}")
    ds, dth = velocity_of_heading(surface, s0, th0, np.radians(heading_deg))
    y0 = np.array([s0, th0, ds[0], dth[0]])
    events = _leave_events(surface) if stop_at_ends else None
    res = solve_ivp(_fan_fun(surface, 1), (0.0, float(length)), y0, method="DOP853", rtol=rtol, atol=atol,
                    dense_output=True, events=events, vectorized=True)
    if res.status == -1:
        raise SolverError(f"geodesic tracing failed: {res.message}")
    left = res.status == 1
    arc = res.t
    s, th = res.y[0], res.y[1]
    _, speed = heading_of_velocity(surface, s, th, res.y[2], res.y[3])
    dense = res.sol
    if left:
        end = "t = 0" if s[-1] <= 0.5 * surface.length else f"s = {surface.length:.6g}"
        status = f"left the mandrel at {end} after {arc[-1]:.6g} of {length:.6g} mm"
    else:
        status = f"traced {length:.6g} mm"

    def sol(l):
        return dense(l)[:2]

    return Trace(s=s, theta=th, arc=arc, length=float(arc[-1]), sol=sol, state=dense, left_mandrel=left,
                 status=status, heading_deg=float(heading_deg),
                 speed_error=float(np.max(np.abs(speed - 1.0))),
                 nfev=int(res.nfev))


@dataclass(frozen=True)
class Fan:
    """k rays traced together from one start (one step sequence).

    arc : (m,) sample arc lengths; s, theta : (k, m) float. left_at : (k,) arc length where each ray
    first left [0, surface.length] (nan if it did not; its samples past that point are the
    continuation of the surface formulas, not the mandrel).
    """

    headings_deg: np.ndarray
    arc: np.ndarray
    s: np.ndarray
    theta: np.ndarray
    left_at: np.ndarray
    nfev: int


def trace_fan(surface: SweepSurface, start: tuple[float, float], headings_deg: np.ndarray, length: float,
              samples: int = 201, rtol: float = 1e-12, atol: float = 1e-12) -> Fan:
    """Trace rays at several headings from one start in one integration (e.g. for a planner)."""
    s0, th0 = float(start[0]), float(start[1])
    _check_start(surface, s0, "trace start")
    if not (np.isfinite(length) and length > 0.0):
        raise ConfigError(f"trace length: must be a number > 0 mm, got {length}")
    heads = np.atleast_1d(np.asarray(headings_deg, dtype=float))
    k = heads.size
    ds, dth = velocity_of_heading(surface, np.full(k, s0), np.full(k, th0), np.radians(heads))
    y0 = np.concatenate([np.full(k, s0), np.full(k, th0), ds, dth])
    res = solve_ivp(_fan_fun(surface, k), (0.0, float(length)), y0, method="DOP853", rtol=rtol, atol=atol,
                    dense_output=True, vectorized=True)
    if res.status == -1:
        raise SolverError(f"geodesic tracing failed: {res.message}")
    arc = np.linspace(0.0, float(length), samples)
    y = res.sol(arc).reshape(4, k, samples)
    left_at = np.full(k, np.nan)
    steps = res.y[:k]  # s of every ray at the integrator's steps, (k, n_steps)
    for i in range(k):
        out = (steps[i] < -STATION_TOL) | (steps[i] > surface.length + STATION_TOL)
        if np.any(out):
            j = int(np.argmax(out))
            left_at[i] = _exit_arc(surface, lambda l, i=i: res.sol(l)[i], res.t[j - 1], res.t[j])
    return Fan(heads, arc, y[0], y[1], left_at, int(res.nfev))


def _exit_arc(surface: SweepSurface, s_of: Callable[[float], float], lo: float, hi: float) -> float:
    """Arc length in [lo, hi] where s crosses 0 or surface.length (bisection on the dense output)."""
    side = 0.0 if s_of(hi) < 0.0 else surface.length
    f_lo = s_of(lo) - side
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        f = s_of(mid) - side
        if np.sign(f) == np.sign(f_lo):
            lo, f_lo = mid, f
        else:
            hi = mid
    return 0.5 * (lo + hi)


# -- two-point shooting ---------------------------------------------------------------------------------
@dataclass(frozen=True)
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
    status: str
    seconds: float
    speed_error: float


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
    ns, along, width = _tangent_basis(ev.ps, ev.pt)
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
    _check_start(surface, s0, "shoot start")
    _check_start(surface, s1, "shoot end")
    if guess is None:
        guess = initial_guess(surface, (s0, th0), (s1, th1))
    if not (np.isfinite(guess[0]) and np.isfinite(guess[1]) and guess[1] > 0.0):
        raise ConfigError(f"shoot guess: (heading_deg, length > 0) expected, got {guess}")
    factor = _metric_factor(surface, s1, th1)
    target = np.array([s1, th1])
    scale = max(float(guess[1]), 1.0)  # mm: the length unknown is scaled to O(1)
    fun3 = _fan_fun(surface, 3)
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
        status = "the geodesic through these points leaves the mandrel"
    elif converged:
        status = f"converged ({method}): the end is missed by {residual:.3g} mm"
    else:
        status = f"not converged ({method}): the end is missed by {residual:.3g} mm"
    arc = np.linspace(0.0, length, SHOT_SAMPLES)
    s_arc, th_arc = path(arc)
    st = dense(res.t)
    _, speed = heading_of_velocity(surface, st[0], st[3], st[6], st[9])
    return ShootResult(heading_deg=heading, length=length, arc=arc, s=s_arc, theta=th_arc, sol=path,
                       state=path_state,
                       converged=converged, residual=residual, left_mandrel=left, nfev=count, status=status,
                       seconds=time.perf_counter() - t_start, speed_error=float(np.max(np.abs(speed - 1.0))))

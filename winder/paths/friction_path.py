"""Two-point, N-round friction-held paths (docs/math/07-friction.md) by shooting the friction ODE (winder.paths.friction).

Formulation (and why). A geodesic between two points (with N rounds) is isolated: its ODE has two
free start data (heading, length) for two end conditions. A prescribed lambda(l) keeps that count,
so every lambda(l) gives its own path through the two points: the problem has a whole function of
freedom and needs a criterion. Friction paths are not minimizers of a length-like energy
(k_g = lambda k_n has no Lagrangian in general), so the variational method of docs/math/02-energy.md, docs/math/03-newton.md does not
extend to them; shooting (docs/math/04-checks.md) does. lambda is a low-degree Legendre polynomial in the
normalized arc length l / L (degree 0: constant lambda per pass, what a shop sets and what `slip:`
means); among the paths that hit the end point we take the one of least mean lambda^2 over the pass:
- it is zero exactly on the geodesic, so where a geodesic joins the points it is the answer; it is
  tried first (lambda = 0, unknowns heading and length: geodesic shooting);
- it is smooth in the unknowns (the least max |lambda| is not), so a Gauss-Newton SQP on
  (heading, length, coefficients) under the two end conditions converges from the geodesic guess;
- a planner spends the freedom on what coverage needs instead: a prescribed start heading (the
  layer's angle) or a prescribed constant slip makes the problem square, unknowns (length, lambda)
  or (heading, length); the lambda found is then the least mu holding that path, the only one.
The result reports max |k_g / k_n| and min k_n measured from the sampled path itself
(winder.geometry.curvature, exact surface normal), not the lambda the ODE was given.

Jacobians: every unknown's column is a central difference of two neighbouring rays integrated with
the nominal ray in one system over the normalized arc sigma = l / L in [0, 1] (each ray its own
length and lambda), so all share one step sequence (internal numerical differentiation).
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from numpy.polynomial import legendre

from winder.geometry.curvature import path_curvatures, slip_and_margin
from winder.errors import ConfigError
from winder.paths.friction import friction_rhs
from winder.paths.headings import heading_of_velocity, velocity_of_heading
from winder.paths.shooting import initial_guess
from winder.geometry.surface import SweepSurface

DIFF_STEP = 1e-6  # central-difference half-step of every unknown (rad, length / scale, lambda)
RTOL_LEVELS = (1e-8,)  # coarse integrator tolerances used first, while the miss is large
MAX_ITER = 40  # SQP iterations per level
MAX_HEADING_STEP = 0.5  # rad: a step changes the heading by at most this
MAX_SLIP_STEP = 0.5  # and a lambda coefficient by at most this
CONVERGED_RESIDUAL = 1e-9  # converged: the end is missed by <= this times max(length, 1 mm)
LEVEL_GOAL = 10.0  # a coarse level ends when the miss is below this times its rtol times the length
COEF_TOL = 1e-10  # ... and the lambda coefficients move by less than this
LEAVE_TOL = 1e-6  # mm: a path this far past an end of the mandrel has left it
SLIP_MEASURE_TOL = 1e-6  # the measured |k_g / k_n| may exceed mu by this (its own error)
SAMPLES = 401  # samples of the result, equally spaced in arc length
MEASURE_SAMPLES = 2001  # samples the slip and k_n are measured on (the spline's end error is O(h^4))
GEODESIC_SLIP = 1e-12  # |lambda| below this everywhere: a geodesic
ARMIJO = 1e-4


class Status:
    """FrictionResult.status codes."""

    OK = 0
    NOT_CONVERGED = 1
    LEFT_MANDREL = 2
    BRIDGES = 3
    SLIPS = 4


@dataclasses.dataclass(frozen=True, eq=False)
class FrictionResult:
    """A two-point friction-held path (scipy vocabulary: success, status, message, nit, nfev).

    t, s, theta, arc : (m,) float at SAMPLES points equally spaced in arc length: axial station (mm),
        internal station, unwrapped angle (rad), arc length (mm). points : (m, 3) xyz (mm).
    slip : (m,) float, the lambda the ODE used there; slip_coefficients : its Legendre coefficients
        in 2 l / L - 1. length : mm; heading_deg, end_heading_deg : winding angles at both ends.
    max_slip : max |k_g / k_n| and min_normal_curvature : min k_n (1/mm), both measured from the
        sampled path (winder.geometry.curvature), inf / <= 0 where the fiber bridges.
    residual : mm, distance of the traced end from the target. geodesic : lambda = 0 throughout.
    status : Status code; success : status == Status.OK (on the mandrel, pressing, |lambda| <= mu).
    """

    success: bool
    status: int
    message: str
    nit: int
    nfev: int
    t: np.ndarray
    s: np.ndarray
    theta: np.ndarray
    arc: np.ndarray
    points: np.ndarray
    slip: np.ndarray
    slip_coefficients: np.ndarray
    length: float
    heading_deg: float
    end_heading_deg: float
    max_slip: float
    min_normal_curvature: float
    residual: float
    geodesic: bool
    seconds: float


class _Shooter:
    """Fan integrations of rays (heading, length, lambda coefficients) from one start."""

    def __init__(self, surface: SweepSurface, s0: float, th0: float, target: np.ndarray, scale: float):
        self.surface, self.s0, self.th0, self.target, self.scale = surface, s0, th0, target, scale
        ev = surface.evaluate(target[:1], target[1:], order=1)
        jac = np.stack([ev.ps[0], ev.pt[0]], axis=1)
        self.factor = np.linalg.cholesky(jac.T @ jac).T  # |factor du| = mm at the target
        self.nfev = 0

    def run(self, z: np.ndarray, rtol: float, dense: bool = False):
        """Integrate the rays of the columns of z (2 + d + 1, k): returns solve_ivp's result or None."""
        self.nfev += 1
        k = z.shape[1]
        lengths, coefs = z[1] * self.scale, z[2:]
        ds, dth = velocity_of_heading(self.surface, np.full(k, self.s0), np.full(k, self.th0), z[0])
        y0 = np.concatenate([np.full(k, self.s0), np.full(k, self.th0), ds, dth])

        def fun(sigma: float, y: np.ndarray) -> np.ndarray:
            slip = legendre.legval(2.0 * sigma - 1.0, coefs)
            return (friction_rhs(self.surface, y.reshape(4, k), slip) * lengths).reshape(-1)

        with np.errstate(all="ignore"):
            from scipy.integrate import solve_ivp  # noqa: PLC0415 - slow to import: only when tracing
            res = solve_ivp(fun, (0.0, 1.0), y0, method="DOP853", rtol=rtol, atol=rtol, dense_output=dense)
        if res.status == -1 or not np.all(np.isfinite(res.y[:, -1])):
            return None
        return res

    def miss(self, z: np.ndarray, free: np.ndarray, rtol: float, dense: bool = False):
        """End miss (2,) mm, its Jacobian (2, n_free) and the nominal ray's result, or Nones."""
        nf = int(free.sum())
        cols = np.repeat(z[:, None], 1 + 2 * nf, axis=1)
        idx = np.flatnonzero(free)
        cols[idx, 1 + np.arange(nf)] -= DIFF_STEP
        cols[idx, 1 + nf + np.arange(nf)] += DIFF_STEP
        res = self.run(cols, rtol, dense)
        if res is None:
            return None, None, None
        k = cols.shape[1]
        end = res.y[:, -1].reshape(4, k)[:2]
        delta = self.factor @ (end - self.target[:, None])
        jac = (delta[:, 1 + nf:] - delta[:, 1:1 + nf]) / (2.0 * DIFF_STEP)
        return delta[:, 0], jac, res


def _step(jac: np.ndarray, miss: np.ndarray, z: np.ndarray, free: np.ndarray, weights: np.ndarray):
    """SQP step (Gauss-Newton on the constraints) for min 1/2 c^T W c subject to miss(z) = 0.

    Returns (step over the free unknowns, multipliers) or (None, None) if singular."""
    nf = jac.shape[1]
    q = np.diag(weights[free])
    rhs = -q @ z[free]
    if nf == 2:
        try:
            return np.linalg.solve(jac, -miss), np.zeros(2)
        except np.linalg.LinAlgError:
            return None, None
    kkt = np.block([[q, jac.T], [jac, np.zeros((2, 2))]])
    try:
        sol = np.linalg.solve(kkt, np.concatenate([rhs, -miss]))
    except np.linalg.LinAlgError:
        return None, None
    return sol[:nf], sol[nf:]


def _solve(shooter: _Shooter, z: np.ndarray, free: np.ndarray, tol: float) -> tuple[np.ndarray, object, int]:
    """SQP iterations at the integrator levels; returns (z, nominal dense result or None, iterations)."""
    weights = np.concatenate([[0.0, 0.0], 1.0 / (2.0 * np.arange(z.size - 2) + 1.0)])
    levels = [r for r in RTOL_LEVELS if r > tol] + [tol]
    nit, res = 0, None
    for rtol in levels:
        final = rtol == levels[-1]
        miss, jac, res = shooter.miss(z, free, rtol, dense=final)
        if miss is None:
            return z, None, nit
        rho = 1.0
        for _ in range(MAX_ITER):
            length = z[1] * shooter.scale
            goal = (CONVERGED_RESIDUAL if final else LEVEL_GOAL * rtol) * max(length, 1.0)
            step, mult = _step(jac, miss, z, free, weights)
            if step is None:
                break
            coef_step = np.abs(step[np.flatnonzero(free) >= 2]).max(initial=0.0)
            if np.linalg.norm(miss) <= goal and coef_step <= COEF_TOL:
                break
            nit += 1
            rho = max(rho, 2.0 * float(np.abs(mult).max(initial=0.0)))
            full = np.zeros_like(z)
            full[free] = step
            lim = min(1.0, MAX_HEADING_STEP / max(abs(full[0]), 1e-300), 0.5 * z[1] / max(abs(full[1]), 1e-300),
                      MAX_SLIP_STEP / max(np.abs(full[2:]).max(), 1e-300))

            # Exact-penalty merit; a square problem (no objective) only reduces the miss.
            w_merit = weights if free.sum() > 2 else np.zeros_like(weights)

            def merit(zz: np.ndarray, mm: np.ndarray) -> float:
                return 0.5 * float(w_merit @ zz**2) + rho * float(np.linalg.norm(mm))

            m0 = merit(z, miss)
            slope = float((w_merit * z) @ full) - rho * float(np.linalg.norm(miss))
            alpha, accepted = lim, False
            while alpha > 1e-6 * lim:
                miss_t, jac_t, res_t = shooter.miss(z + alpha * full, free, rtol, dense=final)
                if miss_t is not None and merit(z + alpha * full, miss_t) <= m0 + ARMIJO * alpha * min(slope, 0.0):
                    accepted = True
                    break
                alpha *= 0.5
            if not accepted:
                break
            z, miss, jac, res = z + alpha * full, miss_t, jac_t, res_t
    return z, res, nit


def _check_station(surface: SweepSurface, t: float, what: str) -> None:
    if not (np.isfinite(t) and surface.t_start - 1e-9 <= t <= surface.axial_length + 1e-9):
        raise ConfigError(f"{what}: t must lie on the mandrel, in [{surface.t_start:.6g}, "
                          f"{surface.axial_length:.6g}] mm, got {t:g}")


def friction_path(surface: SweepSurface, start: tuple[float, float], end: tuple[float, float], *,
                  rounds: int = 0, mu: float = 0.2, heading_deg: float | None = None,
                  slip: float | None = None, degree: int = 0, guess: tuple[float, float] | None = None,
                  tol: float = 1e-12) -> FrictionResult:
    """The friction-held path from start to end, each (t mm, theta rad), end angle + 2 pi rounds.

    heading_deg : prescribed start winding angle; the unknowns are then the length and lambda's
        coefficients (square for degree 0). slip : prescribed constant lambda; unknowns heading and
        length. Neither: the geodesic if it joins the points on the mandrel, else the least mean
        lambda^2 path with a free heading. degree : lambda's polynomial degree in l / L.
    mu : the friction limit the result is judged by (success needs |lambda| <= mu, measured).
    guess : (heading_deg, length mm) to start from; default the straight segment in (s, theta).
    tol : the integrator's rtol and atol on the final iterations.
    """
    t_start = time.perf_counter()
    _check_station(surface, start[0], "friction path start")
    _check_station(surface, end[0], "friction path end")
    if heading_deg is not None and slip is not None:
        raise ConfigError("friction path: give a start heading or a slip, not both (one is solved for)")
    if not 0 <= degree <= 8:
        raise ConfigError(f"friction path: degree must be in 0..8, got {degree}")
    s0, s1 = (float(v) for v in surface.s_of_t(np.array([start[0], end[0]])))
    th0, th1 = float(start[1]), float(end[1]) + 2.0 * np.pi * rounds
    g_heading, g_length = guess if guess is not None else initial_guess(surface, (s0, th0), (s1, th1))
    if not (np.isfinite(g_length) and g_length > 0.0):
        raise ConfigError(f"friction path guess: (heading_deg, length > 0) expected, got {guess}")
    scale = max(float(g_length), 1.0)
    shooter = _Shooter(surface, s0, th0, np.array([s1, th1]), scale)
    z = np.zeros(3 + degree)
    z[0] = np.radians(heading_deg if heading_deg is not None else g_heading)
    z[1] = g_length / scale
    free = np.ones(z.size, dtype=bool)
    nit = 0
    if heading_deg is not None:
        free[0] = False
    elif slip is not None:
        z[2] = float(slip)
        free[2:] = False
    else:
        # The least mean lambda^2 is zero on a geodesic: try it first.
        free[2:] = False
        z_geo, res, nit = _solve(shooter, z.copy(), free, tol)
        out = _result(shooter, z_geo, res, nit, mu, t_start)
        if out.status in (Status.OK, Status.BRIDGES, Status.SLIPS):
            return out
        free[2:] = True
    z, res, more = _solve(shooter, z, free, tol)
    return _result(shooter, z, res, nit + more, mu, t_start)


def _result(shooter: _Shooter, z: np.ndarray, res, nit: int, mu: float, t_start: float) -> FrictionResult:
    surface = shooter.surface
    length = float(z[1] * shooter.scale)
    coefs = z[2:].copy()
    if res is None or res.sol is None:
        nan = np.full(1, np.nan)
        return FrictionResult(False, Status.NOT_CONVERGED, "no ray of the fan could be integrated to the end",
                              nit, shooter.nfev, nan, nan, nan, nan, np.full((1, 3), np.nan), nan, coefs,
                              length, float(np.degrees(z[0])), float("nan"), float("inf"), float("-inf"),
                              float("inf"), False, time.perf_counter() - t_start)
    k = res.y.shape[0] // 4
    sigma = np.linspace(0.0, 1.0, SAMPLES)
    state = res.sol(sigma)[[0, k, 2 * k, 3 * k]]
    s, th = state[0], state[1]
    end = res.y[:, -1].reshape(4, k)[:2, 0]
    residual = float(np.linalg.norm(shooter.factor @ (end - shooter.target)))
    arc = sigma * length
    lam = legendre.legval(2.0 * sigma - 1.0, coefs)
    fine = np.linspace(0.0, 1.0, MEASURE_SAMPLES)
    s_fine, th_fine = res.sol(fine)[[0, k]]
    k_n, k_g = path_curvatures(surface, fine * length, s_fine, th_fine)
    max_slip, min_kn = slip_and_margin(k_n, k_g)
    end_heading, _ = heading_of_velocity(surface, s[-1:], th[-1:], state[2, -1:], state[3, -1:])
    left = bool(s.min() < -LEAVE_TOL or s.max() > surface.length + LEAVE_TOL)
    worst = float(np.abs(lam).max())
    if residual > CONVERGED_RESIDUAL * max(length, 1.0) * 10.0:
        status, message = Status.NOT_CONVERGED, f"not converged: the end is missed by {residual:.3g} mm"
    elif left:
        status, message = Status.LEFT_MANDREL, "the path between these points leaves the mandrel"
    elif min_kn <= 0.0:
        i = int(np.argmin(k_n))
        status = Status.BRIDGES
        where = float(surface.t_of_s(s_fine[i:i + 1])[0])
        message = (f"the fiber bridges (k_n = {min_kn:.3g} /mm) at t = {where:.4g} "
                   f"mm: no friction holds it there")
    elif worst > mu or max_slip > mu + SLIP_MEASURE_TOL:
        status = Status.SLIPS
        message = f"the path needs |k_g / k_n| up to {max(worst, max_slip):.3g}, above the friction {mu:g}"
    else:
        status = Status.OK
        message = f"converged: the end is missed by {residual:.3g} mm, |k_g / k_n| <= {max_slip:.3g}"
    pts = surface.points(s, th)
    return FrictionResult(
        success=status == Status.OK, status=status, message=message, nit=nit, nfev=shooter.nfev,
        t=surface.t_of_s(s), s=s, theta=th, arc=arc, points=pts, slip=lam, slip_coefficients=coefs,
        length=length, heading_deg=float(np.degrees(z[0])), end_heading_deg=float(np.degrees(end_heading[0])),
        max_slip=max_slip, min_normal_curvature=min_kn, residual=residual, geodesic=worst < GEODESIC_SLIP,
        seconds=time.perf_counter() - t_start)

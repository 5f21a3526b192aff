"""The geodesic ODE in the parameter domain (docs/math/04-checks.md); friction-held paths (docs/math/07-friction.md) belong here too.

This is the paper's Runge-Kutta baseline ("one point, one direction") and an independent check of
the variational solver in winder.paths.geodesic. A curve u(l) = (s(l), theta(l)) on the surface,
parametrized by arc length l, is a geodesic when its acceleration is normal to the surface:

    g u'' = -J^T (Phi_ss s'^2 + 2 Phi_st s' theta' + Phi_tt theta'^2),

J = [Phi_s, Phi_theta] (3 x 2), g = J^T J (the metric). The state is y = (s, theta, s', theta'); the
right-hand side (geodesic_rhs) works on a (4, k) array of k independent states at once, so that a fan
of rays is integrated in one solve_ivp call (with one step sequence).

Directions are given as the winding angle alpha (heading; see winder.paths.headings).

Stations are the surface's internal station s in [0, surface.length] (the axial station t for every
mandrel except vessels; convert with surface.s_of_t / t_of_s).

trace: integrate from one point in one direction (DOP853, dense output), stopping where s leaves
    [0, surface.length].
trace_fan: a fan of rays from one point in one solve_ivp call. Two-point shooting on top of these
    is winder.paths.shooting.
Headings and the Clairaut constant (winder.paths.headings) convert between winding angles and
parameter velocities.
"""

from __future__ import annotations

import dataclasses
from dataclasses import field
from typing import Callable

import numpy as np

from winder.errors import ConfigError, SolverError
from winder.geometry.surface import SweepSurface
from winder.paths.headings import heading_of_velocity, row_dot, velocity_of_heading

STATION_TOL = 1e-9  # mm: a start station this far outside [0, length] is still on the mandrel


# -- the ODE ---------------------------------------------------------------------------------------------
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
    b0, b1 = -row_dot(ev.ps, acc), -row_dot(ev.pt, acc)
    g00, g01, g11 = row_dot(ev.ps, ev.ps), row_dot(ev.ps, ev.pt), row_dot(ev.pt, ev.pt)
    det = g00 * g11 - g01 * g01
    out = np.empty_like(y2)
    out[0], out[1] = ds, dth
    out[2] = (g11 * b0 - g01 * b1) / det
    out[3] = (g00 * b1 - g01 * b0) / det
    return out[:, 0] if flat else out


# -- integration ------------------------------------------------------------------------------------------
def fan_rhs(surface: SweepSurface, k: int) -> Callable[[float, np.ndarray], np.ndarray]:
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


@dataclasses.dataclass(frozen=True, eq=False)
class Trace:
    """A geodesic traced from one point in one direction.

    s, theta : (m,) float at the integrator's steps (theta unwrapped, radians); arc : (m,) their
    arc lengths (mm) from the start. length : the arc length reached (mm; shorter than asked if the
    path left the mandrel). sol : dense output, arc length (scalar or (k,)) -> array (2,) or (2, k)
    of (s, theta); state(l) gives the whole (4,) / (4, k) state (s, theta, s', theta').
    left_mandrel : the path reached s = 0 or s = surface.length before the asked length.
    success, status, message, nfev : scipy's result vocabulary (nfev: right-hand side evaluations).
    speed_error : max | |J u'| - 1 | over the steps (the arc-length parametrization's drift).
    """

    s: np.ndarray
    theta: np.ndarray
    arc: np.ndarray
    length: float
    sol: Callable[[np.ndarray], np.ndarray]
    state: Callable[[np.ndarray], np.ndarray] = field(repr=False)
    left_mandrel: bool
    message: str
    heading_deg: float
    speed_error: float
    nfev: int

    @property
    def success(self) -> bool:
        """The whole asked length was traced on the mandrel."""
        return not self.left_mandrel

    @property
    def status(self) -> int:
        """0 traced the asked length, 1 left the mandrel first (solve_ivp's event code)."""
        return 1 if self.left_mandrel else 0


def check_start(surface: SweepSurface, s: float, what: str) -> None:
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
    check_start(surface, s0, "trace start")
    if not (np.isfinite(length) and length > 0.0):
        raise ConfigError(f"trace length: must be a number > 0 mm, got {length}")
    ds, dth = velocity_of_heading(surface, s0, th0, np.radians(heading_deg))
    y0 = np.array([s0, th0, ds[0], dth[0]])
    events = _leave_events(surface) if stop_at_ends else None
    from scipy.integrate import solve_ivp  # noqa: PLC0415 - slow to import: only when tracing
    res = solve_ivp(fan_rhs(surface, 1), (0.0, float(length)), y0, method="DOP853", rtol=rtol, atol=atol,
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
        message = f"left the mandrel at {end} after {arc[-1]:.6g} of {length:.6g} mm"
    else:
        message = f"traced {length:.6g} mm"

    def sol(l):
        return dense(l)[:2]

    return Trace(s=s, theta=th, arc=arc, length=float(arc[-1]), sol=sol, state=dense, left_mandrel=left,
                 message=message, heading_deg=float(heading_deg),
                 speed_error=float(np.max(np.abs(speed - 1.0))),
                 nfev=int(res.nfev))


@dataclasses.dataclass(frozen=True, eq=False)
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
    check_start(surface, s0, "trace start")
    if not (np.isfinite(length) and length > 0.0):
        raise ConfigError(f"trace length: must be a number > 0 mm, got {length}")
    heads = np.atleast_1d(np.asarray(headings_deg, dtype=float))
    k = heads.size
    ds, dth = velocity_of_heading(surface, np.full(k, s0), np.full(k, th0), np.radians(heads))
    y0 = np.concatenate([np.full(k, s0), np.full(k, th0), ds, dth])
    from scipy.integrate import solve_ivp  # noqa: PLC0415 - slow to import: only when tracing
    res = solve_ivp(fan_rhs(surface, k), (0.0, float(length)), y0, method="DOP853", rtol=rtol, atol=atol,
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


def reach_station(surface: SweepSurface, s0: float, thetas: np.ndarray, heading_deg: float, s_target: float,
                  length: float, rtol: float = 1e-12, atol: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
    """(theta at s_target, the farthest station reached): the geodesics from (s0, thetas[i]) (k,) at
    heading_deg, integrated as one system so that each surface evaluation takes all k points (on a
    spline axis the evaluations one point at a time were most of a plan's time). A ray is held where it
    crossed s_target (its derivatives 0 past it; the step control resolves the kink), the integration
    stops when the last one crosses; theta is nan for a ray that turned around first (its farthest
    station says where), the stations are clamped to the mandrel for the evaluations."""
    thetas = np.atleast_1d(np.asarray(thetas, dtype=float))
    k = thetas.size
    check_start(surface, s0, "trace start")
    sign = 1.0 if s_target >= s0 else -1.0
    ds, dth = velocity_of_heading(surface, np.full(k, s0), thetas, np.full(k, np.radians(heading_deg)))
    y0 = np.concatenate([np.full(k, float(s0)), thetas, ds, dth])

    def fun(_l: float, y: np.ndarray) -> np.ndarray:
        z = y.reshape(4, -1).copy()  # the k rays (of each of y's columns) side by side
        past = sign * (z[0] - s_target) >= 0.0
        z[0] = np.clip(z[0], 0.0, surface.length)
        out = geodesic_rhs(surface, z)
        out[:, past] = 0.0
        return out.reshape(y.shape)

    def last(_l: float, y: np.ndarray) -> float:  # > 0 while a ray has not crossed s_target
        return float(np.max(sign * (s_target - y[:k])))

    last.terminal, last.direction = True, -1.0
    from scipy.integrate import solve_ivp  # noqa: PLC0415 - slow to import: only when tracing
    from scipy.optimize import brentq  # noqa: PLC0415

    res = solve_ivp(fun, (0.0, float(length)), y0, method="DOP853", rtol=rtol, atol=atol, dense_output=True,
                    events=(last,), vectorized=True)
    if res.status == -1:
        raise SolverError(f"geodesic tracing failed: {res.message}")
    out = np.full(k, np.nan)
    farthest = res.y[:k].max(axis=1) if sign > 0 else res.y[:k].min(axis=1)
    near = STATION_TOL * (1.0 + abs(s_target))  # the terminal event stops within round-off short of it
    for i in range(k):
        hit = np.flatnonzero(sign * (res.y[i] - s_target) >= -near)
        if hit.size == 0:
            continue
        j = int(hit[0])
        if j == 0 or abs(res.y[i, j] - s_target) <= near:
            out[i] = res.y[k + i, j]
            continue
        l_hit = brentq(lambda l, i=i: res.sol(l)[i] - s_target, res.t[j - 1], res.t[j], xtol=1e-12)
        out[i] = res.sol(l_hit)[k + i]
    return out, farthest

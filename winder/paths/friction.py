"""Friction-held fiber paths on the sweep surface (docs/math/07-friction.md): the geodesic ODE plus a sideways force.

A fiber under tension stays where it is laid while |k_g| <= mu k_n (Coulomb friction, k_n > 0: it
presses). With the slippage coefficient lambda = k_g / k_n prescribed, a unit-speed path
u(l) = (s(l), theta(l)) obeys

    u''^k + Gamma^k_ij u'^i u'^j = lambda k_n nu^k,   k_n = b_ij u'^i u'^j,

nu = N x T the tangent-plane normal to the fiber, N = Phi_s x Phi_theta / |...| (into the mandrel).
In the form shooting uses (g the metric, J = [Phi_s, Phi_theta], a = Phi_ij u'^i u'^j):

    g u'' = -J^T a + lambda (N . a) sqrt(det g) (-theta', s'),

because J^T (N x J u') = sqrt(det g) (-theta', s'). The forcing is normal to T, so the unit speed is
kept. One code path serves every axis, profile and section; nothing assumes a surface of revolution.

The two-point friction path, and the formulation chosen for it, are in winder.paths.friction_path.

Stations here are the internal station s (the axial t except on vessels), as in winder.paths.shooting.
"""

from __future__ import annotations

import dataclasses
from dataclasses import field
from typing import Callable

import numpy as np

from winder.errors import ConfigError, SolverError
from winder.paths.headings import heading_of_velocity, velocity_of_heading
from winder.geometry.surface import SweepSurface

Slip = float | Callable[[float], float]
STATION_TOL = 1e-9  # mm: a start this far outside [0, length] is still on the mandrel
ALONG_TOL = 1e-9  # |cos(heading)| below this starts on the parallel: traced by the ODE, which decides the turn
CLOSED_FORM_SAMPLES = 65  # the closed-form trace's (s, theta, arc) samples; its state is exact everywhere


# -- the ODE --------------------------------------------------------------------------------------------
def friction_rhs(surface: SweepSurface, y: np.ndarray, slip: float | np.ndarray) -> np.ndarray:
    """d/dl of y = (s, theta, s', theta'): (4,) or (4, k) float -> same shape; slip scalar or (k,)."""
    y = np.asarray(y, dtype=float)
    y2 = y[:, None] if y.ndim == 1 else y
    s, th, ds, dth = y2
    ev = surface.evaluate(s, th, order=2)
    acc = ev.pss * (ds * ds)[:, None] + 2.0 * ev.pst * (ds * dth)[:, None] + ev.ptt * (dth * dth)[:, None]
    cross = np.cross(ev.ps, ev.pt)
    root = np.linalg.norm(cross, axis=1)  # sqrt(det g)
    force = np.asarray(slip, dtype=float) * np.einsum("ij,ij->i", cross, acc)  # lambda k_n sqrt(det g)
    rhs0 = -np.einsum("ij,ij->i", ev.ps, acc) - force * dth
    rhs1 = -np.einsum("ij,ij->i", ev.pt, acc) + force * ds
    g00, g01, g11 = (np.einsum("ij,ij->i", a, b) for a, b in ((ev.ps, ev.ps), (ev.ps, ev.pt), (ev.pt, ev.pt)))
    det = root * root
    out = np.stack([ds, dth, (g11 * rhs0 - g01 * rhs1) / det, (g00 * rhs1 - g01 * rhs0) / det])
    return out[:, 0] if y.ndim == 1 else out


def _slip_at(slip: Slip, arc: float) -> float:
    return float(slip(arc)) if callable(slip) else float(slip)


# -- tracing ----------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True, eq=False)
class FrictionTrace:
    """A friction-held path traced from one point in one direction.

    s, theta, arc : (m,) float at the integrator's steps (theta unwrapped, rad; arc in mm).
    state : dense output, arc length -> (4,) or (4, j) state (s, theta, s', theta').
    length : the arc length reached (mm). event : "length" (traced as far as asked), "end" (reached
    s = 0 or s = surface.length) or "turnaround" (the fiber crossed the parallel: heading 90 deg).
    turnaround_radius : surface.radius at the turnaround (mm; the distance from the axis on a surface
    of revolution), None otherwise. speed_error : max | |J u'| - 1 | over the steps.
    """

    s: np.ndarray
    theta: np.ndarray
    arc: np.ndarray
    state: Callable[[np.ndarray], np.ndarray] = field(repr=False)
    length: float
    event: str
    turnaround_radius: float | None
    heading_deg: float
    speed_error: float
    nfev: int


def _meridian_component(surface: SweepSurface, y: np.ndarray) -> float:
    """Phi_s . (J u'): zero where the fiber runs along the parallel (a turnaround)."""
    ev = surface.evaluate(np.array([y[0]]), np.array([y[1]]), order=1)
    return float(ev.ps[0] @ (ev.ps[0] * y[2] + ev.pt[0] * y[3]))


def _events(surface: SweepSurface, y0: np.ndarray, slip: Slip, ends: bool, turnaround: bool) -> list:
    events = []
    if ends:
        for side, direction in ((0.0, -1.0), (surface.length, 1.0)):
            def leave(_l, y, side=side):
                return y[0] - side
            leave.terminal, leave.direction = True, direction
            events.append(leave)
    if turnaround:
        c0 = _meridian_component(surface, y0)
        if abs(c0) < 1e-12:  # starting on the turnaround: the sign it takes next decides
            c0 = _meridian_component(surface, y0 + 1e-6 * friction_rhs(surface, y0, _slip_at(slip, 0.0)))

        def turn(_l, y):
            return _meridian_component(surface, y)
        turn.terminal, turn.direction = True, -float(np.sign(c0))
        events.append(turn)
    return events


def trace_friction(surface: SweepSurface, start: tuple[float, float], heading_deg: float, slip: Slip,
                   length: float, *, rtol: float = 1e-12, atol: float = 1e-12, stop_at_ends: bool = True,
                   stop_at_turnaround: bool = False) -> FrictionTrace:
    """Trace from start = (s, theta_rad) at winding angle heading_deg with slippage slip for length mm.

    slip : lambda = k_g / k_n, a number or a function of the arc length (mm) from the start; positive
        lambda turns the fiber toward larger heading (as shooting's heading: from the meridian toward
        increasing theta). On a circular cylinder with a constant slip, the closed form
        (winder.paths.friction_cylinder); elsewhere scipy.integrate.solve_ivp (DOP853), dense output.
    stop_at_ends : stop where s leaves [0, surface.length]. stop_at_turnaround : stop where the fiber
        first runs along the parallel (heading +-90 deg: the turnaround on a surface of revolution).
    """
    s0, th0 = float(start[0]), float(start[1])
    if not (np.isfinite(s0) and -STATION_TOL <= s0 <= surface.length + STATION_TOL):
        raise ConfigError(f"trace start: the station s must lie on the mandrel, in [0, {surface.length:.6g}], "
                          f"got {s0:g}")
    if not (np.isfinite(length) and length > 0.0):
        raise ConfigError(f"trace length: must be a number > 0 mm, got {length}")
    if not callable(slip) and surface.cylinder_radius is not None and abs(np.cos(np.radians(heading_deg))) > ALONG_TOL:
        return _cylinder_trace(surface, s0, th0, heading_deg, float(slip), float(length), stop_at_ends,
                               stop_at_turnaround)
    return _integrated_trace(surface, s0, th0, heading_deg, slip, length, rtol, atol, stop_at_ends, stop_at_turnaround)


def _cylinder_trace(surface: SweepSurface, s0: float, th0: float, heading_deg: float, slip: float, length: float,
                    ends: bool, turnaround: bool) -> FrictionTrace:
    """trace_friction on a circular cylinder: the closed form of winder.paths.friction_cylinder."""
    from winder.paths.friction_cylinder import cylinder_path  # noqa: PLC0415

    radius = surface.cylinder_radius
    state, reached, event = cylinder_path(radius, surface.length, s0, th0, heading_deg, slip, length, ends, turnaround)
    arc = np.linspace(0.0, reached, CLOSED_FORM_SAMPLES)
    y = state(arc)
    return FrictionTrace(s=y[0], theta=y[1], arc=arc, state=state, length=reached, event=event,
                         turnaround_radius=radius if event == "turnaround" else None, heading_deg=float(heading_deg),
                         speed_error=0.0, nfev=0)


def _integrated_trace(surface: SweepSurface, s0: float, th0: float, heading_deg: float, slip: Slip, length: float,
                      rtol: float, atol: float, stop_at_ends: bool, stop_at_turnaround: bool) -> FrictionTrace:
    """trace_friction on any surface: the ODE above by scipy's solve_ivp (DOP853), dense output."""
    ds, dth = velocity_of_heading(surface, s0, th0, np.radians(heading_deg))
    y0 = np.array([s0, th0, ds[0], dth[0]])

    def fun(l: float, y: np.ndarray) -> np.ndarray:
        return friction_rhs(surface, y, _slip_at(slip, l))

    events = _events(surface, y0, slip, stop_at_ends, stop_at_turnaround)
    from scipy.integrate import solve_ivp  # noqa: PLC0415 - only where a path is traced

    res = solve_ivp(fun, (0.0, float(length)), y0, method="DOP853", rtol=rtol, atol=atol,
                    dense_output=True, events=events)
    if res.status == -1:
        raise SolverError(f"friction path tracing failed: {res.message}")
    event, radius = "length", None
    if res.status == 1:
        hit = [i for i, t in enumerate(res.t_events) if t.size]
        event = "turnaround" if stop_at_turnaround and hit[0] == len(events) - 1 else "end"
        if event == "turnaround":
            radius = float(surface.radius(res.y[0, -1:], res.y[1, -1:])[0])
    _, speed = heading_of_velocity(surface, res.y[0], res.y[1], res.y[2], res.y[3])
    return FrictionTrace(s=res.y[0], theta=res.y[1], arc=res.t, state=res.sol, length=float(res.t[-1]),
                         event=event, turnaround_radius=radius, heading_deg=float(heading_deg),
                         speed_error=float(np.max(np.abs(speed - 1.0))), nfev=int(res.nfev))

"""Friction-held passes through the bends of a line-and-arc mandrel, laid out for even bands (docs/math/07-friction.md).

Why this design. Geodesics on a torus keep rho cos(alpha) constant and bunch toward the inside of
the bend, whatever their number. A fiber at constant alpha through an arc is held by the lambda(phi)
of docs/math/07-friction.md, and all such fibers are translates of one another along the bend (the torus is a
surface of revolution about the bend axis): in the tube angle phi (from the inside) they follow one
autonomous flow dphi/dt = (1 - e cos phi) tan(alpha) / a, e = a / R_b, of period
T(alpha) = 2 pi a / (tan(alpha) sqrt(1 - e^2)). When the arc is a whole number m of periods,
tan(alpha_m) = 2 pi a m / (L_arc sqrt(1 - e^2)), the arc maps every entry angle to itself plus m
turns: evenly spaced slots leave the bend evenly spaced, every pass advances alike and the pattern
closes with the dwells as on a straight tube. Inside the arc the spacing varies by at most
(1 + e) / (1 - e) (the flow is slowest at the inside), which the circuit count covers.
On the straight pieces the passes are rotated copies (a tube is a surface of revolution) that turn
from one piece's angle to the next with a constant lambda: on a cylinder
1 / sin(alpha) = 1 / sin(alpha0) - lambda z / a (docs/math/07-friction.md), whose theta(z) is
(acosh(w0) - acosh(w(z))) / lambda with w = 1 / sin(alpha): the least max |lambda| for that turn.
Every curve here is in closed form (no ODE, no solve), so a whole elbow layer costs milliseconds.

Stations are the axial t (= s: these mandrels have no vessel profile); theta in radians.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.geometry.curvature import torus_constant_angle_slip, torus_least_pressing_angle
from winder.geometry.arcs import Arc, Path
from winder.errors import SolverError
from winder.geometry.surface import SweepSurface

MAX_ARC_ANGLE = math.radians(85.0)  # alpha_m above this is a hoop, not a helical layer
SLIP_GRID = 721  # phi samples for the largest |lambda| of a constant-angle arc


@dataclasses.dataclass(frozen=True)
class Piece:
    """One piece of the winding region in the travel order of a pass.

    length : mm along the axis. e : a / R_b (0 on a line). theta_in : the inside of the bend (rad).
    alpha0, alpha1 : winding angle (rad) where the pass enters and leaves the piece; rounds : the
    whole periods an arc holds (0 on a line). t0 : the station where the piece starts (forward order).
    """

    t0: float
    length: float
    e: float
    theta_in: float
    alpha0: float = 0.0
    alpha1: float = 0.0
    rounds: int = 0

    @property
    def is_arc(self) -> bool:
        return self.e > 0.0


def tube_radius(surface: SweepSurface) -> float | None:
    """The constant radius of a circular tube on a line-and-arc axis, or None for any other mandrel."""
    if not (isinstance(surface.curve, Path) and surface.section.is_circle and surface.is_axial_parameter):
        return None
    s = np.linspace(0.0, surface.length, 17)
    r = surface.radius(s, np.zeros_like(s))
    return float(r[0]) if np.ptp(r) <= 1e-9 * r[0] else None


def region_pieces(surface: SweepSurface, t_a: float, t_b: float) -> list[Piece]:
    """The lines and arcs of the axis clipped to [t_a, t_b], in forward order."""
    curve, a = surface.curve, tube_radius(surface)
    out = []
    for piece, z0 in zip(curve.pieces, curve.starts):
        lo, hi = max(float(z0), t_a), min(float(z0) + piece.length, t_b)
        if hi - lo <= 1e-9:
            continue
        if isinstance(piece, Arc):
            cv = curve.evaluate(np.array([0.5 * (lo + hi)]))
            inside = math.atan2(float(cv.d2[0] @ cv.e3[0]), float(cv.d2[0] @ cv.e2[0]))
            out.append(Piece(lo, hi - lo, a / piece.radius, inside))
        else:
            out.append(Piece(lo, hi - lo, 0.0, 0.0))
    return out


def arc_slip(alpha: float, e: float) -> float:
    """Largest |lambda| a constant-angle fiber needs through an arc of e = a / R_b (inf if it bridges)."""
    if alpha <= torus_least_pressing_angle(1.0, e):
        return math.inf
    phi = np.linspace(0.0, 2.0 * np.pi, SLIP_GRID)
    slip = np.abs(torus_constant_angle_slip(alpha, phi, 1.0, e))
    k = int(np.argmax(slip))
    step = phi[1] - phi[0]
    # Refine the grid's best by golden section: the design's bound must not be below the truth.
    from scipy.optimize import minimize_scalar  # noqa: PLC0415 - slow to import: only friction bends
    res = minimize_scalar(lambda x: -abs(float(torus_constant_angle_slip(alpha, x, 1.0, e))),
                          bounds=(phi[k] - step, phi[k] + step), method="bounded", options={"xatol": 1e-12})
    return max(float(slip[k]), -float(res.fun))


def line_slip(alpha0: float, alpha1: float, a: float, length: float) -> float:
    """|lambda| of the constant-lambda turn from alpha0 to alpha1 over a straight piece."""
    return a * abs(1.0 / math.sin(alpha0) - 1.0 / math.sin(alpha1)) / length


def arc_angle(rounds: int, e: float, a: float, length: float) -> float:
    """alpha_m: the angle at which an arc of this length holds `rounds` whole periods."""
    return math.atan(2.0 * math.pi * a * rounds / (length * math.sqrt(1.0 - e * e)))


def design(pieces: list[Piece], alpha: float, a: float, mu: float) -> tuple[list[Piece], float]:
    """Angles through every piece: returns (pieces with alpha0/alpha1/rounds, the largest |lambda|).

    Each arc takes the whole-period angle alpha_m closest to the layer angle alpha whose arc and
    whose turns on the neighbouring straight pieces hold within mu. Raises SolverError naming the least
    mu that would do when none does, or where two arcs meet without a straight piece between them.
    """
    chosen: dict[int, tuple[float, int]] = {}
    worst = 0.0
    for i, p in enumerate(pieces):
        if not p.is_arc:
            continue
        if i + 1 < len(pieces) and pieces[i + 1].is_arc:
            raise SolverError(f"two bends meet at t = {pieces[i + 1].t0:.4g} mm without a straight piece between "
                              f"them: friction-held even winding needs one to change the angle")
        best, least = None, math.inf
        for m in range(1, 200):
            am = arc_angle(m, p.e, a, p.length)
            if am > MAX_ARC_ANGLE:
                break
            need = arc_slip(am, p.e)
            for j in (i - 1, i + 1):
                if 0 <= j < len(pieces):
                    # A neighbouring line turns from the layer angle (at an end) or from the other bend's.
                    need = max(need, line_slip(alpha, am, a, pieces[j].length))
            least = min(least, need)
            if need <= mu and (best is None or abs(am - alpha) < abs(best[0] - alpha)):
                best = (am, m, need)
        if best is None:
            lo = torus_least_pressing_angle(1.0, p.e)
            raise SolverError(f"the bend at t = {p.t0:.4g} to {p.t0 + p.length:.4g} mm cannot be wound evenly within "
                              f"the friction {mu:g}: it needs |k_g / k_n| up to {least:.3g} (least mu), and no fiber "
                              f"below {math.degrees(lo):.1f} deg presses on its inside")
        chosen[i] = (best[0], best[1])
        worst = max(worst, best[2])
    out = []
    for i, p in enumerate(pieces):
        if p.is_arc:
            am, m = chosen[i]
            out.append(Piece(p.t0, p.length, p.e, p.theta_in, am, am, m))
            continue
        a0 = chosen[i - 1][0] if i - 1 in chosen else alpha
        a1 = chosen[i + 1][0] if i + 1 in chosen else alpha
        need = line_slip(a0, a1, a, p.length) if a0 != a1 else 0.0
        if need > mu:
            raise SolverError(f"the straight piece at t = {p.t0:.4g} mm is too short to turn the fiber from "
                              f"{math.degrees(a0):.2f} to {math.degrees(a1):.2f} deg: it needs |k_g / k_n| = "
                              f"{need:.3g}, above the friction {mu:g}")
        worst = max(worst, need)
        out.append(Piece(p.t0, p.length, 0.0, 0.0, a0, a1))
    return out, worst


# -- the curves -----------------------------------------------------------------------------------------
def _u_of_phi(phi: np.ndarray, e: float) -> np.ndarray:
    """The flow's time in periods, unwrapped: U(phi + 2 pi) = U(phi) + 1, U(0) = 0."""
    turns = np.floor((phi + np.pi) / (2.0 * np.pi))
    rest = phi - 2.0 * np.pi * turns
    return turns + np.arctan(math.sqrt((1.0 + e) / (1.0 - e)) * np.tan(0.5 * rest)) / np.pi


def _phi_of_u(u: np.ndarray, e: float) -> np.ndarray:
    turns = np.floor(u + 0.5)
    return 2.0 * np.pi * turns + 2.0 * np.arctan(math.sqrt((1.0 - e) / (1.0 + e)) * np.tan(np.pi * (u - turns)))


def _line(p: Piece, a: float, tau: np.ndarray, theta0: np.ndarray):
    """theta, dtheta/dtau, d2theta/dtau2 ((k, m) each) over a straight piece, tau from its entry."""
    w0, w1 = 1.0 / math.sin(p.alpha0), 1.0 / math.sin(p.alpha1)
    if abs(w0 - w1) < 1e-12:
        rate = math.tan(p.alpha0) / a
        d1 = np.full_like(tau, rate)
        return theta0[:, None] + rate * tau[None, :], np.broadcast_to(d1, (theta0.size, tau.size)), \
            np.zeros((theta0.size, tau.size))
    lam = a * (w0 - w1) / p.length
    w = w0 - lam * tau / a
    root = np.sqrt(w * w - 1.0)
    rise = (math.acosh(w0) - np.arccosh(w)) / lam
    d1, d2 = 1.0 / (a * root), lam * w / (a * a * root**3)
    k = theta0.size
    return theta0[:, None] + rise[None, :], np.broadcast_to(d1, (k, tau.size)), np.broadcast_to(d2, (k, tau.size))


def _arc(p: Piece, a: float, tau: np.ndarray, theta0: np.ndarray):
    """The same through an arc at constant alpha (the closed-form flow)."""
    tan = math.tan(p.alpha0)
    period = 2.0 * math.pi * a / (tan * math.sqrt(1.0 - p.e * p.e))
    u = _u_of_phi(theta0 - p.theta_in, p.e)[:, None] + tau[None, :] / period
    phi = _phi_of_u(u, p.e)
    d1 = (1.0 - p.e * np.cos(phi)) * tan / a
    return p.theta_in + phi, d1, p.e * np.sin(phi) * d1 * tan / a


def pass_curves(pieces: list[Piece], a: float, theta0: np.ndarray, points: int, forward: bool):
    """Passes entering the region at angles theta0 ((k,) float), in travel order.

    forward : t increasing (pieces in their order) or decreasing (pieces reversed); theta increases
    along the travel either way. Returns t ((m,) float, travel order), theta, dtheta/dt and
    d2theta/dt2 ((k, m) float each) and the advance (rad), the same for every pass.
    """
    order = pieces if forward else pieces[::-1]
    total = sum(p.length / math.cos(p.alpha0 if p.is_arc else min(p.alpha0, p.alpha1)) for p in order)
    ts, ths, d1s, d2s = [], [], [], []
    start = np.asarray(theta0, dtype=float)
    for p in order:
        n = max(8, int(math.ceil(points * p.length / math.cos(max(p.alpha0, p.alpha1)) / total)))
        tau = np.linspace(0.0, p.length, n + 1)
        if not forward:
            p = Piece(p.t0, p.length, p.e, p.theta_in, p.alpha1, p.alpha0, p.rounds)
        th, d1, d2 = (_arc if p.is_arc else _line)(p, a, tau, start)
        t = p.t0 + tau if forward else p.t0 + p.length - tau
        if ts and forward:
            # A joint belongs to the piece starting there (the surface is evaluated so): its
            # derivatives are this piece's, not the previous piece's.
            ts[-1], ths[-1], d1s[-1], d2s[-1] = ts[-1][:-1], ths[-1][:, :-1], d1s[-1][:, :-1], d2s[-1][:, :-1]
        keep = slice(1, None) if ts and not forward else slice(None)
        ts.append(t[keep])
        ths.append(th[:, keep])
        d1s.append(d1[:, keep])
        d2s.append(d2[:, keep])
        start = th[:, -1]
    sign = 1.0 if forward else -1.0
    theta = np.concatenate(ths, axis=1)
    return (np.concatenate(ts), theta, sign * np.concatenate(d1s, axis=1), np.concatenate(d2s, axis=1),
            float(theta[0, -1] - theta[0, 0]))


def circuits_needed(pieces: list[Piece], perimeter: float, alpha: float, band_width: float) -> int:
    """Circuits whose bands leave no gap: the layer angle at the ends, each arc's at its widest spacing."""
    need = perimeter * math.cos(alpha) / band_width
    for p in pieces:
        if p.is_arc:
            need = max(need, (1.0 + p.e) / (1.0 - p.e) * perimeter * math.cos(p.alpha0) / band_width)
    return max(1, math.ceil(need - 1e-9))
